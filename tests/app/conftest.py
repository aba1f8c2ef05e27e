"""Shared AppTest helpers of the dashboard tests."""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from dashboard.widgets import HOW_IT_WORKS_KEY  # noqa: E402


def _how_it_works_opens(at: AppTest) -> bool:
    """The page's "How it works" expander is there, sends nothing while closed, and
    shows its equations once opened (the page is then rerun open)."""
    assert any("How it works" in e.label for e in at.expander)
    if at.session_state[HOW_IT_WORKS_KEY] if HOW_IT_WORKS_KEY in at.session_state else False:
        return bool(at.get("latex"))
    assert not at.get("latex"), "a closed How it works expander sends its equations"
    at.session_state[HOW_IT_WORKS_KEY] = True
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    return bool(at.get("latex"))


@pytest.fixture
def how_it_works_opens() -> Callable[[AppTest], bool]:
    """:func:`_how_it_works_opens`, for the page tests."""
    return _how_it_works_opens
