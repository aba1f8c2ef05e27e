"""Reference values (``tests/results/reference.json``) that a refactoring must leave unchanged.

The file was written by ``tests/results/make_reference.py`` before the redesign; this test
recomputes every number the same way and compares each with the tolerance of its kind
(:data:`TOLERANCES`): a closed form to rounding, an optimiser's output to its convergence
tolerance, so that a new release of the optimiser's library does not fail a correct value.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "results"))

import make_reference  # noqa: E402

#: Relative tolerance by kind of value: (a part of the value's path, tolerance, why). The
#: first kind whose part is in the path wins; everything else is a closed form or a seeded
#: computation with no stopping rule, compared to rounding.
TOLERANCES: tuple[tuple[str, float, str], ...] = (
    (
        "mle-",
        1e-3,
        "statsmodels' state-space MLE (L-BFGS, factr 1e7): the likelihood converges to about "
        "2e-9, its parameters to about its square root times the curvature's condition; "
        "statsmodels 0.14 and 0.15 differ by 1.6e-4",
    ),
    (
        "experiment/outliers/",
        1e-6,
        "a seeded 6000-step EKF with Huber's IRLS weights: the rounding of one CPU's BLAS and "
        "SIMD sums (an AMD EPYC's against the machine that wrote the file) grows along the "
        "run and through the weights' thresholds to 2e-9 of the RMSE",
    ),
)
#: Values that are themselves a rounding residue (a filter against its centralised twin,
#: equal in exact arithmetic): compared as a magnitude below this, not digit by digit.
ROUNDING_RESIDUE = ("max_abs_diff_vs_centralized", 1e-9)
CLOSED_FORM = 1e-9


def tolerance(path: str) -> float:
    """The relative tolerance for the value at ``path`` (:data:`TOLERANCES`)."""
    return next((tol for part, tol, _ in TOLERANCES if part in path), CLOSED_FORM)


def _compare(expected: object, actual: object, path: str, bad: list[str]) -> None:
    if isinstance(expected, dict):
        if not isinstance(actual, dict) or set(expected) != set(actual):
            bad.append(f"{path}: keys differ")
            return
        for key in expected:
            _compare(expected[key], actual[key], f"{path}/{key}", bad)
    elif isinstance(expected, list):
        if not isinstance(actual, list) or len(expected) != len(actual):
            bad.append(f"{path}: lengths differ")
            return
        for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
            _compare(e, a, f"{path}[{i}]", bad)
    elif isinstance(expected, float) and path.endswith(ROUNDING_RESIDUE[0]):
        if not (isinstance(actual, int | float) and abs(actual) < ROUNDING_RESIDUE[1]):
            bad.append(f"{path}: {actual!r} is not a rounding residue (< {ROUNDING_RESIDUE[1]})")
    elif isinstance(expected, float) and isinstance(actual, int | float):
        if not math.isclose(expected, actual, rel_tol=tolerance(path), abs_tol=1e-12):
            bad.append(f"{path}: {actual!r} != {expected!r}")
    elif isinstance(expected, str) and " " in expected and len(expected) > 30:
        return  # prose (a note or a reason) may be reworded; names and numbers may not
    elif expected != actual:
        bad.append(f"{path}: {actual!r} != {expected!r}")


def test_every_reference_value_is_reproduced() -> None:
    expected = json.loads((HERE / "results" / "reference.json").read_text())
    bad: list[str] = []
    _compare(expected, make_reference.compute(), "", bad)
    assert not bad, "\n".join(bad[:40])


def test_tolerances_by_kind() -> None:
    assert tolerance("estimates/fast-slow/mle-trend/variance") == 1e-3
    assert tolerance("experiment/monte-carlo/methods/somd/mean") == CLOSED_FORM
    bad: list[str] = []
    _compare({"mle-level": 1.0}, {"mle-level": 1.0005}, "", bad)
    _compare({"somd": 1.0}, {"somd": 1.0 + 1e-8}, "", bad)
    assert bad == ["/somd: 1.00000001 != 1.0"]
    assert tolerance("experiment/outliers/metrics/rmse_position_huber") == 1e-6
    bad = []
    _compare(
        {"max_abs_diff_vs_centralized": 2e-11}, {"max_abs_diff_vs_centralized": 3e-11}, "", bad
    )
    _compare({"max_abs_diff_vs_centralized": 2e-11}, {"max_abs_diff_vs_centralized": 1e-6}, "", bad)
    assert len(bad) == 1 and "rounding residue" in bad[0]
