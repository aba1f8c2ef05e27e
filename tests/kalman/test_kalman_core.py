"""Filter core: equals a textbook KF and filterpy, EKF form, Huber, step API, errors, divergence."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.kalman import (
    DivergenceCheck,
    FixedR,
    HuberUpdate,
    KalmanFilter,
    StateSpaceModel,
    check_covariance,
    quadratic_form_inverse,
    run_filter,
)


def random_linear_system(seed: int = 3, n: int = 4, m: int = 2, steps: int = 300):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    F = 0.97 * A / np.max(np.abs(np.linalg.eigvals(A)))
    H = rng.normal(size=(m, n))
    G = rng.normal(size=(n, n))
    Q = 0.05 * G @ G.T + 0.01 * np.eye(n)
    L = rng.normal(size=(m, m))
    R = L @ L.T + 0.5 * np.eye(m)
    x = np.zeros(n)
    xs, zs = [], []
    for _ in range(steps):
        x = F @ x + rng.multivariate_normal(np.zeros(n), Q)
        xs.append(x)
        zs.append(H @ x + rng.multivariate_normal(np.zeros(m), R))
    x0 = rng.normal(size=n)
    model = StateSpaceModel(Q=Q, R=R, x0=x0, P0=np.eye(n) * 2.0, F=F, H=H)
    return model, np.array(zs), np.array(xs)


def textbook_kf(model: StateSpaceModel, z: np.ndarray):
    F, H, Q, R = model.F, model.H, model.Q, model.R
    x, P = model.x0.copy(), model.P0.copy()
    xs, Ps, ds, nis = [], [], [], []
    for zk in z:
        x = F @ x
        P = F @ P @ F.T + Q
        d = zk - H @ x
        S = H @ P @ H.T + R
        K = P @ H.T @ np.linalg.inv(S)
        x = x + K @ d
        P = (np.eye(len(x)) - K @ H) @ P
        P = 0.5 * (P + P.T)
        xs.append(x)
        Ps.append(P)
        ds.append(d)
        nis.append(d @ np.linalg.solve(S, d))
    return np.array(xs), np.array(Ps), np.array(ds), np.array(nis)


def test_fixed_r_equals_textbook_kf():
    model, z, truth = random_linear_system()
    res = run_filter(model, z, strategy=FixedR(), truth=truth)
    xs, Ps, ds, nis = textbook_kf(model, z)
    assert np.max(np.abs(res.x - xs)) < 1e-10
    assert np.max(np.abs(res.P - Ps)) < 1e-10
    assert np.max(np.abs(res.innovation - ds)) < 1e-10
    assert np.max(np.abs(res.nis - nis)) < 1e-10
    assert not res.diverged and res.divergence_step == -1
    assert np.allclose(res.P, np.swapaxes(res.P, -1, -2), atol=0)  # exactly symmetric
    assert np.allclose(res.R, model.R) and np.allclose(res.Q, model.Q)
    # residual r = z - H x(k|k)
    assert np.max(np.abs(res.residual - (z - xs @ model.H.T))) < 1e-10
    assert res.nees is not None and 2.0 < np.mean(res.nees) < 6.0


def test_fixed_r_equals_filterpy():
    filterpy = pytest.importorskip("filterpy.kalman")
    model, z, _ = random_linear_system(seed=11, n=3, m=2, steps=200)
    kf = filterpy.KalmanFilter(dim_x=3, dim_z=2)
    kf.F, kf.H, kf.Q, kf.R = model.F, model.H, model.Q, model.R
    kf.x = model.x0.reshape(3, 1).copy()
    kf.P = model.P0.copy()
    xs, Ps = [], []
    for zk in z:
        kf.predict()
        kf.update(zk.reshape(2, 1))
        xs.append(kf.x.ravel().copy())
        Ps.append(kf.P.copy())
    res = run_filter(model, z)
    assert np.max(np.abs(res.x - np.array(xs))) < 1e-10
    assert np.max(np.abs(res.P - np.array(Ps))) < 1e-10


def test_batch_equals_single_runs():
    model, z, truth = random_linear_system(seed=5, steps=150)
    rng = np.random.default_rng(0)
    zb = np.stack([z, z + rng.normal(size=z.shape), z * 0.5])
    batch = run_filter(model, zb, truth=np.stack([truth] * 3))
    assert batch.batched and batch.x.shape == (3, 150, 4)
    for b in range(3):
        single = run_filter(model, zb[b], truth=truth)
        assert np.max(np.abs(batch.x[b] - single.x)) < 1e-12
        assert np.max(np.abs(batch.nees[b] - single.nees)) < 1e-9


def test_extended_form_of_a_linear_model_equals_linear():
    model, z, _ = random_linear_system(seed=8, steps=100)
    F, H = model.F, model.H
    ekf = StateSpaceModel(
        Q=model.Q,
        R=model.R,
        x0=model.x0,
        P0=model.P0,
        f=lambda x, k: x @ F.T,
        F_jacobian=lambda x, k: F,
        h=lambda x, k: x @ H.T,
        H_jacobian=lambda x, k: np.broadcast_to(H, (x.shape[0], *H.shape)),
    )
    a, b = run_filter(model, z), run_filter(ekf, z)
    assert np.max(np.abs(a.x - b.x)) < 1e-10
    assert np.max(np.abs(a.P - b.P)) < 1e-10


def test_selection_h_fast_path_equals_matrix_path():
    rng = np.random.default_rng(2)
    F = np.array([[1, 0.1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1.0]])
    H = np.array([[0, 0, 1.0, 0], [1.0, 0, 0, 0]])  # picks states 2 and 0
    Q = np.diag([1e-3, 1e-2, 1e-3, 1e-2])
    model = StateSpaceModel(Q=Q, R=np.diag([1.0, 2.0]), x0=np.zeros(4), P0=np.eye(4), F=F, H=H)
    assert model.measured_states == (2, 0)
    z = rng.normal(size=(80, 2)).cumsum(axis=0)
    ekf = StateSpaceModel(
        Q=Q,
        R=model.R,
        x0=np.zeros(4),
        P0=np.eye(4),
        F=F,
        h=lambda x, k: x @ H.T,
        H_jacobian=lambda x, k: H,
    )
    a, b = run_filter(model, z), run_filter(ekf, z)
    assert np.max(np.abs(a.x - b.x)) < 1e-10
    assert np.max(np.abs(a.residual - b.residual)) < 1e-10


def test_step_interface_equals_run_and_exposes_predictions():
    model, z, _ = random_linear_system(seed=4, steps=60)
    res = run_filter(model, z)
    filt = KalmanFilter(model)
    for k in range(60):
        filt.predict()
        np.testing.assert_allclose(filt.x_pred[0], res.x_pred[k], atol=1e-12)
        np.testing.assert_allclose(filt.P_pred[0], res.P_pred[k], atol=1e-12)
        filt.update(z[k])
        np.testing.assert_allclose(filt.x[0], res.x[k], atol=1e-12)
        np.testing.assert_allclose(filt.P[0], res.P[k], atol=1e-12)
    filt.predict()
    filt.skip_update()
    assert np.array_equal(filt.x, filt.x_pred) and np.array_equal(filt.P, filt.P_pred)


def test_huber_with_infinite_kappa_equals_plain_update():
    model, z, _ = random_linear_system(seed=9, steps=200)
    plain = run_filter(model, z)
    huber = run_filter(model, z, robust=HuberUpdate(kappa=np.inf))
    assert np.max(np.abs(plain.x - huber.x)) < 1e-10
    assert np.max(np.abs(plain.P - huber.P)) < 1e-10
    assert huber.strategy == "fixed+huber"


def test_huber_resists_outliers():
    from noisevar.systems.scenarios import outliers

    sc = outliers(runs=2, seed=1, n_steps=2000)
    plain = sc.run(FixedR())
    robust = sc.run(FixedR(), robust=HuberUpdate())
    hit = sc.outlier_mask[:, sc.first_step :].any(axis=-1)
    e_plain = np.hypot(*plain.state_error()[..., [0, 2]].transpose(2, 0, 1))
    e_rob = np.hypot(*robust.state_error()[..., [0, 2]].transpose(2, 0, 1))
    assert e_rob[hit].mean() < 0.7 * e_plain[hit].mean()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"H": np.ones((2, 3))}, "H has shape"),
        ({"Q": np.eye(3)}, "Q has shape"),
        (
            {"Q": np.array([[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])},
            "not symmetric",
        ),
        ({"Q": -np.eye(4)}, "not positive semidefinite"),
        ({"R": np.diag([1.0, 0.0])}, "not positive definite"),
        ({"R": np.array([[1.0, 2.0], [2.0, 1.0]])}, "not positive definite"),
        ({"R": np.array([[1.0, np.nan], [np.nan, 1.0]])}, "NaN"),
        ({"x0": np.zeros(3)}, "shape"),
        ({"F": None}, "transition matrix F or a function f"),
        (
            {"F": None, "f": lambda x, k: x[:, :2], "F_jacobian": lambda x, k: np.eye(4)},
            "returned shape",
        ),
        ({"F": None, "f": lambda x, k: x}, "callables f and F_jacobian"),
    ],
)
def test_bad_models_give_clear_errors(kwargs, match):
    base = {
        "Q": np.eye(4) * 0.1,
        "R": np.eye(2),
        "x0": np.zeros(4),
        "P0": np.eye(4),
        "F": np.eye(4),
        "H": np.eye(2, 4),
    }
    base.update(kwargs)
    with pytest.raises(NoisevarError, match=match):
        StateSpaceModel(**base)


def test_bad_measurements_give_clear_errors():
    model, z, _ = random_linear_system(steps=20)
    bad = z.copy()
    bad[5, 1] = np.nan
    with pytest.raises(NoisevarError, match="step 5, channel 1"):
        run_filter(model, bad)
    with pytest.raises(NoisevarError, match="expected"):
        run_filter(model, z[:, :1])
    with pytest.raises(NoisevarError, match="truth"):
        run_filter(model, z, truth=np.zeros((5, 4)))
    filt = KalmanFilter(model)
    filt.predict()
    with pytest.raises(NoisevarError, match="NaN"):
        filt.update(np.array([np.nan, 1.0]))
    with pytest.raises(NoisevarError, match="shape"):
        filt.update(np.zeros(3))
    with pytest.raises(NoisevarError, match="RStrategy"):
        run_filter(model, z, strategy="vb")
    with pytest.raises(NoisevarError, match="x0"):
        run_filter(model, z, x0=np.zeros(7))


def test_check_covariance_accepts_variances_vector():
    np.testing.assert_array_equal(check_covariance([1.0, 2.0], "R"), np.diag([1.0, 2.0]))


def test_divergence_exploding_covariance_is_reported_and_masked():
    # an unstable, unobserved state: its variance grows 4x per step
    F = np.diag([2.0, 1.0])
    model = StateSpaceModel(
        Q=np.diag([1.0, 0.01]), R=np.eye(1), x0=np.zeros(2), P0=np.eye(2), F=F, H=[[0.0, 1.0]]
    )
    z = np.random.default_rng(0).normal(size=(200, 1))
    res = run_filter(model, z)
    assert res.diverged
    assert "covariance exploded" in res.divergence_reason
    k = res.divergence_step
    assert 0 < k < 200
    assert np.all(np.isnan(res.x[k:])) and np.all(np.isfinite(res.x[:k]))


def test_divergence_nan_state_is_reported():
    def f(x, k):
        return x if k < 30 else x * np.inf

    model = StateSpaceModel(
        Q=np.eye(1) * 0.1,
        R=np.eye(1),
        x0=np.ones(1),
        P0=np.eye(1),
        f=f,
        F_jacobian=lambda x, k: np.ones((x.shape[0], 1, 1)),
        H=np.eye(1),
    )
    res = run_filter(model, np.ones((100, 1)), divergence=DivergenceCheck(check_every=10))
    assert res.diverged and "NaN" in res.divergence_reason
    assert res.divergence_step == 30


def test_divergence_nis_far_outside_band():
    # the filter believes R = 0.01 while the noise variance is 100
    model = StateSpaceModel(
        Q=np.eye(1) * 1e-6,
        R=np.eye(1) * 0.01,
        x0=np.zeros(1),
        P0=np.eye(1),
        F=np.eye(1),
        H=np.eye(1),
    )
    z = np.random.default_rng(1).normal(0, 10, size=(500, 1))
    res = run_filter(model, z)
    assert res.diverged and res.divergence_reason.startswith("NIS diverged")
    assert np.all(np.isfinite(res.x))  # inconsistent, not blown up: values kept


def test_quadratic_form_inverse_matches_linalg():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(7, 9, 5, 5))
    A = A @ np.swapaxes(A, -1, -2) + np.eye(5)
    v = rng.normal(size=(7, 9, 5))
    ref = np.einsum("...i,...ij,...j->...", v, np.linalg.inv(A), v)
    np.testing.assert_allclose(quadratic_form_inverse(A, v), ref, rtol=1e-12)
    A[0, 0] = -np.eye(5)
    assert np.isnan(quadratic_form_inverse(A, v)[0, 0])
