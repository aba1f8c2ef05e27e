"""Monte Carlo rows: no statistics from a few survivors, and the parameters in use (issue 28)."""

from __future__ import annotations

import json

import numpy as np

from noisevar.estimators.compare import run_monte_carlo
from noisevar.estimators.mc_summary import enough_runs, summary_row
from noisevar.figures.compare import monte_carlo_figure


def test_summary_row_rule() -> None:
    errors = np.full(100, np.nan)
    errors[:3] = [0.01, -0.02, 0.03]
    row = summary_row("somd", errors, 97, 100, 0.03, {"gamma_amp": 0.05})
    assert row["status"].startswith("failed 97/100") and np.isnan(row["rmse"])
    assert row["params"] == "gamma_amp=0.05"
    errors[:] = 0.01
    errors[:5] = np.nan
    row = summary_row("somd", errors, 5, 100, 0.03)
    assert row["status"] == "failed 5/100 (statistics of the 95 others)"
    assert row["rmse"] > 0 and row["params"] == "defaults"
    assert not enough_runs(1, 1) and enough_runs(50, 100) and not enough_runs(49, 100)


def test_failed_somd_has_no_histogram_and_its_panel_says_failed() -> None:
    mc = run_monte_carlo(
        "fast-slow",
        runs=10,
        methods=["somd", "diff2"],
        params={"somd": {"gamma_amp": 0.05}},
        n=2000,
        seed=0,
    )
    assert mc.params["somd"] == {"gamma_amp": 0.05}
    rows = {r["method"]: r for r in mc.summary()}
    assert rows["somd"]["failures"] > 5 and np.isnan(rows["somd"]["bias"])
    fig = monte_carlo_figure(mc)
    titles = [a.text for a in fig.layout.annotations]
    assert any(t.startswith("somd: failed ") for t in titles)
    somd_bars = next(t for t in fig.data if t.name == "somd")
    assert sum(somd_bars.y) == 0
    json.dumps(rows["diff2"])  # JSON-ready
