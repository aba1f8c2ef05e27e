"""Suite-wide guards.

Every dashboard run a test makes (``AppTest.run``) must end without an uncaught exception:
a page that raises shows users a traceback, even on a run whose state the test does not
look at (a log's first topic before the test picks another, say).
"""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _no_uncaught_dashboard_exception(monkeypatch):
    try:
        from streamlit.testing.v1 import AppTest
    except ImportError:  # pragma: no cover - the app extra is not installed
        yield
        return
    run = AppTest.run

    def checked(self, *args, **kwargs):
        out = run(self, *args, **kwargs)
        raised = [e.value for e in self.exception]
        assert not raised, f"the dashboard raised: {raised}"
        return out

    monkeypatch.setattr(AppTest, "run", checked)
    yield
