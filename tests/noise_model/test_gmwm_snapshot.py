"""GMWM results are unchanged by speed work: a snapshot on seeded composite records (§E10).

The snapshot (tests/data/gmwm_snapshot.json) was written by this file's ``__main__`` from
the code before the speed work (issue 30). Parameters, intervals and the comparison
table's objectives must agree to the optimiser's tolerance; the chosen model and the
models tried exactly. Regenerate only when a result is meant to change:
``python tests/noise_model/test_gmwm_snapshot.py``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from noisevar.noise_model.gmwm import fit_imu_model
from noisevar.noise_model.simulate import simulate_inertial

SNAPSHOT = Path(__file__).resolve().parents[1] / "data" / "gmwm_snapshot.json"
#: Relative agreement of parameters and objectives (least_squares' tolerances are 1e-8
#: on the log-parameters; the model choice and intervals amplify them little).
RTOL = 1e-4
#: Absolute floor of the objectives' agreement (chi-square units).
ATOL_OBJECTIVE = 1e-3
#: The comparison table's criteria (compared with the absolute floor as well).
CRITERIA = ("objective", "wvic", "hq", "bic")
RATE = 200.0
N = 2**18


def _record() -> np.ndarray:
    """Three seeded axes: white + quantisation + one GM + random walk, and a two-GM one."""
    one = dict(quantization=1.29e-4, random_walk=1e-3, rate_random_walk=1e-4)
    axes = [
        simulate_inertial(N, RATE, gauss_markov=((5e-4, 5.0),), seed=11, **one),
        simulate_inertial(N, RATE, gauss_markov=((2e-3, 0.2), (5e-4, 20.0)), seed=12, **one),
        simulate_inertial(N, RATE, random_walk=1e-3, rate_random_walk=3e-4, seed=13),
    ]
    return np.column_stack(axes)


def _results() -> dict:
    x = _record()
    out = {"auto": [m.to_dict() for m in fit_imu_model(x, RATE, workers=1)]}
    fixed = fit_imu_model(x[:, 0], RATE, models=["WN+RW", "QN+WN+GM+RW"], robust=True)
    out["robust_list"] = [fixed.to_dict()]
    return out


def _compare(got: object, want: object, path: str) -> None:
    if isinstance(want, dict):
        assert isinstance(got, dict) and set(got) == set(want), path
        for k in want:
            _compare(got[k], want[k], f"{path}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), path
        for i, (g, w) in enumerate(zip(got, want, strict=True)):
            _compare(g, w, f"{path}[{i}]")
    elif isinstance(want, bool) or want is None or isinstance(want, str):
        assert got == want, path
    else:
        atol = ATOL_OBJECTIVE if path.rsplit(".", 1)[-1] in CRITERIA else 0.0
        assert got == pytest.approx(want, rel=RTOL, abs=atol), path


def test_results_match_the_snapshot() -> None:
    want = json.loads(SNAPSHOT.read_text(encoding="utf-8"))
    got = json.loads(json.dumps(_results()))
    _compare(got, want, "result")


if __name__ == "__main__":
    SNAPSHOT.write_text(json.dumps(_results(), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {SNAPSHOT}")
