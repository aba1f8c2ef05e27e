"""Suite-wide guards and settings.

Every dashboard run a test makes (``AppTest.run``) must end without an uncaught exception:
a page that raises shows users a traceback, even on a run whose state the test does not
look at (a log's first topic before the test picks another, say).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import settings

# Every property test is seeded (the same examples on every run and every machine) and has no
# per-example deadline (a loaded CI machine, or parallel workers, must not fail a slow example).
settings.register_profile("noisevar", derandomize=True, deadline=None)
settings.load_profile("noisevar")


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


@pytest.fixture
def glitched_altitude() -> np.ndarray:
    """ADS-B altitude as traffic's ``time_issue`` holds it (issue 26, real_audit9): a 25 ft
    grid, 60 lone glitches 16,000 ft down and 150 held samples; R is mostly the glitches."""
    rng = np.random.default_rng(0)
    n = 8000
    z = np.round((36000 + rng.normal(0, 7, n)) / 25) * 25
    idx = rng.choice(np.arange(100, n - 100), 60, replace=False)
    z[idx] -= 16000
    z[3000:3150] = 20800
    return z
