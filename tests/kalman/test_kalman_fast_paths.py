"""Batched runs, records and helpers of the filter give the plain results (to rounding)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.estimators.somd import somd_variance_records
from noisevar.kalman import (
    FixedR,
    KalmanFilter,
    RStrategy,
    StateSpaceModel,
    VariationalBayesR,
    run_filter,
)
from noisevar.kalman.result import wrap_angle
from noisevar.kalman.steps import wrap_columns
from noisevar.systems.scenarios import gps_circle, noise_step

LARGE_BATCH = 32


@pytest.mark.parametrize("strategy", [FixedR, VariationalBayesR])
def test_large_batch_equals_small_batches(strategy):
    """A batch of runs gives each run's result filtered alone."""
    B = LARGE_BATCH
    sc = gps_circle(runs=B, seed=2, duration=400.0)
    big = sc.run(strategy())
    for b in (0, B - 1):
        small = run_filter(
            sc.model, sc.z[b, 1:], strategy=strategy(), truth=sc.truth[b, 1:], x0=sc.x0[b]
        )
        np.testing.assert_allclose(big.x[b], small.x, rtol=0, atol=1e-9)
        np.testing.assert_allclose(big.P[b], small.P, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(big.nis[b], small.nis, rtol=1e-8)
        assert big.divergence_step[b] == small.divergence_step


def test_linear_large_batch_two_channels():
    sc = noise_step(runs=LARGE_BATCH, seed=3, n_steps=600)
    big = sc.run(VariationalBayesR())
    small = run_filter(
        sc.model, sc.z[5, 2:], strategy=VariationalBayesR(), truth=sc.truth[5, 2:], x0=sc.x0[5]
    )
    np.testing.assert_allclose(big.x[5], small.x, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(big.R[5], small.R, rtol=1e-9)


def test_constant_r_is_recorded_as_a_view_and_changing_r_as_values():
    sc = gps_circle(runs=2, seed=0, duration=100.0)
    fixed = sc.run(FixedR())
    assert not fixed.R.flags.writeable
    np.testing.assert_array_equal(fixed.R, np.broadcast_to(sc.model.R, fixed.R.shape))
    vb = sc.run(VariationalBayesR())
    assert not np.allclose(vb.R[:, -1], sc.model.R)


class _ReplacesState(RStrategy):
    """A strategy whose observe() replaces the filter's estimate (as a fusion centre might)."""

    name = "replaces"

    def measurement_covariance(self, filt: KalmanFilter) -> np.ndarray:
        return filt.model.R

    def observe(self, filt: KalmanFilter) -> None:
        filt.x = filt.x + 1.0


def test_records_follow_arrays_replaced_by_hooks():
    sc = gps_circle(runs=1, seed=0, duration=50.0)
    res = run_filter(sc.model, sc.z[0, 1:], strategy=_ReplacesState(), x0=sc.x0[0])
    filt = KalmanFilter(sc.model, strategy=_ReplacesState(), x0=sc.x0[0])
    for k, z in enumerate(sc.z[0, 1:]):
        filt.predict()
        filt.update(z)
        np.testing.assert_array_equal(res.x[k], filt.x[0])


def test_step_arrays_are_not_overwritten_by_later_steps():
    model = StateSpaceModel(
        Q=np.eye(2) * 0.1, R=np.eye(2), x0=[0.0, 0.0], P0=np.eye(2), F=np.eye(2), H=np.eye(2)
    )
    filt = KalmanFilter(model)
    kept = []
    for z in ([1.0, 2.0], [3.0, -1.0], [0.5, 0.5]):
        filt.predict()
        filt.update(z)
        kept.append((filt.x, filt.P, filt.x.copy(), filt.P.copy()))
    for x, P, x_copy, P_copy in kept:
        np.testing.assert_array_equal(x, x_copy)
        np.testing.assert_array_equal(P, P_copy)


@pytest.mark.parametrize("B", [1, 7])
def test_wrap_columns_equals_wrap_angle(B):
    rng = np.random.default_rng(B)
    a = rng.normal(scale=10.0, size=(B, 4))
    a[0, 3] = np.pi
    ref = a.copy()
    ref[:, 3] = wrap_angle(ref[:, 3])
    wrap_columns(a, [3])
    np.testing.assert_array_equal(a, ref)


@pytest.mark.parametrize("paper", [False, True])
def test_somd_records_equal_the_estimator(paper):
    sc = gps_circle(runs=3, seed=1, duration=1600.0)  # speed (h = 1e-7) needs > 2935
    zu = sc.measured()
    for j, h in enumerate(sc.h_smooth):
        got = somd_variance_records(zu[:, :, j], h, paper=paper)
        for b in range(3):
            ref = noisevar.estimate(
                zu[b, :, j], method="somd-paper" if paper else "somd", h_smooth=h, select=False
            ).variance
            assert got[b] == pytest.approx(ref, rel=1e-12)


def test_somd_records_too_short_give_nan():
    z = np.random.default_rng(0).normal(size=(2, 50))
    assert np.all(np.isnan(somd_variance_records(z, 1e-4)))
