"""AppTest: the Noise model page on records at the float range's edges (brief hostile29b):
a number or one st.error, never an uncaught exception (the Allan figure's model curve
overflowed at 1e300: OverflowError)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

from dashboard.state import SIGNAL_KEY, make_signal  # noqa: E402
from noisevar.io import load_table  # noqa: E402
from noisevar.synth import still_start  # noqa: E402

RATE = 100.0


@pytest.mark.parametrize("x", [1e300, 1e154])
def test_noise_model_page_at_extreme_scales(x: float) -> None:
    z = still_start(2000, 4000, rng=3) * x
    csv = pd.DataFrame({"t": np.arange(z.size) / RATE, "gyro": z}).to_csv(
        index=False, float_format="%.17g"
    )
    table = load_table(csv.encode(), "rec.csv")
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 1.0 / RATE, "upload", None)
    at.switch_page("app_pages/Noise_model.py").run()
    assert not at.exception, [e.value for e in at.exception]
    if any(box.key == "nm_regimes" for box in at.checkbox):  # offered when R is there
        at.checkbox(key="nm_regimes").check().run()
        assert not at.exception, [e.value for e in at.exception]
    shown = [m.value for m in at.metric] + [e.value for e in at.error]
    assert not any(w in str(v) for v in shown for w in ("nan", "inf", "None"))
