"""Write ``reference.json``: numbers that a refactoring must leave unchanged.

Run from the repository root: ``python tests/results/make_reference.py``. Every
number comes from seeded computations through the public API and the CLI; the
test ``tests/test_reference_values.py`` recomputes them and compares.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import noisevar

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]

#: (experiment, extra CLI arguments): small, seeded runs of every experiment.
EXPERIMENTS = (
    ("monte-carlo", ["--runs", "20", "--seed", "3"]),
    ("gps-circle", ["--runs", "3", "--seed", "2"]),
    ("noise-step", ["--runs", "3", "--seed", "2"]),
    ("noise-ramp", ["--runs", "3", "--seed", "2"]),
    ("fusion", ["--runs", "3", "--seed", "2"]),
    ("outliers", ["--runs", "3", "--seed", "2"]),
    ("carrier", ["--runs", "5", "--seed", "2"]),
    ("latency", ["--runs", "5", "--seed", "2"]),
)
#: Keys whose values are timings or otherwise not reproducible.
VOLATILE = ("elapsed", "seconds", "time_s", "runtime", "wall", "jobs")


def _estimates() -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for signal in ("fast-slow", "steps-ramps", "noise-step", "gps-circle"):
        z = noisevar.generate(signal, n=3000, seed=7).measured
        for method in noisevar.methods():
            if method == "somd-redundant":
                ref = noisevar.generate(signal, n=3000, seed=8).measured
                est = noisevar.estimate(z, method, reference=ref)
            else:
                try:
                    est = noisevar.estimate(z, method)
                except noisevar.NoisevarError as exc:
                    out[f"{signal}/{method}"] = {"error": str(exc)}
                    continue
            out[f"{signal}/{method}"] = {
                "variance": est.variance,
                "ci95_lo": est.ci95[0],
                "ci95_hi": est.ci95[1],
                "n_used": est.n_used,
            }
    return out


def _experiment(name: str, args: list[str]) -> object:
    cmd = [sys.executable, "-m", "noisevar", "experiment", name, *args, "--format", "json"]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=True)
    return _strip(json.loads(done.stdout))


def _strip(obj: object) -> object:
    if isinstance(obj, dict):
        return {k: _strip(v) for k, v in obj.items() if not any(s in k for s in VOLATILE)}
    if isinstance(obj, list):
        return [_strip(v) for v in obj]
    return obj


def compute() -> dict[str, object]:
    """Every reference value, freshly computed."""
    ref: dict[str, object] = {"estimates": _estimates()}
    sensors = np.column_stack(
        [noisevar.generate("fast-slow", n=3000, seed=s).measured for s in (1, 2, 3)]
    )
    r = noisevar.estimate_redundant(sensors)
    ref["redundant"] = [float(v) for v in np.ravel(r.variances)]
    for name, args in EXPERIMENTS:
        ref[f"experiment/{name}"] = _experiment(name, args)
    return ref


if __name__ == "__main__":
    (HERE / "reference.json").write_text(json.dumps(compute(), indent=1, sort_keys=True) + "\n")
