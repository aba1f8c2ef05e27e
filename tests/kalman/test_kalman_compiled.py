"""The compiled (numba) backend gives the numpy backend's results (to 1e-10)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.kalman import (
    KalmanFilter,
    OracleR,
    RStrategy,
    SomdOnlineR,
    StateSpaceModel,
    kernels,
    make_strategy,
    run_filter,
)
from noisevar.systems.scenarios import gps_circle, noise_step

pytestmark = pytest.mark.skipif(not kernels.HAVE_NUMBA, reason="numba not installed")

STRATEGY_NAMES = ["fixed", "oracle", "somd-online", "rae", "iae", "rae-q", "sage-husa", "vb"]
FIELDS = ("x", "P", "innovation", "residual", "innovation_cov", "R", "Q", "nis", "nees")


def _strategy(name: str, R_true: np.ndarray, h_smooth) -> RStrategy:
    if name == "oracle":
        return OracleR(R_true)
    if name == "somd-online":
        return SomdOnlineR(h_smooth=h_smooth)
    return make_strategy(name)


def _both(run, monkeypatch):
    """``run()`` with the compiled kernels, then with the numpy path."""
    monkeypatch.setattr(kernels, "USE_COMPILED", True)
    fast = run()
    monkeypatch.setattr(kernels, "USE_COMPILED", False)
    plain = run()
    return fast, plain


def _assert_same(fast, plain, tol: float = 1e-10) -> None:
    np.testing.assert_array_equal(fast.diverged, plain.diverged)
    np.testing.assert_array_equal(fast.divergence_step, plain.divergence_step)
    for key in FIELDS:
        a, b = getattr(fast, key), getattr(plain, key)
        if b is None:
            assert a is None, key
            continue
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=key)
        finite = np.isfinite(b)
        scale = float(np.max(np.abs(b[finite]), initial=1.0))
        np.testing.assert_allclose(a, b, rtol=tol, atol=tol * scale, err_msg=key)


def _random_linear(n: int, m: int, seed: int) -> tuple[StateSpaceModel, np.ndarray]:
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    F = 0.97 * A / np.max(np.abs(np.linalg.eigvals(A)))  # stable
    H = rng.normal(size=(m, n))
    G = rng.normal(size=(n, n))
    Q = 0.01 * (G @ G.T + np.eye(n))
    R = np.diag(rng.uniform(0.5, 2.0, m))
    model = StateSpaceModel(Q=Q, R=R, x0=np.zeros(n), P0=np.eye(n), F=F, H=H)
    B, N = 3, 400
    x = np.zeros((B, n))
    z = np.empty((B, N, m))
    for k in range(N):
        x = x @ F.T + rng.multivariate_normal(np.zeros(n), Q, size=B)
        z[:, k] = x @ H.T + rng.normal(size=(B, m)) * np.sqrt(np.diag(R)) * 1.5
    return model, z


@pytest.mark.parametrize("name", STRATEGY_NAMES)
def test_random_linear_system(name, monkeypatch):
    model, z = _random_linear(3, 2, seed=11)
    R_true = 2.25 * model.R

    def run():
        return run_filter(model, z, strategy=_strategy(name, R_true, 1e-3), store_predicted=True)

    fast, plain = _both(run, monkeypatch)
    _assert_same(fast, plain)
    np.testing.assert_allclose(fast.x_pred, plain.x_pred, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(fast.P_pred, plain.P_pred, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("name", STRATEGY_NAMES)
def test_gps_circle_every_strategy(name, monkeypatch):
    sc = gps_circle(runs=2, seed=5, duration=600.0)

    def run():
        return sc.run(_strategy(name, sc.R_true[0], sc.h_smooth))

    fast, plain = _both(run, monkeypatch)
    _assert_same(fast, plain)


@pytest.mark.parametrize("name", ["fixed", "vb", "sage-husa"])
def test_selection_h_batch(name, monkeypatch):
    """noise-step measures two of four states (H selects), batch of 4, one angle-free model."""
    sc = noise_step(runs=4, seed=2, n_steps=600)

    def run():
        return sc.run(_strategy(name, sc.R_true, sc.h_smooth))

    fast, plain = _both(run, monkeypatch)
    _assert_same(fast, plain)


def _range_bearing_model() -> StateSpaceModel:
    def f(x, k):
        return x @ np.array([[1.0, 0, 1, 0], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]]).T

    def F_jac(x, k):
        return np.array([[1.0, 0, 1, 0], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]])

    def h(x, k):
        return np.stack([np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0])], axis=1)

    def H_jac(x, k):
        r2 = x[:, 0] ** 2 + x[:, 1] ** 2
        r = np.sqrt(r2)
        J = np.zeros((x.shape[0], 2, 4))
        J[:, 0, 0], J[:, 0, 1] = x[:, 0] / r, x[:, 1] / r
        J[:, 1, 0], J[:, 1, 1] = -x[:, 1] / r2, x[:, 0] / r2
        return J

    return StateSpaceModel(
        Q=np.diag([0.1, 0.1, 0.01, 0.01]),
        R=np.diag([1.0, 1e-4]),
        x0=np.array([-100.0, -5.0, 2.0, 0.5]),
        P0=np.diag([10.0, 10.0, 1.0, 1.0]),
        f=f,
        F_jacobian=F_jac,
        h=h,
        H_jacobian=H_jac,
        angle_measurements=(1,),
    )


@pytest.mark.parametrize("name", ["fixed", "rae", "vb"])
def test_user_ekf_functions_with_an_angle(name, monkeypatch):
    """Plain-numpy f, F, h, H of a user (range and a bearing that crosses ±π)."""
    model = _range_bearing_model()
    rng = np.random.default_rng(4)
    N = 300
    x = np.array([-100.0, -5.0, 2.0, 0.5])
    truth = np.empty((N, 4))
    for k in range(N):
        x = model.f(x[None], k)[0]
        truth[k] = x
    z = model.h(truth, 0) + rng.normal(size=(N, 2)) * [1.0, 0.01]
    z[:, 1] = np.mod(z[:, 1] + np.pi, 2 * np.pi) - np.pi

    def run():
        return run_filter(model, z, strategy=make_strategy(name), truth=truth)

    fast, plain = _both(run, monkeypatch)
    _assert_same(fast, plain)


class _ListR(RStrategy):
    """A user strategy returning ``R`` as a nested list and ``Q`` as a batch."""

    name = "list-r"

    def process_covariance(self, filt):
        return np.repeat(filt.model.Q[None], filt.batch_size, axis=0) * 1.5

    def measurement_covariance(self, filt):
        return (np.asarray(filt.model.R) * 2.0).tolist()


def test_user_strategy_returning_other_types(monkeypatch):
    sc = gps_circle(runs=2, seed=1, duration=200.0)
    fast, plain = _both(lambda: sc.run(_ListR()), monkeypatch)
    _assert_same(fast, plain)


def test_step_by_step_equals_whole_record(monkeypatch):
    sc = gps_circle(runs=1, seed=3, duration=100.0)
    z = sc.z[0, 1:]
    whole = run_filter(sc.model, z, strategy=make_strategy("vb"), x0=sc.x0[0])
    monkeypatch.setattr(kernels, "USE_COMPILED", True)
    filt = KalmanFilter(sc.model, strategy=make_strategy("vb"), x0=sc.x0[0])
    assert filt.compiled
    kept = []
    for k in range(z.shape[0]):
        filt.predict()
        filt.update(z[k])
        kept.append((filt.x_pred, filt.x))
    # every step's arrays are new memory
    np.testing.assert_allclose(np.array([x for _, x in kept])[:, 0], whole.x, rtol=0, atol=1e-9)
    assert kept[0][1] is not kept[1][1] and kept[0][0] is not kept[1][0]


def test_bad_r_shape_from_a_strategy_is_reported(monkeypatch):
    class Bad(RStrategy):
        def measurement_covariance(self, filt):
            return np.eye(3)

    sc = gps_circle(runs=1, seed=0, duration=50.0)
    monkeypatch.setattr(kernels, "USE_COMPILED", True)
    with pytest.raises(NoisevarError, match="R has shape"):
        sc.run(Bad())


def test_transition_must_agree_with_f():
    sc = gps_circle(runs=1, seed=0, duration=50.0)
    m = sc.model

    def wrong(x, k, x_out, F_out):
        m.transition(x, k, x_out, F_out)
        x_out += 1.0

    with pytest.raises(NoisevarError, match="transition disagrees"):
        StateSpaceModel(
            Q=m.Q,
            R=m.R,
            x0=m.x0,
            P0=m.P0,
            f=m.f,
            F_jacobian=m.F_jacobian,
            H=m.H,
            transition=wrong,
        )
    with pytest.raises(NoisevarError, match="transition must be"):
        StateSpaceModel(Q=m.Q, R=m.R, x0=m.x0, P0=m.P0, F=np.eye(4), H=m.H, transition=wrong)


def test_singular_innovation_covariance_gives_nan():
    n = m = 2
    x = np.zeros((1, n))
    P = np.zeros((1, n, n))
    R = np.zeros((1, m, m))
    S, SK = np.empty((1, m, m)), np.empty((1, m + n, m))
    xo, Po, r = np.empty((1, n)), np.empty((1, n, n)), np.empty((1, m))
    kernels.gain_update(
        x,
        P,
        R,
        np.zeros((1, m)),
        np.eye(2)[None],
        kernels.config(0, (), None),
        x,
        True,
        S,
        SK,
        xo,
        Po,
        r,
        np.empty(kernels.work_shape(n, m)),
        (None,) * n,
        (None,) * m,
    )
    assert np.all(np.isnan(SK[:, :m]))
