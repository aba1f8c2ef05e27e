"""fit_kalman on a record whose r is a few glitches: its Gaussian assumption is said to be
broken and its interval is widened, in Python, the CLI and the Noise model page (issue 26).

traffic's ADS-B altitude (benchmarks/real_audit9.py) fitted r = 444,592 ft² with a 95 %
interval of 430,150-459,518 (±3 %): R there is 13,153x its core variance, held by 2.2 % of
the samples, and r is as uncertain as their count.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from streamlit.testing.v1 import AppTest

from noisevar.cli import main
from noisevar.noise_model import fit_kalman

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def _track(seed: int, n: int = 3000) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(np.cumsum(rng.normal(0, 0.3, n))) * 0.1 + rng.normal(0, 1.0, n)


def test_glitches_widen_the_interval_and_say_the_assumption_is_broken(glitched_altitude) -> None:
    t = fit_kalman(glitched_altitude)
    lo, hi = t.r_interval
    assert not t.innovations_gaussian and t.innovations_kurtosis > 10
    assert any("heavy-tailed" in n and "Gaussian assumption is broken" in n for n in t.notes)
    assert hi / lo > 1.3, t.r_interval  # ±3 % before: as if the glitches were Gaussian
    assert t.to_dict()["innovations_kurtosis"] == t.innovations_kurtosis
    g = fit_kalman(_track(4))  # Gaussian noise: nothing said, nothing widened
    assert g.innovations_gaussian and not any("heavy-tailed" in n for n in g.notes)


def test_the_widened_interval_covers_r_with_glitches() -> None:
    """1 % of samples 10σ off at random: r's target is the noise's variance, glitches in
    (2σ²). Covered in 33 of 40 records (14 of 40 with the Gaussian interval); short of 95 %:
    the kurtosis is read on the same record, low where few glitches fell."""
    hits = 0
    for seed in range(40):
        z = _track(seed)
        rng = np.random.default_rng(100 + seed)
        idx = np.flatnonzero(rng.random(z.size) < 0.01)
        z[idx] += rng.choice([-10.0, 10.0], idx.size)
        lo, hi = fit_kalman(z).r_interval
        hits += lo <= 2.0 <= hi
    assert hits >= 30, hits


def test_cli_fit_says_the_tails(tmp_path, capsys, glitched_altitude) -> None:
    path = tmp_path / "altitude.csv"
    np.savetxt(path, glitched_altitude, header="altitude", comments="")
    assert main(["fit", str(path), "--column", "altitude", "--rate", "1"]) == 0
    out = capsys.readouterr().out
    assert "tails     NOT Gaussian (kurtosis" in out, out
    assert "heavy-tailed" in out, out


def _page() -> None:
    import numpy as np

    from dashboard.sections.noise_model_fit import render_fit

    rng = np.random.default_rng(0)  # glitched_altitude: the page's script is this body
    z = np.round((36000 + rng.normal(0, 7, 8000)) / 25) * 25
    z[rng.choice(np.arange(100, 7900), 60, replace=False)] -= 16000
    z[3000:3150] = 20800
    render_fit(z, 1.0)


def test_the_page_does_not_call_the_fit_good(monkeypatch) -> None:
    from dashboard import workers

    monkeypatch.setattr(workers, "WORKERS", 0)  # a pool would re-run the page's script
    at = AppTest.from_function(_page, default_timeout=180).run()
    assert not at.exception, [e.value for e in at.exception]
    assert not at.success, [s.value for s in at.success]
    assert any("NOT Gaussian" in w.value for w in at.warning), [w.value for w in at.warning]
    assert any("heavy-tailed" in c.value for c in at.caption)
