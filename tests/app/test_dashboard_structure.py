"""The dashboard's structure: ``st.navigation`` over one page registry, thin page scripts."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from dashboard.pages import HOME, PAGES  # noqa: E402

PAGE_FILES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "app_pages").glob("*.py"))


def test_every_page_script_is_registered_once():
    assert sorted(p.path for p in PAGES) == PAGE_FILES
    assert PAGES[0] is HOME
    assert len({p.title for p in PAGES}) == len(PAGES)
    assert all(p.icon.startswith(":material/") and p.blurb for p in PAGES)


def test_no_classic_pages_folder():
    """A ``pages/`` folder beside app.py makes Streamlit run its scripts without the frame."""
    assert not (ROOT / "pages").exists()


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.title)
def test_title_and_url_come_from_the_file_name(page):
    """Streamlit's URL path is the file name; AppTest finds a page by it before a run."""
    assert page.title.replace(" ", "_") == page.url_path == Path(page.path).stem


def test_app_py_is_the_navigation_only():
    tree = ast.parse((ROOT / "app.py").read_text(encoding="utf-8"))
    called = {ast.unparse(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
    assert {"st.navigation", "frame", "page.run"} <= called
    assert "st.title" not in called


@pytest.mark.parametrize("path", PAGE_FILES)
def test_page_scripts_leave_the_frame_to_app_py(path):
    text = (ROOT / path).read_text(encoding="utf-8")
    for frame_call in ("set_page_config", "st.navigation", "clean_query_params"):
        assert frame_call not in text, f"{path}: {frame_call} belongs to the frame (app.py)"


def test_the_still_running_icon_names_streamlits_own_element():
    """dashboard.widgets hides Streamlit's cycling running icon by its test id (issue 29):
    the installed frontend must still have that element."""
    import streamlit as st

    from dashboard.widgets import RUNNING_ICON

    js = Path(st.__file__).parent / "static" / "static" / "js"
    assert any(RUNNING_ICON in f.read_text(errors="ignore") for f in js.glob("index.*.js"))


def test_number_inputs_round_what_they_show():
    """Streamlit formats a number input with sprintf-js, whose ``%g`` without a precision
    prints every digit: a PX4 log's rate read "204.58265139116202" on the Noise model page
    (a browser screenshot). Every ``format=`` of a number input gives a precision."""
    bare = []
    for path in [*(ROOT / "dashboard").rglob("*.py"), *(ROOT / "app_pages").glob("*.py")]:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.keyword) and node.arg == "format":
                if isinstance(node.value, ast.Constant) and node.value.value in ("%g", "%f", "%e"):
                    bare.append(f"{path.name}:{node.value.lineno}")
    assert not bare, bare
