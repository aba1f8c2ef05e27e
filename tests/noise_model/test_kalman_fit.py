"""fit_kalman: the Nile values, recovery on seeded tracks, the NIS band, rejection, bad input."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal
import statsmodels.api as sm

import noisevar
from noisevar.errors import NoisevarError
from noisevar.kalman.divergence import nis_band
from noisevar.noise_model import evaluate_kalman, fit_kalman, run_tuned
from noisevar.noise_model._steady import _transient, diffuse_start, filter_pass
from noisevar.noise_model.kalman_fit import kinematic_model


@pytest.fixture(scope="module")
def nile() -> np.ndarray:
    return sm.datasets.nile.load_pandas().data["volume"].to_numpy(float)


def test_reexported():
    assert noisevar.fit_kalman is fit_kalman
    assert noisevar.KalmanTuning.__name__ == "KalmanTuning"


def test_nile_local_level_matches_durbin_koopman(nile):
    t = fit_kalman(nile, model="rw", method="mle")
    assert t.r == pytest.approx(15099, rel=5e-3)
    assert t.q == pytest.approx(1469.1, rel=5e-3)
    assert t.r_interval[0] < t.r < t.r_interval[1]
    assert t.start == 1


def test_nile_loglik_matches_statsmodels(nile):
    mod = sm.tsa.UnobservedComponents(nile, level="llevel", use_exact_diffuse=True)
    t = fit_kalman(nile, model="rw", method="mle")
    assert t.loglik == pytest.approx(mod.loglike([t.r, t.q]), abs=1e-6)


def test_kinematic_matrices_are_E6_1():
    T = 0.2
    F, h, Q1 = kinematic_model("ca", T)
    assert np.allclose(F, [[1, T, T**2 / 2], [0, 1, T], [0, 0, 1]])
    assert np.allclose(Q1[0], [T**5 / 20, T**4 / 8, T**3 / 6])
    assert np.allclose(Q1[1:, 1:], [[T**3 / 3, T**2 / 2], [T**2 / 2, T]])
    assert np.allclose(h, [1, 0, 0])


def test_lti_pass_equals_the_time_varying_filter(make_track):
    z = make_track("cv", 3000, 10.0, 0.5, 1.0, seed=3)
    F, h, Q1 = kinematic_model("cv", 0.1)
    fast = filter_pass(z - z[0], F, h, 0.5 * Q1, 1.0)
    x0, P0, d = diffuse_start(z - z[0], F, h, 0.5 * Q1, 1.0)
    e, s, X, used, _ = _transient(z[d:] - z[0], F, h, 0.5 * Q1, 1.0, x0, P0, -1.0, 10**9)
    assert used == z.size - d and fast.innovations.size == used
    assert np.allclose(fast.innovations, e, atol=1e-9)
    assert np.allclose(fast.states, X, atol=1e-9)


@pytest.mark.parametrize("method", ["mle", "als"])
@pytest.mark.parametrize("model,q", [("cv", 2.0), ("ca", 5.0), ("rw", 0.3)])
def test_recovers_q_and_r(method, model, q, make_track):
    z = make_track(model, 8000, 10.0, q, 4.0, seed=11)
    t = fit_kalman(z, model=model, rate=10.0, method=method)
    assert t.r == pytest.approx(4.0, rel=0.06)
    assert t.q == pytest.approx(q, rel=0.3)
    assert t.q_interval[0] < q < t.q_interval[1]
    assert t.innovations_white
    assert t.nis_consistent
    assert t.h == pytest.approx(t.q * 0.1 ** {"rw": 1, "cv": 3, "ca": 5}[model] / t.r)


def test_nis_band_and_validation_of_a_wrong_r(make_track):
    z = make_track("cv", 5000, 10.0, 1.0, 1.0, seed=4)
    good = evaluate_kalman(z, "cv", 1.0, 1.0, rate=10.0)
    bad = evaluate_kalman(z, "cv", 1.0, 0.25, rate=10.0)
    assert good.nis_band == nis_band(1, 5000 - 2)
    assert good.nis_consistent and not bad.nis_consistent
    assert bad.nis_mean > 3.0
    assert any("NIS" in n for n in bad.notes)


def test_a_model_the_data_reject_is_said_so():
    rng = np.random.default_rng(5)
    # a random walk observed through strongly coloured (AR(1)) noise: rw innovations are not white
    z = np.cumsum(rng.normal(0, 0.1, 6000)) + rng.normal(0, 0.3, 6000)
    z += scipy.signal.lfilter([1], [1, -0.9], rng.normal(size=6000))
    t = fit_kalman(z, model="cv", rate=1.0)
    assert not t.innovations_white
    assert any("reject" in n for n in t.notes)


def test_run_tuned_gives_the_filter_on_the_record(make_track):
    z = make_track("cv", 2000, 10.0, 1.0, 1.0, seed=6)
    t = fit_kalman(z, "cv", rate=10.0)
    run = run_tuned(t, z)
    assert run.index[0] == t.start and run.states.shape == (2000 - t.start, 2)
    assert np.mean(run.nis) == pytest.approx(t.nis_mean, rel=1e-12)
    assert np.std(run.states[:, 0] - z[t.start :]) < np.sqrt(t.r)


def test_to_dict_is_json_safe(make_track):
    import json

    z = make_track("rw", 500, 1.0, 0.1, 1.0, seed=7)
    d = fit_kalman(z, "rw").to_dict()
    text = json.dumps(d, allow_nan=False)
    assert d["bic"] == pytest.approx(2 * np.log(499) - 2 * d["loglik"])
    assert '"model": "rw"' in text and d["units"]["q"].startswith("u²/sample")


def test_progress_reaches_one(make_track):
    seen: list[float] = []
    fit_kalman(make_track("rw", 400, 1.0, 0.1, 1.0, seed=8), "rw", progress=seen.append)
    assert seen[-1] == 1.0 and all(0 <= a <= b <= 1 for a, b in zip(seen, seen[1:], strict=False))


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"model": "xx"}, "unknown model"),
        ({"rate": 0.0}, "positive"),
        ({"rate": -5.0}, "positive"),
        ({"method": "em"}, "unknown method"),
        ({"lags": 1}, "lags"),
    ],
)
def test_bad_arguments(kwargs, match):
    with pytest.raises(NoisevarError, match=match):
        fit_kalman(np.random.default_rng(0).normal(size=200), **kwargs)


@pytest.mark.parametrize(
    "z,match",
    [
        (np.ones(100), "constant"),
        (np.arange(10.0), "at least"),
        (np.r_[np.nan, np.ones(99)], "NaN"),
        (np.ones((10, 10)), "1-D"),
    ],
)
def test_bad_signals(z, match):
    with pytest.raises(NoisevarError, match=match):
        fit_kalman(z, "cv")


def test_evaluate_refuses_non_positive_q():
    with pytest.raises(NoisevarError, match="q must be a positive"):
        evaluate_kalman(np.random.default_rng(0).normal(size=200), "rw", 0.0, 1.0)


def test_an_unidentified_term_gets_an_open_interval_without_a_warning():
    import warnings

    from noisevar.noise_model.kalman_tails import RobustCovariance

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        draws = np.linspace(-2.0, 2.0, 9)[:, None]
        lo, hi = RobustCovariance(np.eye(1) * 1e6, draws, np.ones((9, 1, 1))).interval(0.0, [1])
    assert lo == 0.0 and hi == float("inf")
