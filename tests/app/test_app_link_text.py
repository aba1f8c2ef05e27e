"""Link values are shown as text, never as Markdown (issue 29, item 4)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

from dashboard.text import plain  # noqa: E402

#: A Markdown link or image whose brackets are not escaped: ``[text](url)``, ``![alt](url)``.
UNESCAPED_LINK = re.compile(r"(?<!\\)\[[^\]]*(?<!\\)\]\(")


def _bodies(at: AppTest) -> list[str]:
    boxes = [*at.info, *at.warning, *at.error, *at.success, *at.caption, *at.markdown]
    return [b.value for b in boxes]


@pytest.mark.parametrize(
    ("upload", "escaped"),
    [
        (
            "[Re-upload here](https://example.invalid/phish)",
            r"\[Re-upload here\]\(https\://example.invalid/phish\)",
        ),
        ("![x](http://127.0.0.1:9/p.png)", r"\!\[x\]\(http\://127.0.0.1\:9/p.png\)"),
    ],
)
def test_an_upload_link_value_renders_as_its_text(upload, escaped):
    at = AppTest.from_file(APP, default_timeout=120)
    at.query_params["upload"] = upload
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    info = [i.value for i in at.info if "uploaded file" in i.value]
    assert len(info) == 1, _bodies(at)
    assert escaped in info[0]
    for body in _bodies(at):
        assert not UNESCAPED_LINK.search(body), body
        assert "https://" not in body and "http://" not in body, body


def test_a_bad_recipe_is_echoed_as_text():
    at = AppTest.from_file(APP, default_timeout=120)
    at.query_params["sig"] = "gen:[a](https://example.invalid/x);n=6000"
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    assert at.warning, _bodies(at)
    for body in _bodies(at):
        assert not UNESCAPED_LINK.search(body), body
        assert "https://" not in body, body


@pytest.mark.parametrize(
    ("value", "shown"),
    [
        ("[a](https://x.invalid)", r"\[a\]\(https\://x.invalid\)"),
        ("![i](//h/p.png)", r"\!\[i\]\(//h/p.png\)"),
        ("<img src=x>", r"\<img src=x\>"),
        ("*b* _i_ `c` ~s~ $x$", r"\*b\* \_i\_ \`c\` \~s\~ \$x\$"),
        ("www.example.invalid a@b.invalid", r"www\.example.invalid a\@b.invalid"),
        (":red[x] :material/home:", r"\:red\[x\] \:material/home:"),
        ("# head", r"\# head"),
        ("- item", r"\- item"),
        ("1. one", r"1\. one"),
        ("&lt;", r"\&lt;"),
        ("a\nb", r"a\\x0ab"),
        # ordinary messages read the same
        ("gamma_amp: 1.5e-3 (choose 0.1-0.9)", r"gamma_amp: 1.5e-3 \(choose 0.1-0.9\)"),
    ],
)
def test_plain_escapes_every_markup(value, shown):
    assert plain(value) == shown
