"""The dashboard's structure: one page registry that matches ``pages/``, thin page scripts."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from dashboard.pages import HOME, PAGES, page_info  # noqa: E402

PAGE_FILES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "pages").glob("*.py"))


def test_registry_and_pages_folder_agree():
    assert sorted(p.path for p in PAGES) == PAGE_FILES
    assert len({p.title for p in (HOME, *PAGES)}) == len(PAGES) + 1
    assert all(p.icon.startswith(":material/") and p.blurb for p in PAGES)


@pytest.mark.parametrize("path", ["app.py", *PAGE_FILES])
def test_every_page_takes_its_title_from_the_registry(path):
    tree = ast.parse((ROOT / path).read_text(encoding="utf-8"))
    calls = [
        n
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "setup_page"
    ]
    assert len(calls) == 1, f"{path} calls setup_page(__file__) once"
    (arg,) = calls[0].args
    assert isinstance(arg, ast.Name) and arg.id == "__file__"
    assert page_info(path).path == path


def test_unknown_page_is_refused():
    with pytest.raises(KeyError, match="add a line"):
        page_info("pages/99_Nothing.py")
