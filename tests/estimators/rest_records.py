"""Seeded records with one rest inside motion (tests/estimators/test_still_inside_phase.py,
benchmarks/still_phase.py)."""

from __future__ import annotations

import numpy as np


def rest_in_motion(seed: int, n: int, at: int, length: int) -> np.ndarray:
    """White noise (σ = 0.1) under motion (a fast sine of amplitude 0.5-2 and noise of
    σ = 0.3) everywhere but one rest of ``length`` samples from ``at``."""
    rng = np.random.default_rng(seed)
    z = 0.1 * rng.normal(size=n)
    t = np.arange(n)
    moving = np.ones(n, dtype=bool)
    moving[at : at + length] = False
    wave = np.sin(2 * np.pi * t / rng.uniform(8, 20)) * rng.uniform(0.5, 2)
    return z + moving * (wave + 0.3 * rng.normal(size=n))
