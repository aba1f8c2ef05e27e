"""The §E3 rounding factor's own spread is in R's interval (issue 26, real_audit17).

pyphysio's BVP on a 0.001 grid: the factor read through ``auto``'s longest span (81) was
x7.85 on one stretch and x6.15 on the next (signal leaking through the long span's
residual, which rounding error does not do: through spans 11-41 it reads 1.03-1.05), and
R's interval, the estimate's times the one factor, left that spread out: the second
stretch's R read 0.513x the first's, outside its ci95. Seeded: a fast pulse wave rounded to
its grid with noise a tenth of a step.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


def _pulse_wave(seed: int) -> tuple[np.ndarray, float]:
    """A pulse wave of ~3000 steps, a beat per 820 samples (fast upstroke, slow decay), on a
    wandering baseline, noise 0.1 step, rounded; and the true error variance."""
    rng = np.random.default_rng(seed)
    k = np.arange(40000)
    ph = k % 820.0
    c = 3000.0 * (1.0 - np.exp(-ph / 30.0)) * np.exp(-ph / 200.0)
    c += 200.0 * np.sin(2.0 * np.pi * k / 9000.0)
    z = np.round(c + 0.1 * rng.normal(size=k.size))
    return z, float(np.mean((z - c) ** 2))


@pytest.mark.parametrize("seed", [0, 1])
def test_interval_carries_the_factor_read_through_the_shortest_span(seed: int) -> None:
    """Before: R 0.183 steps² (ci95 0.180-0.186) against a true error variance 0.094."""
    z, truth = _pulse_wave(seed)
    est = noisevar.estimate(z)
    assert any("multiplied by" in n and "shortest span" in n for n in est.notes), est.notes
    assert est.ci95[0] <= truth <= est.ci95[1], (truth, est.variance, est.ci95)


def test_rounding_alone_keeps_a_tight_interval() -> None:
    """A slow sine rounded with noise 0.2 step: both spans read one factor, the interval
    stays as tight as before (within 1 %)."""
    rng = np.random.default_rng(1)
    k = np.arange(20000)
    c = 20.0 * np.sin(2 * np.pi * k / 1500) + 3.0 * np.sin(2 * np.pi * k / 5550 + 1)
    z = np.round(c + 0.2 * rng.normal(size=k.size))
    est = noisevar.estimate(z)
    lo, hi = est.ci95
    assert hi / lo < 1.12, est.ci95
    assert lo <= float(np.mean((z - c) ** 2)) <= hi
