"""The Kalman package: no private numpy import, the step functions are a KF, strategy state."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import noisevar
from noisevar.kalman import (
    KalmanFilter,
    StateSpaceModel,
    VariationalBayesR,
    make_strategy,
    nis_band,
    steps,
)

ROOT = Path(noisevar.__file__).resolve().parent


def test_no_private_numpy_linalg_anywhere():
    for path in (ROOT / "kalman").rglob("*.py"):
        assert "_umath_linalg" not in path.read_text(encoding="utf-8"), path


def test_step_functions_equal_a_textbook_kalman_step():
    rng = np.random.default_rng(0)
    n, m, B = 3, 2, 4
    F = np.eye(n) + 0.1 * rng.normal(size=(n, n))
    H = rng.normal(size=(m, n))
    G = rng.normal(size=(n, n))
    Q = G @ G.T * 0.01
    R = np.diag([0.5, 2.0])
    x = rng.normal(size=(B, n))
    L = rng.normal(size=(B, n, n))
    P = L @ L.transpose(0, 2, 1) + np.eye(n)
    z = rng.normal(size=(B, m))
    x_pred, P_pred = steps.predict(x, P, F, Q)
    d = steps.innovation(z, steps.matvec(H, x_pred))
    PHt, S, S_inv, K = steps.gain(P_pred, H, R)
    x_new, P_new = steps.update(x_pred, P_pred, d, K, H, R)
    for b in range(B):  # one run at a time, as in a textbook
        xp = F @ x[b]
        Pp = F @ P[b] @ F.T + Q
        y = z[b] - H @ xp
        Sb = H @ Pp @ H.T + R
        Kb = Pp @ H.T @ np.linalg.inv(Sb)
        xb = xp + Kb @ y
        Pb = (np.eye(n) - Kb @ H) @ Pp  # the short form equals Joseph for the optimal gain
        np.testing.assert_allclose(x_pred[b], xp, rtol=1e-12)
        np.testing.assert_allclose(P_pred[b], Pp, rtol=1e-12)
        np.testing.assert_allclose(S[b], Sb, rtol=1e-12)
        np.testing.assert_allclose(S_inv[b] @ Sb, np.eye(m), atol=1e-12)
        np.testing.assert_allclose(K[b], Kb, rtol=1e-10)
        np.testing.assert_allclose(x_new[b], xb, rtol=1e-10)
        np.testing.assert_allclose(P_new[b], Pb, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(P_new[b], P_new[b].T, rtol=0, atol=0)


def test_wrap_and_singular_inverse():
    a = np.array([[0.0, 3.5 * np.pi], [1.0, -np.pi]])
    steps.wrap_columns(a, [1])
    np.testing.assert_allclose(a[:, 1], [-0.5 * np.pi, -np.pi])
    inv = steps.inv(np.stack([np.eye(2), np.zeros((2, 2))]))
    np.testing.assert_array_equal(inv[0], np.eye(2))
    assert np.all(np.isnan(inv[1]))


def _model() -> StateSpaceModel:
    return StateSpaceModel(
        Q=np.eye(2) * 0.01, R=np.eye(2), x0=[0.0, 0.0], P0=np.eye(2), F=np.eye(2), H=np.eye(2)
    )


@pytest.mark.parametrize("name", ["vb", "rae", "sage-husa", "rae-q", "iae", "fixed"])
def test_state_restore_puts_the_chosen_runs_back(name):
    rng = np.random.default_rng(1)
    B = 3
    filt = KalmanFilter(_model(), strategy=make_strategy(name), batch_size=B)
    for _ in range(5):
        filt.predict()
        filt.update(rng.normal(size=(B, 2)))
    saved = filt.strategy.state()
    assert all(v.shape[0] == B for v in saved.values())
    for _ in range(3):
        filt.predict()
        filt.update(5.0 * rng.normal(size=(B, 2)))
    after = filt.strategy.state()
    runs = np.array([True, False, True])
    filt.strategy.restore(saved, runs)
    now = filt.strategy.state()
    assert set(now) == set(saved)
    for key in saved:
        np.testing.assert_array_equal(now[key][runs], saved[key][runs])
        np.testing.assert_array_equal(now[key][~runs], after[key][~runs])


def test_state_is_a_copy():
    filt = KalmanFilter(_model(), strategy=VariationalBayesR(), batch_size=2)
    saved = filt.strategy.state()
    assert {"_alpha", "_beta", "_beta_pred"} <= set(saved)
    filt.predict()
    filt.update(np.ones((2, 2)))
    assert not np.allclose(filt.strategy.state()["_alpha"], saved["_alpha"])


def test_nis_band_is_a_pair_around_the_mean():
    lo, hi = nis_band(4, window=50)
    assert lo < 4.0 < hi
    lo1, hi1 = nis_band(4)
    assert lo1 < lo and hi1 > hi
