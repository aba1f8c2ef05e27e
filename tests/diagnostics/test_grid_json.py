"""The second differences' grid (``diagnostics.grid``) reaches the JSON export."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

import noisevar


def _record(tmp_path):
    rng = np.random.default_rng(0)
    n = 4000
    x = np.round(rng.normal(0, 0.02, n) / 0.01) * 0.01 + 1.234567e-4 * np.arange(n)
    path = tmp_path / "on_grid_with_trend.csv"
    np.savetxt(path, x, header="x", comments="")
    return x, path


def test_the_grid_under_a_trend_is_exported(tmp_path) -> None:
    x, path = _record(tmp_path)
    d = noisevar.estimate(x).diagnostics
    assert d.lsb is None and d.grid is not None  # off the grid, its differences on it
    assert abs(d.to_dict()["grid"] - 0.01) < 1e-9
    out = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(path), "--format", "json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    got = json.loads(out.stdout)
    assert abs(got["diagnostics"]["grid"] - 0.01) < 1e-9, got["diagnostics"].keys()
