"""The shortcuts that make ``auto`` cheaper on records with motion give the same numbers (issue 26).

Each is compared with the long way it replaces, to the last bit: the reversed grid's
profile-only pass with the full diagnostics, the still ranges' estimate without
diagnostic sums with the one that sums them, PELT's cost table with a cost per call,
the window medians computed once (each run's middle candidate first) with one per
candidate, the local levels read at some samples with the levels of the whole window,
glitches bridged over their neighbours alone with the line over every sample, the
bracketing levels looked up per half block with the two block centres per sample.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from noisevar import synth
from noisevar.diagnostics import Segmentation, diagnose, profile_of
from noisevar.diagnostics.regimes import _Cost, _pelt
from noisevar.estimators.auto import ChunkedAuto
from noisevar.numeric import steps


def _motion(n: int, seed: int) -> np.ndarray:
    """White noise with bursts of a fast sinusoid (:func:`noisevar.synth.sine_bursts`)."""
    return synth.sine_bursts(n, rng=seed)


def _same(a, b) -> None:
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


@pytest.mark.parametrize("seed", [1, 2])
def test_the_profile_only_pass_is_the_diagnostics_profile(seed):
    z = _motion(12_000, seed)
    seg = Segmentation(((0, 5_000), (5_000, 12_000)), ())
    exclude = np.zeros(z.size, dtype=bool)
    exclude[7_000:7_040] = True  # samples around a jump, left out
    light = profile_of(z, seg, exclude)
    assert len(light.regimes) > 1 and not light.quiet.all()
    _same(light, diagnose(z, seg, exclude).level_profile)


def test_the_still_ranges_estimate_needs_no_diagnostic_sums():
    z = _motion(40_000, 7)

    def read(a: int, b: int) -> np.ndarray:
        return z[max(a, 0) : b].copy()

    full = ChunkedAuto(read, z.size, probe=z.__getitem__, chunk=1 << 13).estimate({})
    light = ChunkedAuto(read, z.size, chunk=1 << 13, diagnostics=False).estimate({})
    assert full.to_dict() == light.to_dict()
    assert (full.variance, full.ci95, full.dof) == (light.variance, light.ci95, light.dof)


def test_pelt_from_the_cost_table_finds_the_breaks_of_a_cost_per_call():
    import ruptures

    rng = np.random.default_rng(3)
    split = 0
    for _ in range(20):
        m = int(rng.integers(5, 120))
        level = rng.chisquare(40, m) / 40
        level[rng.integers(0, m) :] *= rng.choice([0.3, 4.0, 12.0])
        cost = _Cost(level, rng.uniform(20, 500, m))

        class PerCall(ruptures.base.BaseCost):
            model = "per-call"
            min_size = 1

            def __init__(self, cost: _Cost) -> None:
                self.cost = cost

            def fit(self, signal):
                self.signal = signal
                return self

            def error(self, start, end):
                return float(self.cost(start, end))

        pen = 6.0 * np.log(m)
        direct = ruptures.Pelt(custom_cost=PerCall(cost), min_size=1, jump=1)
        breaks = _pelt(cost, m, pen)
        assert breaks == direct.fit(np.zeros((m, 1))).predict(pen=pen)[:-1]
        split += bool(breaks)
    assert split >= 10


def _jumps(n: int, seed: int) -> np.ndarray:
    """White noise (σ = 1) with three level jumps of 4-8 σ: few candidates."""
    rng = np.random.default_rng(seed)
    x = rng.normal(size=n)
    for at in rng.integers(0, n, 3):
        x[at:] += rng.choice([-1, 1]) * rng.uniform(4, 8)
    return x


def _steps_of(n: int, seed: int) -> np.ndarray:
    """:func:`_jumps`' three level jumps alone, twice their size (8-16 σ of white noise)."""
    return 2.0 * (_jumps(n, seed) - np.random.default_rng(seed).normal(size=n))


@pytest.mark.parametrize(
    "z", [_motion(6_000, 11), _motion(20_000, 12), _jumps(20_000, 4), _jumps(3_000, 5)]
)
def test_window_medians_once_are_the_medians_per_candidate(monkeypatch, z):
    """Runs settled by their middle candidate first: the runs every candidate's test keeps."""
    w = steps.STEP_WINDOW

    def above(x: np.ndarray) -> np.ndarray:
        return x > 0.5

    def per_candidate(z, candidates, above, scale, w):  # the medians taken per candidate
        idx = np.flatnonzero(candidates)
        at = np.clip(idx[:, None] + np.array([w, 0, -w, -2 * w]), 0, z.size - w)
        med = np.median(steps.detrended_windows(z, at, idx, w), axis=2)
        d3 = med @ np.array([1.0, -3.0, 3.0, -1.0])
        probe = np.zeros(z.size)
        probe[idx] = d3**2 * scale / (steps.STEP_CONFIRM**2 * 20.0 * steps._median_variance(w))
        confirmed = steps._above_both_sides(probe, above)[idx]
        run = np.cumsum(np.r_[True, np.diff(idx) > w])
        keep_run = np.zeros(run[-1] + 1, dtype=bool)
        keep_run[run[confirmed]] = True
        out = np.zeros_like(candidates)
        out[idx[keep_run[run]]] = True
        return out

    fast = steps.step_mask(z, above, 1.0, w)
    assert fast.any()
    monkeypatch.setattr(steps, "_confirm_steps", per_candidate)
    assert np.array_equal(fast, steps.step_mask(z, above, 1.0, w))


def test_the_sorting_network_gives_numpys_medians():
    rng = np.random.default_rng(5)
    z = np.r_[rng.normal(size=3000), np.round(rng.normal(size=3000) * 2) / 2]  # ties too
    starts = np.sort(rng.choice(z.size - 6, 2000, replace=False))
    windows = np.lib.stride_tricks.sliding_window_view(z, 6)[starts]
    assert np.array_equal(steps._window_medians(z, starts, 6), np.median(windows, axis=1))


@pytest.mark.parametrize("after", [0, 100])
def test_the_levels_read_at_some_samples_are_the_window_s_levels(after):
    from noisevar.estimators.auto._levels import Above, Grids, kept_levels

    z = _motion(20_000, 13) + _steps_of(20_000, 13)  # its bursts are no jumps: add some
    sq = np.convolve(z, [1.0, -2.0, 1.0], mode="same") ** 2 / 6.0
    g = Grids.make(z.size, 256, after)
    above = Above(*kept_levels(sq, None, g, 12.25), g)
    rng = np.random.default_rng(after)
    idx = np.sort(rng.choice(z.size, 3_000, replace=False))
    probe = np.zeros(z.size)
    probe[idx] = sq[idx] * rng.uniform(0.5, 2.0, idx.size)
    assert np.array_equal(above.at(probe[idx], idx), above(probe)[idx])

    class Dense:  # the same levels, without ``at`` (raised as ``above`` is, read densely)
        def __init__(self, a):
            self.a = a

        def __call__(self, x: np.ndarray) -> np.ndarray:
            return self.a(x)

        def raised(self, x, idx, expected):
            return Dense(self.a.raised(x, idx, expected))

    dense = Dense(above)

    found = steps.step_mask(z, above, 12.25)
    assert found.any() and np.array_equal(found, steps.step_mask(z, dense, 12.25))
    lone = steps.lone_steps(z, found, above, 12.25)
    assert np.array_equal(lone, steps.lone_steps(z, found, dense, 12.25))


def test_glitches_bridged_over_their_ends_alone_are_bridged_as_over_every_sample():
    from noisevar.estimators.auto._trim import GLITCH_MAX, _bridged

    rng = np.random.default_rng(17)
    for _ in range(200):
        n = int(rng.integers(3, 400))
        z = rng.normal(size=n)
        outliers = rng.random(n) < rng.choice([0.02, 0.2, 0.6, 0.95])
        edges = np.flatnonzero(np.diff(np.r_[0, outliers.view(np.int8), 0]))
        glitch = np.zeros(n, dtype=bool)
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            glitch[a:b] = b - a <= GLITCH_MAX
        want = z.copy()
        if glitch.any() and not glitch.all():  # the line over every sample that is no glitch
            idx = np.arange(n)
            want[glitch] = np.interp(idx[glitch], idx[~glitch], z[~glitch])
        got = _bridged(z, outliers, (False, False))  # inside the record (edges: _edges)
        assert got.dtype == want.dtype and np.array_equal(got, want)


def test_the_half_block_levels_are_the_bracketing_levels():
    from noisevar.estimators.auto._levels import bracketing

    def per_sample(idx, local, block):  # the two block centres around each sample, compared
        nb = local.size
        own = np.minimum(idx // block, nb - 1)
        side = np.clip(np.where(idx - own * block < block // 2, own - 1, own + 1), 0, nb - 1)
        return np.maximum(local[own], local[side])

    rng = np.random.default_rng(23)
    for _ in range(300):
        block = int(rng.choice([2, 16, 17, 256]))
        nb = int(rng.integers(1, 40))
        local = rng.random(nb) * rng.choice([0.0, 1.0, np.inf], nb, p=[0.1, 0.85, 0.05])
        idx = rng.integers(0, nb * block + int(rng.integers(0, 2 * block)), 300)
        assert np.array_equal(bracketing(idx, local, block), per_sample(idx, local, block))


def test_the_residual_filter_read_backwards_is_the_residual_mirrored():
    from noisevar.diagnostics.plan import DIAG_ORDER, DIAG_SPAN
    from noisevar.numeric.fir import centred_fir, residual_sequence

    z = _motion(50_000, 21) * 3.7e-3 + 12.0
    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    assert np.array_equal(centred_fir(z[::-1].copy(), d), centred_fir(z, d)[::-1])


@pytest.mark.parametrize(("seed", "n"), [(1, 150_000), (2, 150_000), (3, 20_000)])
def test_the_reversed_grid_read_off_pass_one_is_the_reversed_records_profile(seed, n):
    """The first pass's mirrored blocks (no pass over the reversed record): the profile of
    the record reversed, the same blocks, quiet set and regimes, its sums to rounding (at
    20,000 samples the kurtosis's blocks are not the profile's)."""
    z = _steps_of(n, seed) + _motion(n, seed)  # bursts are no jumps (their own level)
    ca = ChunkedAuto(lambda a, b: z[max(a, 0) : b], z.size, probe=z.__getitem__, chunk=1 << 13)
    ca.estimate({})
    assert ca.sums is not None and ca.sums.back is not None and ca.jump_runs
    from noisevar.diagnostics import profile_from_sums

    got = profile_from_sums(ca.sums.back)
    left = np.zeros(z.size, dtype=bool)
    for a, b in ca.jump_runs:
        left[a:b] = True
    want = profile_of(z[::-1].copy(), Segmentation(((0, z.size),), ()), left[::-1].copy())
    assert got.still_stretches == want.still_stretches and got.regimes == want.regimes
    for f in ("start", "stop", "count", "quiet", "robust"):
        assert np.array_equal(getattr(got, f), getattr(want, f)), f
    for f in ("variance", "lo", "hi", "dof"):
        np.testing.assert_allclose(getattr(got, f), getattr(want, f), rtol=1e-12, err_msg=f)
