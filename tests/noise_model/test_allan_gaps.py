"""The Allan deviation of rate data that dropped samples (noise_model/allan_gaps.py, §E4).

Seeded white + random-walk rate noise at 400 Hz, 30-45 % of samples dropped at random:
placed on their base period, N and K fall within their intervals of the truth; taken as
uniform at the median rate, K is off by the taus' compression (1 / share kept).
"""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model import allan, inertial_noise
from noisevar.noise_model.allan_gaps import StampGrid, gap_grid, gapped_adev, stamp_grid

RATE = 400.0
N_TRUE, K_TRUE = 0.01, 0.01


def _white_plus_walk(seed: int, seconds: float = 300.0) -> tuple[np.ndarray, np.ndarray, float]:
    rng = np.random.default_rng(seed)
    n = int(RATE * seconds)
    y = N_TRUE * np.sqrt(RATE) * rng.standard_normal(n)
    y += np.cumsum(K_TRUE / np.sqrt(RATE) * rng.standard_normal(n))
    t = np.arange(n) / RATE + rng.normal(scale=0.02 / RATE, size=n)  # 2 % jitter
    dropped = rng.uniform(0.30, 0.45)
    keep = rng.random(n) > dropped
    return y[keep], t[keep], dropped


def test_stamp_grid_places_dropped_samples_and_refuses_other_steps() -> None:
    t = np.array([0, 1, 3, 4, 7, 8, 9], dtype=float) * 0.0025
    grid = stamp_grid(t + 1e-5 * np.sin(np.arange(7)))
    assert grid is not None and grid.size == 10 and grid.dropped == 3
    np.testing.assert_array_equal(grid.slot, [0, 1, 3, 4, 7, 8, 9])
    assert grid.period == pytest.approx(0.0025, rel=1e-3)
    assert stamp_grid(np.arange(50) * 0.01).dropped == 0
    # steps of 1.5 periods are not whole multiples; a clock that drifts strays from its slot
    assert stamp_grid(np.cumsum(np.tile([1.0, 1.5], 20))) is None
    assert stamp_grid(np.cumsum(1 + 0.2 * np.arange(40) / 40)) is None
    # a record that is mostly one pause is not placed on a grid
    assert stamp_grid(np.r_[np.arange(10), 1000 + np.arange(10)]) is None
    assert gap_grid(t, "phase", "oadev") is None and gap_grid(t, "rate", "mdev") is None
    assert gap_grid(t, "rate", "oadev", "still") is None and gap_grid(None, "rate", "oadev") is None


def test_uniform_times_are_bit_identical_and_phase_data_stay_uniform() -> None:
    rng = np.random.default_rng(3)
    y, t = rng.standard_normal(5000), np.arange(5000) / RATE
    plain, timed = allan(y, RATE, "rate"), allan(y, RATE, "rate", t=t)
    for a, b in ((plain.deviation, timed.deviation), (plain.edf, timed.edf)):
        np.testing.assert_array_equal(a, b)
    assert timed.notes == ()
    keep = rng.random(5000) > 0.3
    phase = allan(y[keep], RATE, "phase", t=t[keep])
    np.testing.assert_array_equal(phase.deviation, allan(y[keep], RATE, "phase").deviation)
    fit, fit_t = inertial_noise(y, RATE), inertial_noise(y, RATE, t=t)
    assert [s.value for s in fit.terms] == [s.value for s in fit_t.terms]
    assert [s.interval for s in fit.terms] == [s.interval for s in fit_t.terms]


def test_white_noise_with_drops_keeps_its_deviation_within_its_intervals() -> None:
    rng = np.random.default_rng(4)
    n = 200_000
    y, keep = rng.standard_normal(n), rng.random(n) > 0.4
    t = np.flatnonzero(keep) / RATE
    g = gapped_adev(y[keep], stamp_grid(t), 2 ** np.arange(7))
    # sigma / sqrt(m) within 3 % where the edf is in the thousands (2 standard errors)
    np.testing.assert_allclose(g.deviation * np.sqrt(g.m), 1.0, rtol=0.03)
    assert np.all(g.n <= g.full) and g.n[0] < 0.4 * g.full[0]  # pairs both present only
    res = allan(y[keep], RATE, "rate", t=t, ci=0.95)
    truth = 1 / np.sqrt(res.taus * RATE)
    assert np.mean((res.interval[0] <= truth) & (truth <= res.interval[1])) >= 0.85


def test_n_and_k_within_their_intervals_where_the_median_rate_misses_k() -> None:
    placed, uniform, compressed = [], [], []
    for seed in range(8):
        y, t, dropped = _white_plus_walk(seed)
        fit = inertial_noise(y, RATE, t=t, ci=0.95)
        (n_lo, n_hi), (k_lo, k_hi) = fit.term("N").interval, fit.term("K").interval
        assert n_lo <= N_TRUE <= n_hi and k_lo <= K_TRUE <= k_hi, seed
        assert "samples dropped" in fit.notes[0] and fit.rate == pytest.approx(RATE, rel=1e-4)
        placed.append(fit.term("K").value / K_TRUE)
        # taken as uniform at the median rate: taus compressed by the share kept, so
        # K^2 tau / 3 is read at tau (1 - dropped) and K is 1 / sqrt(1 - dropped) too high
        uniform.append(inertial_noise(y, RATE, ci=0.95).term("K").value / K_TRUE)
        compressed.append(1 / np.sqrt(1 - dropped))
    assert np.mean(placed) == pytest.approx(1.0, abs=0.08)
    assert min(uniform) > 1.0 and np.mean(uniform) == pytest.approx(np.mean(compressed), rel=0.1)


def test_scale_and_bad_input() -> None:
    y, t, _ = _white_plus_walk(5, seconds=20.0)
    a, b = allan(y, RATE, "rate", t=t), allan(y * 2.0**60, RATE, "rate", t=t)
    np.testing.assert_allclose(b.deviation, a.deviation * 2.0**60, rtol=1e-12)
    with pytest.raises(NoisevarError, match="one time per sample"):
        allan(y, RATE, "rate", t=t[:-1])
    with pytest.raises(NoisevarError, match="adjacent"):
        gapped_adev([1.0, 2.0, 0.5], StampGrid(1.0, np.array([0, 2, 4])), [1])
