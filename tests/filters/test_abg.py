"""Alpha-beta-gamma filter (docs/algorithms.md §A2, §A8): gains, lfilter, streaming, c(h)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.filters.abg import (
    N_INIT,
    ABGStream,
    abg_filter,
    abg_filter_loop,
    abg_gains,
    abg_transfer_function,
    check_h,
    noise_ratio,
    settling_samples,
    somd_bias_factor,
    stable_h_limit,
    steady_state_zi,
)

OUTPUTS = ("predicted", "filtered")
PAPER_HS = (1e-7, 1.5e-5, 1e-4, 9e-4)  # the paper's smoothing values (docs/algorithms.md §A9)
FAST_HS = (9e-4, 3e-3, 0.03, 0.3)  # well-conditioned third-order direct form


def _test_signal(n=3000, seed=0):
    """A random walk plus white noise: slow and fast content, no special structure."""
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(0.0, 1.0, n)) + rng.normal(0.0, 5.0, n) + 40.0


def _rel_err(y, ref):
    return float(np.max(np.abs(y - ref)) / np.max(np.abs(ref)))


def _line_state(z):
    """State x[-1] of a filter in steady state on the least-squares line of z[:N_INIT].

    On a line the type-3 filter has zero error, so its state is exactly
    [position at sample -1, change per sample, 0].
    """
    i = np.arange(N_INIT, dtype=float)
    slope, intercept = np.polyfit(i, z[:N_INIT], 1)
    return np.array([intercept - slope, slope, 0.0])


def _zi_from_state(h, output, x0):
    """lfilter zi equivalent to a state-space state x0, derived from the loop alone.

    The zero-input responses of both forms are determined by their first three
    samples (third-order system); match them by linearity.
    """
    b, a = abg_transfer_function(h, output)
    zeros = np.zeros(3)
    m = np.column_stack([signal.lfilter(b, a, zeros, zi=e)[0] for e in np.eye(3)])
    y_loop = abg_filter_loop(zeros, h, x0, output=output)
    return np.linalg.solve(m, y_loop)


# ----------------------------------------------------------------------- gains, eq. 12
@pytest.mark.parametrize("h", [1e-9, 1e-7, 1.5e-5, 1e-4, 9e-4, 0.1, 0.3])
def test_gains_are_eq_12(h):
    alpha, beta, gamma = abg_gains(h)
    assert alpha == pytest.approx(2.0 * h ** (1.0 / 3.0), rel=1e-14)
    assert beta == pytest.approx(2.0 * h ** (2.0 / 3.0), rel=1e-14)
    assert gamma == h
    # and the identity that ties them: beta = alpha^2 / 2, gamma = alpha^3 / 8
    assert beta == pytest.approx(alpha**2 / 2.0, rel=1e-12)
    assert gamma == pytest.approx(alpha**3 / 8.0, rel=1e-12)


def test_gains_known_values():
    assert abg_gains(1e-6) == pytest.approx((0.02, 2e-4, 1e-6), rel=1e-12)
    assert abg_gains(0.125) == pytest.approx((1.0, 0.5, 0.125), rel=1e-12)


@pytest.mark.parametrize("h", [1e-7, 1.5e-5, 9e-4, 0.2])
@pytest.mark.parametrize("output", OUTPUTS)
def test_transfer_function_has_unit_dc_gain(h, output):
    """A type-3 loop follows a constant: DC gain exactly 1."""
    b, a = abg_transfer_function(h, output)
    assert len(a) == 4
    assert np.sum(b) / np.sum(a) == pytest.approx(1.0, rel=1e-6)


# ------------------------------------------------------ lfilter form = explicit recursion
@pytest.mark.parametrize("h", FAST_HS)
@pytest.mark.parametrize("output", OUTPUTS)
def test_lfilter_equals_loop_from_zero_state(h, output):
    z = _test_signal(seed=11)
    y = abg_filter(z, h, zi=np.zeros(3), output=output)
    ref = abg_filter_loop(z, h, np.zeros(3), output=output)
    assert _rel_err(y, ref) < 1e-12


@pytest.mark.parametrize("h", FAST_HS)
@pytest.mark.parametrize("output", OUTPUTS)
def test_lfilter_equals_loop_from_steady_state_on_a_line(h, output):
    """Default zi (steady_state_zi) is the state [b - a, a, 0] of the line fit."""
    z = _test_signal(seed=12)
    y = abg_filter(z, h, output=output)  # default: steady-state start
    ref = abg_filter_loop(z, h, _line_state(z), output=output)
    assert _rel_err(y, ref) < 1e-12


@pytest.mark.parametrize("h", FAST_HS)
@pytest.mark.parametrize("output", OUTPUTS)
def test_lfilter_equals_loop_from_arbitrary_state(h, output):
    z = _test_signal(seed=13)
    x0 = np.array([30.0, -2.0, 0.25])
    zi = _zi_from_state(h, output, x0)
    y = abg_filter(z, h, zi=zi, output=output)
    ref = abg_filter_loop(z, h, x0, output=output)
    assert _rel_err(y, ref) < 1e-12


@pytest.mark.parametrize("h", PAPER_HS)
@pytest.mark.parametrize("output", OUTPUTS)
def test_lfilter_equals_loop_at_paper_h(h, output):
    """At the paper's small h both starts still equal the recursion to about 1e-12.

    The three poles sit within about alpha/2 of z = 1, so the rounding of each
    step of a third-order recursion is amplified by up to ~1/h. Run as
    ``lfilter(b, a, z)`` (the direct form) the output agrees with the
    per-sample state recursion only to about 4e-9 (h=1e-7), 3e-11
    (h=1.5e-5), 1e-11 (h=1e-4) and 5e-13 (h=9e-4) relative. Both starts
    (the default steady state, and an explicit ``zi``) run the error filter
    ``κ (1 - z⁻¹)³ / A`` on the third difference instead
    (``noisevar.filters.abg._tracking_error``), whose rounding is relative to the
    third difference, not the signal: measured 1.6e-10, 1.1e-12 to 1.2e-12,
    1e-13 and 3e-14 on one machine, 1.8e-10, 6.7e-13, 2.6e-13 and 1.5e-14 on
    another (the last digits depend on the platform's rounding). The bounds
    are those with a margin; any wrong coefficient gives O(1) differences.
    (A cascade of second-order sections is no better: 1.3e-12 at 1.5e-5. The
    state recursion itself agrees with an 80-bit reference to 1e-15.)
    """
    bound = {1e-7: 6e-10, 1.5e-5: 2.5e-12, 1e-4: 1e-12, 9e-4: 1e-12}[h]
    z = _test_signal(seed=14)
    y0 = abg_filter(z, h, zi=np.zeros(3), output=output)
    assert _rel_err(y0, abg_filter_loop(z, h, np.zeros(3), output=output)) < bound
    y = abg_filter(z, h, output=output)
    assert _rel_err(y, abg_filter_loop(z, h, _line_state(z), output=output)) < bound


def test_default_start_equals_lfilter_with_steady_state_zi():
    """The error form is the same filter as lfilter(b, a) from the steady-state zi."""
    z = _test_signal(seed=21) + 1e3
    for h in (1e-3, 2e-2):
        for output in OUTPUTS:
            b, a = abg_transfer_function(h, output)
            ref, _ = signal.lfilter(b, a, z, zi=steady_state_zi(z, h, output=output))
            assert _rel_err(abg_filter(z, h, output=output), ref) < 1e-12


def test_predicted_output_does_not_use_the_current_sample():
    """The virtual sensor is H x(k|k-1): changing z[k] changes outputs only after k.

    (Up to rounding: the error form computes y = z - e, where z[k] cancels.)
    """
    z = _test_signal(seed=15, n=400)
    z2 = z.copy()
    z2[200] += 1e3
    zi = np.zeros(3)
    y, y2 = abg_filter(z, 1e-4, zi=zi), abg_filter(z2, 1e-4, zi=zi)
    np.testing.assert_allclose(y[:201], y2[:201], rtol=0, atol=1e-9)
    assert abs(y2[201] - y[201]) > 1.0
    f, f2 = (
        abg_filter(z, 1e-4, zi=zi, output="filtered"),
        abg_filter(z2, 1e-4, zi=zi, output="filtered"),
    )
    np.testing.assert_allclose(f[:200], f2[:200], rtol=0, atol=1e-9)
    assert f2[200] - f[200] == pytest.approx(1e3 * abg_gains(1e-4)[0], rel=1e-9)


def test_filter_runs_along_any_axis_of_stacked_records():
    rng = np.random.default_rng(16)
    zs = np.cumsum(rng.normal(size=(500, 3)), axis=0)
    y = abg_filter(zs, 1e-3, axis=0)
    assert y.shape == zs.shape
    for j in range(3):
        np.testing.assert_allclose(y[:, j], abg_filter(zs[:, j], 1e-3), rtol=1e-13, atol=1e-12)


# -------------------------------------------------------------------------- streaming
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("output", OUTPUTS)
def test_stream_equals_one_pass(seed, output):
    rng = np.random.default_rng(100 + seed)
    n = 2500
    z = _test_signal(n=n, seed=seed)
    h = float(rng.choice([1e-7, 1.5e-5, 1e-4, 9e-4, 0.05]))
    first = int(rng.integers(N_INIT, 200))
    cuts = np.sort(
        rng.choice(np.arange(first + 1, n), size=int(rng.integers(1, 30)), replace=False)
    )
    chunks = np.split(z, np.concatenate([[first], cuts]))
    stream = ABGStream(h=h, output=output)
    y = np.concatenate([stream.process(c) for c in chunks])
    ref = abg_filter(z, h, output=output)
    assert y.shape == ref.shape
    assert _rel_err(y, ref) < 1e-12


def test_stream_with_single_samples_and_empty_chunks():
    z = _test_signal(n=300, seed=17)
    stream = ABGStream(h=1e-4)
    parts = [stream.process(z[:N_INIT]), stream.process(np.array([]))]
    parts += [stream.process(z[k : k + 1]) for k in range(N_INIT, z.size)]
    assert parts[1].size == 0
    assert _rel_err(np.concatenate(parts), abg_filter(z, 1e-4)) < 1e-12


def test_stream_with_explicit_state_equals_one_pass_with_that_state():
    z = _test_signal(n=1000, seed=18)
    zi = steady_state_zi(z[:50], 1e-3, n_init=50)
    stream = ABGStream(h=1e-3, zi=zi)
    y = np.concatenate([stream.process(c) for c in np.array_split(z, 7)])
    assert _rel_err(y, abg_filter(z, 1e-3, zi=zi)) < 1e-12


# ------------------------------------------------------------- type-3: ramp and parabola
@pytest.mark.parametrize("h", PAPER_HS)
@pytest.mark.parametrize("output", OUTPUTS)
def test_ramp_is_followed_with_zero_error_from_the_start(h, output):
    """The steady-state start on a line makes a ramp exact from sample 0."""
    k = np.arange(3000, dtype=float)
    ramp = 12.0 + 0.7 * k
    y = abg_filter(ramp, h, output=output)
    assert np.max(np.abs(y - ramp)) < 1e-8 * np.max(np.abs(ramp))


@pytest.mark.parametrize("h", [1.5e-5, 1e-4, 9e-4])
@pytest.mark.parametrize("output", OUTPUTS)
def test_parabola_is_followed_with_zero_steady_state_error(h, output):
    k = np.arange(4 * settling_samples(h), dtype=float)
    par = 2.0 + 0.3 * k + 1e-3 * k**2
    # explicit recursion: after the start-up transient the error is exactly 0
    y_loop = abg_filter_loop(par, h, _line_state(par), output=output)
    err0 = np.max(np.abs(y_loop - par)[:50])
    assert err0 > 1e-3  # the line start is wrong for a parabola
    tail = np.abs(y_loop - par)[3 * settling_samples(h) :]
    assert np.max(tail) < 1e-6 * err0
    # lfilter form: the same, down to its rounding
    y = abg_filter(par, h, output=output)
    assert np.max(np.abs(y - par)[3 * settling_samples(h) :]) < 1e-8 * np.max(par)


def test_settling_samples_bounds_the_start_up_transient():
    for h in PAPER_HS:
        s = settling_samples(h)
        y = abg_filter_loop(np.zeros(3 * s), h, [100.0, 0.0, 0.0])
        assert np.max(np.abs(y[:10])) > 50.0
        assert np.max(np.abs(y[s:])) < 0.3  # impulse energy < 1e-6 -> amplitude ~1e-3
    assert settling_samples(1e-7) > settling_samples(1.5e-5) > settling_samples(9e-4)


# ---------------------------------------------------------------------------- stability
def test_stable_limit_is_about_0_392():
    limit = stable_h_limit()
    assert 0.35 < limit < 0.4
    assert limit == pytest.approx(0.3923, abs=1e-3)


def test_filter_just_below_limit_is_stable_and_at_0_4_unstable():
    limit = stable_h_limit()
    imp = np.zeros(4000)
    y = abg_filter_loop(imp, 0.98 * limit, [1.0, 0.0, 0.0])
    assert np.max(np.abs(y[-500:])) < 1e-6
    # the same recursion run by hand at h = 0.4 (check_h refuses it) diverges
    from noisevar.filters.abg import _F

    alpha, beta, gamma = abg_gains(0.4)
    k = np.array([alpha, beta, gamma])
    x = np.array([1.0, 0.0, 0.0])
    for _ in range(4000):
        xp = _F @ x
        x = xp - k * xp[0]
    assert np.max(np.abs(x)) > 1.0


@pytest.mark.parametrize(
    "bad", [0.0, -1e-5, float("nan"), float("inf"), 0.4, 1.0, "stable_h_limit"]
)
def test_unstable_or_invalid_h_is_refused(bad):
    h = stable_h_limit() if bad == "stable_h_limit" else bad
    with pytest.raises(NoisevarError, match="stable range"):
        check_h(h)
    with pytest.raises(NoisevarError, match="stable range"):
        abg_filter(np.arange(100.0), h)
    with pytest.raises(NoisevarError, match="stable range"):
        ABGStream(h=h)
    with pytest.raises(NoisevarError, match="stable range"):
        noise_ratio(h)
    with pytest.raises(NoisevarError, match="stable range"):
        somd_bias_factor(h)


def test_non_numeric_h_is_refused_with_the_parameter_name():
    with pytest.raises(NoisevarError, match="h_smooth must be a number"):
        check_h("fast", "h_smooth")
    assert check_h(1e-4) == 1e-4
    assert isinstance(check_h(np.float32(1e-4)), float)


def test_unknown_output_is_refused():
    with pytest.raises(NoisevarError, match="output must be one of"):
        abg_filter(np.arange(100.0), 1e-4, output="smoothed")


def test_empty_signal_is_refused_by_the_initial_state():
    with pytest.raises(NoisevarError, match="empty"):
        abg_filter(np.array([]), 1e-4)


# ------------------------------------------------------------------- noise ratio, c(h)
def test_noise_ratio_of_the_prediction_documented_values():
    """noise_ratio is documented for the one-step prediction (our default output)."""
    expected = {1e-7: 0.0882, 1.5e-5: 0.206, 1e-4: 0.2867, 9e-4: 0.4286}
    for h, r in expected.items():
        assert noise_ratio(h) == pytest.approx(r, rel=2e-3)


def test_noise_ratio_of_the_filtered_output_matches_the_spec():
    """Spec A2 quotes 0.088, 0.20, 0.28, 0.40: those are the filtered estimate's."""
    spec = {1e-7: 0.088, 1.5e-5: 0.20, 1e-4: 0.28, 9e-4: 0.40}
    for h, r in spec.items():
        imp = np.zeros(60_000)
        imp[0] = 1.0
        g = abg_filter(imp, h, zi=np.zeros(3), output="filtered")
        assert np.sqrt(np.sum(g**2)) == pytest.approx(r, rel=0.02)
        # the prediction is noisier than the update, and within 10 % of it
        assert 1.0 < noise_ratio(h) / np.sqrt(np.sum(g**2)) < 1.1


@pytest.mark.parametrize("h", [1.5e-5, 9e-4])
def test_noise_ratio_matches_simulated_white_noise(h):
    rng = np.random.default_rng(21)
    w = rng.normal(0.0, 3.0, 200_000)
    y = abg_filter(w, h)[settling_samples(h) :]
    assert np.std(y) / 3.0 == pytest.approx(noise_ratio(h), rel=0.03)


def test_bias_factor_documented_values():
    expected = {1e-7: 2.019, 1.5e-5: 2.104, 1e-4: 2.204, 9e-4: 2.473}
    for h, c in expected.items():
        assert somd_bias_factor(h) == pytest.approx(c, abs=1.5e-3)


@pytest.mark.parametrize("h", [1.5e-5, 9e-4])
def test_bias_factor_is_the_variance_of_the_mutual_difference(h):
    """c(h) = var(Δ(Z1 - Z2)) / sigma² for white noise, Z1 the prediction, Z2 the samples."""
    rng = np.random.default_rng(22)
    w = rng.normal(0.0, 2.0, 400_000)
    y = abg_filter(w, h)
    mutual = np.diff(y - w)[settling_samples(h) :]
    assert np.mean(mutual**2) / 4.0 == pytest.approx(somd_bias_factor(h), rel=0.01)
    # with the filtered estimate as virtual sensor c is below 2 (docstring: 1.90 at 1.5e-5)
    f = abg_filter(w, h, output="filtered")
    c_filtered = np.mean(np.diff(f - w)[settling_samples(h) :] ** 2) / 4.0
    assert c_filtered < 2.0


@pytest.mark.parametrize("h", [1.5e-5, 9e-4])
def test_c_h_removes_the_somd_bias_on_white_noise(h):
    """Mean over seeded runs: corrected SOMD within 1 %, the paper's biased by c/2 - 1."""
    rng = np.random.default_rng(23)
    sigma2 = 4.0
    runs = rng.normal(0.0, 2.0, (64, 6000))
    ours = [nv.estimate(z, method="somd", select=False, h_smooth=h).variance for z in runs]
    paper = [nv.estimate(z, method="somd-paper", select=False, h_smooth=h).variance for z in runs]
    assert np.mean(ours) / sigma2 == pytest.approx(1.0, abs=0.01)
    c = somd_bias_factor(h)
    assert np.mean(paper) / sigma2 == pytest.approx(c / 2.0, abs=0.012)
    assert np.mean(paper) / sigma2 - 1.0 > 0.04  # +5 % at 1.5e-5, +24 % at 9e-4
    # the two differ by exactly the factor c/2 on the same data
    assert paper[0] / ours[0] == pytest.approx(c / 2.0, rel=1e-12)


@pytest.mark.parametrize("h", [1e-7, 1.5e-5, 9e-4])
def test_a_large_offset_costs_no_precision(h):
    """A UTM-sized offset must not swamp the recursion (poles near 1 at small h).

    The error filter runs on the third difference of z - z[0], so the output
    for z + c is the output for z plus c up to the rounding of c itself (4e6
    has an ulp of 5e-10: measured 8e-8 at h = 1e-7); run naively, lfilter's
    rounding would be relative to 4e6 (about 2e-2 absolute at h = 1e-7).
    """
    rng = np.random.default_rng(3)
    z = 300 * np.cos(np.pi / 200 * np.arange(6000)) + rng.normal(0, 5, 6000)
    offset = 4e6
    diff = abg_filter(z + offset, h) - offset - abg_filter(z, h)
    assert np.max(np.abs(diff)) < 1e-6  # naive lfilter on z + 4e6: ~1e-2
