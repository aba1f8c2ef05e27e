"""Invariances of every estimator, checked with hypothesis (derandomised: seeded, repeatable).

- multiplying the signal by s multiplies every variance by s² (rel 1e-6);
- adding a constant changes nothing (rel 1e-6);
- reversing time changes the estimate little (tolerances stated per method).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import noisevar as nv

N = 3000
FAMILIES = nv.signal_names()
SETTINGS = settings(
    max_examples=12,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)

#: Every method except the (slow) statsmodels MLE, with the parameters that
#: make it scale-free: somd-paper's literal angle is in raw units by design
#: (docs/algorithms.md §A5), so it is checked with the scaled angle and without selection.
CASES = {
    "auto": {},
    "auto-span21": {"method": "auto", "span": 21},
    "somd": {},
    "somd-multi-h": {"method": "somd", "h_smooth": [1e-5, 4e-5, 1e-4]},
    "somd-paper-scaled": {"method": "somd-paper", "angle": "scaled"},
    "somd-paper-noselect": {"method": "somd-paper", "select": False},
    "rice": {},
    "diff2": {},
    "hkt1": {},
    "hkt2": {},
    "hkt3": {},
    "mad-diff": {},
    "wavelet-mad": {},
}


def _params(case):
    p = dict(CASES[case])
    p.setdefault("method", case)
    return p


def _signal(family, seed):
    return nv.generate(family, n=N, seed=seed).measured


seeds = st.integers(min_value=0, max_value=2**31 - 1)
families = st.sampled_from(FAMILIES)
scales = st.one_of(
    st.floats(min_value=1e-4, max_value=1e4, allow_nan=False, allow_infinity=False),
    st.floats(min_value=-1e4, max_value=-1e-4, allow_nan=False, allow_infinity=False),
)
offsets = st.floats(min_value=-1e4, max_value=1e4, allow_nan=False, allow_infinity=False)


#: somd-paper's selection uses the printed chain |A1/A2|, |A2/A3|, |A3/A4| [19]:
#: a sign flip swaps above/below (A1 <-> -A2, A3 <-> -A4) and changes the middle
#: ratio, so for it only s > 0 is claimed. somd's symmetric test closes the chain
#: (A4/A1 too) and is claimed for every s (see the next test).
SIGN_SENSITIVE = ("somd-paper-scaled",)


@pytest.mark.parametrize("case", list(CASES))
@SETTINGS
@given(family=families, seed=seeds, s=scales)
def test_scaling_multiplies_the_variance_by_s_squared(case, family, seed, s):
    if case in SIGN_SENSITIVE:
        s = abs(s)
    z = _signal(family, seed)
    params = _params(case)
    base = nv.estimate(z, **params)
    scaled = nv.estimate(s * z, **params)
    assert scaled.variance == pytest.approx(s**2 * base.variance, rel=1e-6)
    assert scaled.ci95[0] == pytest.approx(s**2 * base.ci95[0], rel=1e-6)
    assert scaled.n_used == base.n_used


def test_sign_flip_and_window_selection():
    """somd keeps the same windows for -z; the printed chain of [19] does not."""
    z = _signal("fast-slow", 0)
    flat = nv.estimate(z, method="somd", select=False).variance
    assert nv.estimate(-z, method="somd", select=False).variance == pytest.approx(flat, rel=1e-9)
    sel = nv.estimate(z, method="somd")
    flipped = nv.estimate(-z, method="somd")
    a = sel.details.selection.amplitudes
    b = flipped.details.selection.amplitudes
    # above and below swap: A1 <-> -A2, A3 <-> -A4 (to rounding)
    np.testing.assert_allclose(b[:, [1, 0, 3, 2]], -a, rtol=1e-6, atol=1e-9)
    np.testing.assert_array_equal(flipped.details.selection.ang_ok, sel.details.selection.ang_ok)
    np.testing.assert_array_equal(flipped.details.kept_windows, sel.details.kept_windows)
    assert flipped.variance == pytest.approx(sel.variance, rel=1e-9)
    # the printed test compares A1 with A4 after the flip: it keeps other windows
    paper = nv.estimate(z, method="somd-paper")
    paper_flipped = nv.estimate(-z, method="somd-paper")
    assert not np.array_equal(paper.details.kept_windows, paper_flipped.details.kept_windows)


@pytest.mark.parametrize("case", list(CASES))
@SETTINGS
@given(family=families, seed=seeds, c=offsets)
def test_adding_a_constant_changes_nothing(case, family, seed, c):
    z = _signal(family, seed)
    params = _params(case)
    base = nv.estimate(z, **params)
    shifted = nv.estimate(z + c, **params)
    assert shifted.variance == pytest.approx(base.variance, rel=1e-6)
    assert shifted.n_used == base.n_used


@SETTINGS
@given(seed=seeds, s=scales, c=offsets)
def test_redundant_somd_scales_and_ignores_offsets(seed, s, c):
    rng = np.random.default_rng(seed)
    t = np.arange(N) / N
    shared = 100.0 * np.sin(2 * np.pi * 2 * t)
    ref = shared + 0.3 * np.sin(2 * np.pi * t) + rng.normal(0.0, 0.2, N)
    z = shared - 0.5 * t + rng.normal(0.0, 2.0, N)
    base = nv.estimate(z, method="somd-redundant", reference=ref, reference_variance=0.04)
    moved = nv.estimate(
        s * z + c, method="somd-redundant", reference=s * ref - c, reference_variance=0.04 * s**2
    )
    assert moved.variance == pytest.approx(s**2 * base.variance, rel=1e-6)
    three = np.column_stack([ref, z, shared + rng.normal(0.0, 1.0, N)])
    v3 = nv.estimate_redundant(three).variances
    np.testing.assert_allclose(nv.estimate_redundant(s * three + c).variances, s**2 * v3, rtol=1e-6)


# ------------------------------------------------------------------------ time reversal
#: Symmetric difference sequences see the same squares backwards: exact.
EXACT_UNDER_REVERSAL = ("rice", "diff2", "hkt1", "mad-diff")
#: Measured maximum |reversed/forward - 1| over 150 records (6 families x 25
#: seeds, n=3000) in brackets; tolerances are about twice that.
REVERSAL_TOLERANCE = {
    "hkt2": 0.015,  # asymmetric sequence, same information (0.005)
    "hkt3": 0.015,  # (0.006)
    "auto": 0.08,  # symmetric sequence; blocks and trimming start at the other end (0.041)
    "wavelet-mad": 0.3,  # db4 is asymmetric; a median of n/2 coefficients (0.15)
}


@pytest.mark.parametrize("method", EXACT_UNDER_REVERSAL)
@SETTINGS
@given(family=families, seed=seeds)
def test_reversal_is_exact_for_symmetric_differences(method, family, seed):
    z = _signal(family, seed)
    forward = nv.estimate(z, method=method).variance
    assert nv.estimate(z[::-1], method=method).variance == pytest.approx(forward, rel=1e-12)


@pytest.mark.parametrize("method", list(REVERSAL_TOLERANCE))
@SETTINGS
@given(family=families, seed=seeds)
def test_reversal_changes_little(method, family, seed):
    z = _signal(family, seed)
    forward = nv.estimate(z, method=method).variance
    backward = nv.estimate(z[::-1], method=method).variance
    assert backward == pytest.approx(forward, rel=REVERSAL_TOLERANCE[method])


@pytest.mark.parametrize("method", ["somd", "somd-paper"])
@SETTINGS
@given(family=st.sampled_from(["fast-slow", "gps-circle", "random-jerk"]), seed=seeds)
def test_reversal_changes_somd_moderately_on_stationary_noise(method, family, seed):
    """SOMD's filter is causal: backwards, other windows pass and other samples settle.

    Measured max 15 % (n=3000, 25 seeds) on these stationary-noise families;
    with a noise level that changes along the record the settling skip drops
    a quieter or a noisier stretch and the two directions differ by up to 60 %,
    so those families are left out here.
    """
    z = _signal(family, seed)
    forward = nv.estimate(z, method=method).variance
    backward = nv.estimate(z[::-1], method=method).variance
    assert backward == pytest.approx(forward, rel=0.3)


def test_mle_invariances_once():
    """statsmodels ML normalises its input: invariant up to the optimiser's tolerance."""
    z = nv.generate("random-jerk", n=1500, seed=3).measured
    base = nv.estimate(z, method="mle-trend").variance
    moved = nv.estimate(37.0 * z + 1234.5, method="mle-trend").variance
    assert moved == pytest.approx(37.0**2 * base, rel=1e-3)
    assert nv.estimate(z[::-1], method="mle-trend").variance == pytest.approx(base, rel=0.05)
