"""Estimators: accuracy on the signal families, redundant sensors, results, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.estimators import HKT_SEQUENCES, METHODS, sequence_efficiency
from noisevar.filters.abg import somd_bias_factor

N = 6000
SEEDS = range(8)
FAMILIES = ("fast-slow", "gps-circle", "random-jerk", "steps-ramps", "noise-step", "noise-ramp")
PEERS = ("rice", "diff2", "hkt1", "hkt2", "hkt3", "mad-diff", "wavelet-mad")


def _rel_errors(method, family, seeds=SEEDS, n=N, **params):
    out = []
    for seed in seeds:
        g = nv.generate(family, n=n, seed=seed)
        out.append(nv.estimate(g.measured, method=method, **params).variance / g.true_variance - 1)
    return np.array(out)


# ------------------------------------------------------------------------ the registry
def test_methods_lists_every_estimator():
    names = nv.methods()
    assert names[0] == "auto"
    for name in ("somd", "somd-paper", "somd-redundant", *PEERS, "mle-level", "mle-trend"):
        assert name in names
    assert len(set(names)) == len(names)
    assert nv.methods("peer") == [*PEERS, "mle-level", "mle-trend"]
    assert nv.methods("ours") == ["auto"]
    assert set(nv.methods("somd")) == {"somd", "somd-paper", "somd-redundant"}
    desc = nv.describe_methods()
    assert list(desc) == names and all(isinstance(v, str) and v for v in desc.values())


def test_sequence_efficiency_known_values():
    assert sequence_efficiency([1.0]) == pytest.approx(1.0)
    assert sequence_efficiency([1.0, -1.0]) == pytest.approx(1.5)  # Rice
    assert sequence_efficiency([1.0, -2.0, 1.0]) == pytest.approx(1 + 2 * (4 / 6) ** 2 + 2 / 36)
    for d in HKT_SEQUENCES.values():
        # exactly zero sum (else an offset leaks in), unit norm
        assert np.sum(d) == pytest.approx(0.0, abs=1e-15)
        assert np.sum(d**2) == pytest.approx(1.0, abs=1e-14)
    # the published values (Hall, Kay & Titterington 1990), to their 4 decimals
    np.testing.assert_allclose(HKT_SEQUENCES[2], [0.8090, -0.5, -0.3090], atol=6e-5)
    np.testing.assert_allclose(HKT_SEQUENCES[3], [0.1942, 0.2809, 0.3832, -0.8582], atol=6e-5)


@pytest.mark.parametrize("method", ["rice", "diff2", "hkt1", "hkt2", "hkt3", "auto", "somd"])
def test_a_large_offset_changes_nothing(method):
    """GPS positions in UTM metres are ~5e6 with metre noise: the offset must not leak."""
    z = nv.generate("random-jerk", n=N, seed=19).measured
    base = nv.estimate(z, method=method).variance
    assert nv.estimate(z + 5e6, method=method).variance == pytest.approx(base, rel=1e-4)


# ---------------------------------------------------------------------- known answers
def test_difference_estimators_by_hand():
    rng = np.random.default_rng(1)
    z = rng.normal(0.0, 3.0, 5000)
    dz, d2z = np.diff(z), np.diff(z, 2)
    assert nv.estimate(z, method="rice").variance == pytest.approx(np.mean(dz**2) / 2, rel=1e-12)
    assert nv.estimate(z, method="diff2").variance == pytest.approx(np.mean(d2z**2) / 6, rel=1e-12)
    assert nv.estimate(z, method="hkt1").variance == pytest.approx(np.mean(dz**2) / 2, rel=1e-12)
    d = HKT_SEQUENCES[3]
    e = np.array([np.dot(d, z[k : k + 4]) for k in range(z.size - 3)])
    assert nv.estimate(z, method="hkt3").variance == pytest.approx(
        np.mean(e**2) / np.sum(d**2), rel=1e-12
    )
    mad = np.median(np.abs(dz - np.median(dz))) / 0.6744897501960817
    assert nv.estimate(z, method="mad-diff").variance == pytest.approx(mad**2 / 2, rel=1e-12)


def test_wavelet_mad_by_hand():
    import pywt

    rng = np.random.default_rng(2)
    z = rng.normal(0.0, 2.0, 4096)
    _, detail = pywt.dwt(z, "db4", mode="periodization")
    sigma = np.median(np.abs(detail)) / 0.6744897501960817
    assert nv.estimate(z, method="wavelet-mad").variance == pytest.approx(sigma**2, rel=1e-12)
    sym = nv.estimate(z, method="wavelet-mad", wavelet="sym8")
    assert sym.params["wavelet"] == "sym8"
    assert sym.variance == pytest.approx(4.0, rel=0.1)


def test_auto_known_answer_on_white_noise_with_a_cubic_trend():
    """The auto virtual sensor is a local cubic: blind to any cubic trend."""
    rng = np.random.default_rng(3)
    k = np.arange(20_000, dtype=float)
    w = rng.normal(0.0, 1.5, k.size)
    cubic = 3.0 + 0.2 * k - 4e-5 * k**2 + 2e-9 * k**3
    plain = nv.estimate(w).variance
    assert plain == pytest.approx(2.25, rel=0.04)
    assert nv.estimate(w + cubic, span=41).variance == pytest.approx(
        nv.estimate(w, span=41).variance, rel=1e-8
    )


# -------------------------------------------------------------------- accuracy: auto
@pytest.mark.parametrize("family", FAMILIES)
def test_auto_is_accurate_on_every_family(family):
    """Auto at n=6000: every seed within 8 % (the Cramér-Rao sd is 1.8 %), mean within 2.5 %."""
    err = _rel_errors("auto", family)
    assert np.max(np.abs(err)) < 0.08
    assert abs(np.mean(err)) < 0.025


# ------------------------------------------------------------------- accuracy: peers
@pytest.mark.parametrize(
    ("method", "family", "tol"),
    [
        ("rice", "random-jerk", 0.04),
        ("rice", "noise-ramp", 0.03),
        ("hkt1", "noise-step", 0.03),
        ("diff2", "gps-circle", 0.03),
        ("diff2", "fast-slow", 0.03),
        ("diff2", "random-jerk", 0.03),
        ("hkt2", "noise-ramp", 0.03),
        ("hkt3", "noise-step", 0.03),
        ("mad-diff", "random-jerk", 0.04),
        ("mad-diff", "steps-ramps", 0.05),  # robust to the jumps
        ("wavelet-mad", "gps-circle", 0.05),
        ("wavelet-mad", "steps-ramps", 0.06),
        ("somd", "fast-slow", 0.06),
        ("somd", "gps-circle", 0.05),
        ("somd", "random-jerk", 0.05),
    ],
)
def test_peer_is_accurate_where_it_should_be(method, family, tol):
    """Mean relative error over 8 seeded runs (sd of that mean is about 1 %)."""
    err = _rel_errors(method, family)
    assert abs(np.mean(err)) < tol
    assert np.max(np.abs(err)) < 0.15


def test_somd_paper_is_biased_high_by_c_over_2():
    """Spec A8: the paper's factor 1/2 over-estimates by c(h)/2 - 1 (+5 % at h=1.5e-5)."""
    paper = _rel_errors("somd-paper", "random-jerk", seeds=range(12))
    ours = _rel_errors("somd", "random-jerk", seeds=range(12))
    c = somd_bias_factor(1.5e-5)
    assert np.mean(paper) > 0.03
    assert np.mean(paper) == pytest.approx(c / 2 - 1, abs=0.03)
    assert abs(np.mean(ours)) < 0.03


def test_rice_is_biased_on_the_gps_circle():
    """Rice assumes the signal does not change between samples; on the circle it does.

    East position R cos(wt) changes by about R w T = 4.7 m per sample (noise 5 m),
    and mean((Δz)²)/2 = sigma² + mean((Δclean)²)/2: about +22 %. The second
    difference removes the (locally linear) motion, and auto with it.
    """
    g = nv.generate("gps-circle", n=N, seed=4)
    motion = np.mean(np.diff(g.clean) ** 2) / 2.0
    rice = nv.estimate(g.measured, method="rice").variance
    assert motion / g.true_variance == pytest.approx(0.22, abs=0.01)
    assert rice / g.true_variance - 1.0 > 0.15
    assert rice == pytest.approx(g.true_variance + motion, rel=0.04)
    assert nv.estimate(g.measured, method="diff2").variance == pytest.approx(25.0, rel=0.06)
    assert nv.estimate(g.measured).variance == pytest.approx(25.0, rel=0.06)


def test_first_difference_peers_are_fooled_by_jumps_and_robust_ones_are_not():
    g = nv.generate("steps-ramps", n=N, seed=5)
    assert nv.estimate(g.measured, method="rice").variance > 1.2 * g.true_variance
    assert nv.estimate(g.measured, method="mad-diff").variance == pytest.approx(
        g.true_variance, rel=0.08
    )
    auto = nv.estimate(g.measured)
    assert auto.variance == pytest.approx(g.true_variance, rel=0.06)
    assert any("around level jumps" in note for note in auto.notes)


def test_mle_trend_and_level():
    """statsmodels ML (slow: one run each). Local level data for the local level model."""
    g = nv.generate("random-jerk", n=3000, seed=6)
    trend = nv.estimate(g.measured, method="mle-trend")
    assert trend.variance == pytest.approx(g.true_variance, rel=0.08)
    assert trend.ci95[0] < trend.variance < trend.ci95[1]
    rng = np.random.default_rng(6)
    level = np.cumsum(rng.normal(0.0, 0.5, 3000)) + rng.normal(0.0, 2.0, 3000)
    est = nv.estimate(level, method="mle-level")
    assert est.variance == pytest.approx(4.0, rel=0.12)
    # the model normalises its input, so units do not matter
    assert nv.estimate(level * 1000.0, method="mle-level").variance == pytest.approx(
        est.variance * 1e6, rel=1e-4
    )


def test_mle_level_starts_from_the_differences_and_reaches_the_same_maximum(monkeypatch):
    """The local level fit starts from the differences' moments (issue 29: the Compare
    table's cost): the same variance as from statsmodels' own start, to its convergence
    tolerance, in fewer likelihood evaluations."""
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    from noisevar.estimators import mle

    fit = UnobservedComponents.fit
    calls: list[int] = []

    def counted(self, *args, **kwargs):
        res = fit(self, *args, **kwargs)
        calls.append(res.mle_retvals["fcalls"])
        return res

    monkeypatch.setattr(UnobservedComponents, "fit", counted)
    z = nv.generate("fast-slow", n=20_000, seed=4).measured  # the benchmark's record
    warm = nv.estimate(z, method="mle-level")
    monkeypatch.setattr(mle, "level_start", lambda y: None)
    cold = nv.estimate(z, method="mle-level")
    assert warm.variance == pytest.approx(cold.variance, rel=1e-3)
    assert calls[0] < 0.75 * calls[1]
    assert mle.level_start(np.ones(100)) is None and mle.level_start(np.arange(5.0)) is None


def test_mle_says_when_its_optimiser_did_not_converge(monkeypatch):
    """statsmodels returns a non-converged fit without complaint; the result says so.

    (At n = 50000 on noise-step, 1 run in 20 stopped after 5 iterations, 13x too high.)
    """
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    fit = UnobservedComponents.fit

    def stopped_early(self, *args, **kwargs):
        res = fit(self, *args, **kwargs)
        res.mle_retvals = {**res.mle_retvals, "converged": False, "iterations": 5}
        return res

    g = nv.generate("random-jerk", n=1000, seed=6)
    assert not any("converg" in note for note in nv.estimate(g.measured, method="mle-trend").notes)
    monkeypatch.setattr(UnobservedComponents, "fit", stopped_early)
    est = nv.estimate(g.measured, method="mle-trend")
    assert any("without converging (after 5 iterations)" in note for note in est.notes)


# ---------------------------------------------------------------- redundant sensors
def _sensors(seed, n, variances):
    """A shared smooth signal, slowly varying per-sensor biases and white noises."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / n
    shared = 300.0 * np.sin(2 * np.pi * 3 * t) + 50.0 * t**2 * n / 1000.0
    cols = []
    for i, v in enumerate(variances):
        bias = 5.0 * np.sin(2 * np.pi * t * (0.5 + 0.3 * i) + i) + 2.0 * i * t
        cols.append(shared + bias + rng.normal(0.0, np.sqrt(v), n))
    return np.column_stack(cols)


def test_two_sensor_somd_recovers_the_noisy_sensor():
    """Eq. 8: var(V2) = E[(ΔZ1 - ΔZ2)²]/2 (- var(V1) when it is known)."""
    z = _sensors(7, 20_000, [0.04, 4.0])
    # the biases matter: the plain difference of the sensors is far off
    assert np.var(z[:, 1] - z[:, 0]) > 2 * 4.04
    known = nv.estimate(
        z[:, 1], method="somd-redundant", reference=z[:, 0], reference_variance=0.04
    )
    assert known.variance == pytest.approx(4.0, rel=0.05)
    assert known.params["reference_variance"] == 0.04
    paper = nv.estimate(z[:, 1], method="somd-redundant", reference=z[:, 0])
    assert paper.variance - known.variance == pytest.approx(0.04, rel=1e-9)
    assert paper.ci95[0] < paper.variance < paper.ci95[1]
    pair = np.mean((np.diff(z[:, 0]) - np.diff(z[:, 1])) ** 2) / 2.0
    assert paper.variance == pytest.approx(pair, rel=1e-12)
    assert paper.n_used == z.shape[0] - 1


def test_estimate_redundant_with_two_sensors_gives_the_sum():
    z = _sensors(8, 20_000, [1.0, 3.0])
    est = nv.estimate_redundant(z)
    assert est.variances == pytest.approx([4.0, 4.0], rel=0.05)
    assert est.pair_sums[0, 1] == est.pair_sums[1, 0] == est.variances[0]
    assert any("only the sum" in note for note in est.notes)


@pytest.mark.parametrize("seed", [9, 10])
def test_three_sensors_give_each_sensors_variance(seed):
    truth = np.array([1.0, 2.0, 4.0])
    z = _sensors(seed, 50_000, truth)
    est = nv.estimate_redundant(z)
    assert est.variances.shape == (3,)
    # relative sd of the three-cornered hat here: 2.2 %, 1.3 %, 0.9 %
    for got, want, rtol in zip(est.variances, truth, (0.09, 0.055, 0.04), strict=True):
        assert got == pytest.approx(want, rel=rtol)
    assert np.all(est.ci95[:, 0] <= est.variances) and np.all(est.variances <= est.ci95[:, 1])
    np.testing.assert_allclose(est.pair_sums, est.pair_sums.T)
    assert est.pair_sums[0, 2] == pytest.approx(5.0, rel=0.03)
    assert est.n_used == 50_000
    d = est.to_dict()
    assert json.loads(json.dumps(d))["variances"] == pytest.approx(est.variances.tolist())


def test_four_sensors_least_squares():
    truth = np.array([0.5, 1.0, 2.0, 3.0])
    est = nv.estimate_redundant(_sensors(11, 50_000, truth))
    np.testing.assert_allclose(est.variances, truth, rtol=0.08)


def test_a_noiseless_sensor_gets_a_variance_near_zero_never_negative():
    est = nv.estimate_redundant(_sensors(12, 5000, [0.0, 1.0, 1.0]))
    assert 0.0 <= est.variances[0] < 0.05
    np.testing.assert_allclose(est.variances[1:], 1.0, rtol=0.1)


def test_redundant_bad_input():
    with pytest.raises(NoisevarError, match="two or more sensors"):
        nv.estimate_redundant(np.zeros((100, 1)))
    with pytest.raises(NoisevarError, match="two or more sensors"):
        nv.estimate_redundant(np.zeros(100))
    z = _sensors(13, 200, [1.0, 1.0])
    z[5, 1] = np.nan
    with pytest.raises(NoisevarError, match="NaN or Inf"):
        nv.estimate_redundant(z)
    with pytest.raises(NoisevarError, match="needs a second sensor"):
        nv.estimate(z[:, 0], method="somd-redundant")
    with pytest.raises(NoisevarError, match="same length"):
        nv.estimate(z[:, 0], method="somd-redundant", reference=z[:100, 0])


# ------------------------------------------------------------------------- the result
@pytest.mark.parametrize("method", [m for m in nv.methods() if m != "somd-redundant"])
def test_result_carries_what_the_dashboard_needs(method):
    n = 3000 if method.startswith("mle") else N
    g = nv.generate("random-jerk", n=n, seed=14)
    est = nv.estimate(g.measured, method=method)
    assert isinstance(est, nv.VarianceEstimate)
    assert est.method == method
    assert est.params["method"] == method
    assert est.variance > 0
    assert est.std == pytest.approx(np.sqrt(est.variance))
    lo, hi = est.ci95
    assert 0 < lo < est.variance < hi
    assert 0 < est.n_used <= est.n_total == n
    assert est.dof > 0
    d = est.to_dict()
    assert {"variance", "std", "ci95_low", "ci95_high", "method", "n_used", "params"} <= set(d)
    assert json.loads(json.dumps(d))["variance"] == pytest.approx(est.variance)
    if method.startswith("somd"):
        assert est.details is not None
        assert est.details.smooth_output.shape[-1] == n


def test_ci95_is_about_right_for_white_noise():
    """Coverage of the 95 % interval over 200 seeded white-noise records."""
    rng = np.random.default_rng(15)
    runs = rng.normal(0.0, 1.0, (200, 2000))
    for method in ("diff2", "auto"):
        cis = np.array([nv.estimate(z, method=method).ci95 for z in runs])
        cover = np.mean((cis[:, 0] < 1.0) & (1.0 < cis[:, 1]))
        assert 0.88 <= cover <= 0.995, (method, cover)


@pytest.mark.parametrize("method", ["auto", "somd", "somd-paper", "wavelet-mad", "rice"])
def test_params_round_trip(method):
    """result.params is the config form: estimate(z, **params) gives the same estimate."""
    z = nv.generate("fast-slow", n=N, seed=16).measured
    est = nv.estimate(z, method=method)
    params = json.loads(json.dumps(est.params))
    assert set(params) - {"method"} <= set(METHODS[method].param_specs)
    again = nv.estimate(z, **params)
    assert again.variance == est.variance
    assert again.params == est.params


def test_auto_reports_the_span_it_chose_in_a_note():
    z = nv.generate("fast-slow", n=N, seed=17).measured
    est = nv.estimate(z)
    assert est.params["span"] is None
    assert any("mean" in note and "span" in note for note in est.notes)
    fixed = nv.estimate(z, span=21)
    assert fixed.params["span"] == 21
    assert fixed.variance != est.variance


# ------------------------------------------------------------------------- bad input
RNG = np.random.default_rng(18)
WHITE = RNG.normal(0.0, 1.0, 3000)


@pytest.mark.parametrize(
    ("z", "params", "phrase"),
    [
        ([], {}, "the signal is empty"),
        (np.array([]), {"method": "rice"}, "the signal is empty"),
        (["a", "b", "c"], {}, "not numeric"),
        ([1.0, None, 2.0], {}, "non-finite"),
        ({"a": 1}, {}, "not numeric"),
        (RNG.normal(size=(100, 3)), {}, "channel (0,): the signal has only 3 samples"),
        (RNG.normal(size=(2, 3, 4)), {}, "channel (0, 0): the signal has only 4"),
        (WHITE[:5], {}, "only 5 samples"),
        (np.full(500, 3.0), {}, "variance is 0"),
        (np.full(500, 3.0), {"method": "somd"}, "constant"),
        (WHITE[:800], {"method": "somd", "window": 1000}, "too few samples for the window"),
        (WHITE[:500], {"method": "somd"}, "too few samples"),
        (WHITE[:9], {"method": "auto"}, "too few samples (9) for the auto estimator"),
        (WHITE, {"method": "somd", "h_smooth": 0}, "h_smooth=0 is outside the stable range"),
        (WHITE, {"method": "somd", "h_smooth": -1e-5}, "outside the stable range"),
        (WHITE, {"method": "somd", "h_smooth": 0.5}, "outside the stable range"),
        (WHITE, {"method": "somd", "h_smooth": float("nan")}, "h_smooth must be finite"),
        (WHITE, {"method": "somd", "h_smooth": []}, "h_smooth must not be empty"),
        (WHITE, {"method": "somd", "h_smooth": "x"}, "h_smooth must be a number"),
        (WHITE, {"method": "somd", "h_track": 1.0}, "h_track=1 is outside the stable range"),
        (WHITE, {"method": "somd", "track_ratio": 0.5}, "track_ratio=0.5 is out of range"),
        (WHITE, {"method": "somd", "window": 3}, "window must be an integer of at least 8"),
        (WHITE, {"method": "somd", "window": 40.5}, "window must be an integer"),
        (WHITE, {"method": "somd", "window": "forty"}, "window must be a number"),
        (WHITE, {"method": "somd", "gamma_amp": 0}, "gamma_amp=0 is out of range"),
        (WHITE, {"method": "somd", "gamma_amp": 1.5}, "gamma_amp=1.5 is out of range"),
        (WHITE, {"method": "somd", "gamma_ang": 0}, "gamma_ang=0 is out of range"),
        (
            WHITE,
            {"method": "somd", "gamma_ang": 91},
            "gamma_ang=91 is out of range: it must be in (0, 90]",
        ),
        (WHITE, {"method": "somd", "gamma_amp": "wide"}, "gamma_amp must be a number"),
        (
            WHITE,
            {"method": "somd", "angle": "radians"},
            "angle must be a string: one of scaled, paper",
        ),
        (WHITE, {"method": "somd", "gamma_amp": 1e-4}, "no window kept"),
        (WHITE, {"method": "auto", "order": 9}, "order=9 is out of range: it must be in [1, 6]"),
        (WHITE, {"method": "auto", "span": 20}, "span must be odd"),
        (WHITE, {"method": "auto", "trim": 0.5}, "trim=0.5 is out of range"),
        (WHITE, {"method": "wavelet-mad", "wavelet": "nope"}, "unknown wavelet"),
        (WHITE, {"method": "kalman"}, "unknown method 'kalman'; choose one of: auto"),
        (
            WHITE,
            {"h_smoth": 1e-5},
            "'auto' does not take parameter(s) h_smoth; its parameters: span",
        ),
    ],
)
def test_bad_input_raises_one_clear_error(z, params, phrase):
    with pytest.raises(NoisevarError) as info:
        nv.estimate(z, **params)
    msg = str(info.value)
    assert phrase in msg
    assert "\n" not in msg


def test_nan_and_inf_are_refused_naming_the_first_index():
    z = WHITE.copy()
    z[[17, 40]] = np.nan
    z[900] = np.inf
    with pytest.raises(NoisevarError) as info:
        nv.estimate(z)
    msg = str(info.value)
    assert "3 non-finite values" in msg
    assert "first at sample 17" in msg
    assert "drop_nonfinite=True" in msg and "--drop-nonfinite" in msg
    z[17] = -np.inf
    with pytest.raises(NoisevarError, match="first at sample 17"):
        nv.estimate(z, method="rice")


def test_drop_nonfinite_drops_and_says_how_many():
    """Dropped samples are gaps: the record is estimated per segment and pooled, not spliced."""
    z = WHITE.copy()
    z[[17, 40, 900]] = [np.nan, np.inf, np.nan]
    est = nv.estimate(z, drop_nonfinite=True)
    assert est.n_total == WHITE.size - 3
    assert any("dropped 3 non-finite samples" in note for note in est.notes)
    assert any("uniform segments" in note for note in est.notes)
    assert [g.index for g in est.diagnostics.gaps] == [17, 39, 898]
    clean = nv.estimate(np.delete(WHITE, [17, 40, 900]))
    assert est.variance == pytest.approx(clean.variance, rel=0.02)
    assert est.variance != clean.variance  # not spliced
    rice = nv.estimate(z, method="rice", drop_nonfinite=True)
    assert rice.variance == pytest.approx(
        nv.estimate(np.delete(WHITE, [17, 40, 900]), method="rice").variance, rel=0.02
    )


def test_column_vectors_are_accepted():
    assert nv.estimate(WHITE[:, None]).variance == nv.estimate(WHITE).variance
    assert nv.estimate(WHITE[None, :]).variance == nv.estimate(WHITE).variance
    assert nv.estimate(list(WHITE)).variance == nv.estimate(WHITE).variance


def test_parameters_a_method_does_not_take_are_refused():
    with pytest.raises(NoisevarError, match="'rice' does not take parameter.*h_smooth, window"):
        nv.estimate(WHITE, method="rice", h_smooth=1e-4, window=80)


# ---------------------------------------------------- auto: fast internals = naive forms
@pytest.mark.parametrize("n, block", [(1000, 256), (1100, 256), (300, 16), (16, 16)])
def test_above_local_uses_the_higher_of_the_two_bracketing_levels(n, block):
    from noisevar.estimators.auto._trim import _above_local

    rng = np.random.default_rng(n)
    nb = max(1, n // block)
    local = rng.uniform(0.5, 4.0, nb)
    x = rng.uniform(0.0, 5.0, n)
    # per-sample reference: the levels of the block centres on either side of each sample
    centres = (np.arange(nb) + 0.5) * block
    k = np.arange(n)
    right = np.clip(np.searchsorted(centres, k, side="right"), 0, nb - 1)
    left = np.clip(right - 1, 0, nb - 1)
    level = np.maximum(local[left], local[right])
    level[k >= centres[-1]] = local[-1]
    np.testing.assert_array_equal(_above_local(x, local, block), x > level)


def test_a_spike_is_noise_and_a_jump_is_signal():
    """A spike stays in the variance (outliers are noise) and leaves the core; a jump leaves both.

    Near a jump only the samples a residual reaches are lost, and once a jump is
    flagged its size changes nothing.
    """
    n = 3000
    rng = np.random.default_rng(3)
    smooth = 20.0 * np.sin(np.arange(n) / 300.0)
    noisy = smooth + rng.standard_normal(n)
    base = nv.estimate(noisy)
    for size in (60.0, 1e3):
        z = noisy.copy()
        z[1500] += size
        est = nv.estimate(z)
        assert est.n_used == n
        # the spike's square, spread over its residuals, adds size² / n
        assert est.variance == pytest.approx(base.variance + size**2 / n, rel=0.05)
        assert est.core_variance == pytest.approx(1.0, rel=0.05)
        assert est.outlier_fraction == pytest.approx(1 / n)
    sizes = []
    for size in (60.0, 1e3, 1e6):
        z = noisy.copy()
        z[1500:] += size
        est = nv.estimate(z)
        assert 0 < n - est.n_used <= 45
        assert est.variance == pytest.approx(1.0, rel=0.05)
        assert est.outlier_fraction == 0.0
        sizes.append(est.variance)
    assert sizes[2] == pytest.approx(sizes[1], rel=1e-9)


def test_auto_does_not_trim_genuine_noise_after_a_noise_step():
    """A x3 step of the noise level is not an outlier: no record of 40 loses a sample.

    With a threshold interpolated between block centres, the louder samples just
    after the step were held to about 3.5 of their standard deviations and about
    one record in ten lost residuals to trimming (a negative bias).
    """
    trimmed = 0
    for seed in range(40):
        g = nv.generate("noise-step", n=6000, seed=seed)
        r = nv.estimate(g.measured)
        trimmed += r.n_used < r.n_total
    assert trimmed == 0


# ------------------------------------------------- auto's compiled residual filters
@pytest.mark.parametrize("span", [11, 21, 41, 81])
def test_compiled_residual_squares_equal_convolve(span, monkeypatch):
    """The numba kernel of noisevar.numeric.fir is np.convolve's filter, to rounding."""
    import noisevar.estimators.auto.core as est
    from noisevar.numeric import fir

    assert fir.USE_COMPILED, "numba is a core dependency: the compiled path must be on"
    rng = np.random.default_rng(21)
    # a large offset, a fast component and a tile boundary that falls mid-record
    z = 5e5 + np.cumsum(rng.normal(0, 1, 5000)) + 3 * np.sin(np.arange(5000) / 4.0)
    z += rng.normal(0, 0.7, z.size)
    fast = est._residual_squares(z, span, 3)
    monkeypatch.setattr(fir, "USE_COMPILED", False)
    ref = est._residual_squares(z, span, 3)
    assert np.max(np.abs(fast - ref)) < 1e-9 * np.mean(ref)
    # and it really is the residual: a cubic leaves nothing
    t = np.arange(3000.0)
    cubic = 2.0 + 0.3 * t - 1e-3 * t**2 + 1e-7 * t**3
    monkeypatch.setattr(fir, "USE_COMPILED", True)
    assert np.max(est._residual_squares(cubic, span, 3)) < 1e-12 * np.max(cubic) ** 2


@pytest.mark.parametrize("family", ["gps-circle", "steps-ramps", "noise-ramp"])
def test_auto_compiled_equals_numpy_path(family, monkeypatch):
    from noisevar.numeric import fir

    z = nv.generate(family, n=6000, seed=5).measured
    fast = nv.estimate(z, method="auto")
    monkeypatch.setattr(fir, "USE_COMPILED", False)
    ref = nv.estimate(z, method="auto")
    assert fast.variance == pytest.approx(ref.variance, rel=1e-12)
    assert fast.n_used == ref.n_used


def test_auto_long_span_stays_out_of_blocks_next_to_a_fast_burst():
    """Span 81 reaches 40 samples into the neighbouring blocks; next to fast-slow's burst
    (period 60) it would leak into the first samples of the block after it.

    Paired over 20 noise draws: the estimate on clean + noise over the estimate on the
    noise alone stays below the leak the rule prevents.
    """
    g = nv.generate("fast-slow", n=1000, seed=0)
    leak = []
    for s in range(20):
        noise = np.random.default_rng(s).normal(0.0, 5.0, 1000)
        with_signal = nv.estimate(g.clean + noise, method="auto").variance
        leak.append(with_signal / nv.estimate(noise, method="auto").variance - 1.0)
    assert np.mean(leak) < 0.009


@pytest.mark.parametrize("seed", range(20))
def test_local_peaks_equal_the_maximum_filter(seed):
    from scipy.ndimage import maximum_filter1d

    from noisevar.estimators.auto._trim import _local_peaks

    rng = np.random.default_rng(seed)
    n = int(rng.integers(12, 3000))
    x = rng.standard_t(2, n) ** 2
    if seed % 2:
        x = np.round(x)  # ties: equal neighbours are peaks too
    for size in (5, 11, 21):
        for k in (3, n // 2):  # few (the windows read) and many (the filter)
            idx = np.sort(rng.choice(n, size=k, replace=False))
            expected = idx[(x == maximum_filter1d(x, size))[idx]]
            np.testing.assert_array_equal(_local_peaks(x, idx, size), expected)
