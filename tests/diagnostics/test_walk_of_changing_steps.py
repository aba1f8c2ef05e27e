"""A random walk whose steps change in size, with no measurement noise (a logger's 10-minute
temperature: larger steps by day than by night; brightwind's met mast T2m, real_audit12).

Its increments are white but of a level that changes: their whiteness test's null is widened
as the residual's is, so the walk is not read as measurable noise; and where its still
stretches are a walk of smaller steps (their level's interval reaches 0) their level is
never quoted as the R to use.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


def _walk(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    steps = np.r_[0.2 * rng.normal(size=n // 3), 0.05 * rng.normal(size=n - n // 3)]
    return np.round(10.0 + np.cumsum(steps), 3)


@pytest.mark.parametrize("seed", [0, 2, 4])
def test_a_walk_of_changing_steps_is_a_walk(seed: int) -> None:
    """Before: "the noise level changes along the record ... its quiet stretches give
    6.211e-4 ... its white part" on a record with no noise but its rounding (8.3e-8)."""
    est = noisevar.estimate(_walk(seed, 1000))
    assert not est.diagnostics.identifiable
    assert est.diagnostics.verdict.startswith("the record behaves like a random walk")


@pytest.mark.parametrize(("seed", "n"), [(0, 1000), (3, 400), (5, 188)])
def test_its_still_stretches_are_not_the_r_to_use(seed: int, n: int) -> None:
    """Before: "its still stretches (46% of it) give 0.002741: the noise where it stood still,
    the R to use", with that level's interval from 0."""
    est = noisevar.estimate(_walk(seed, n))
    v = est.diagnostics.verdict
    assert est.still is not None and est.still.ci95[0] == 0.0
    assert "R to use" not in v
    assert "only bounds the noise from above" in v
