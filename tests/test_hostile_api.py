"""The Python API under hostile input (issue 15): every finite record gives a finite,
non-negative variance inside a finite interval, or one NoisevarError; answers scale."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.estimators import _scale

METHODS = [m for m in nv.methods() if m != "somd-redundant"]
#: Methods whose optimiser path may move with the input's rounding (statsmodels ML).
LOOSE = {"mle-level": 1e-5, "mle-trend": 1e-5}

finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
#: Whole finite range: raw doubles, and a smooth-plus-noise record at any magnitude.
records = st.one_of(
    arrays(np.float64, st.integers(100, 240), elements=finite),
    st.builds(
        lambda e, seed, n: (
            (
                np.cumsum(np.random.default_rng(seed).normal(0, 0.05, n))
                + np.random.default_rng(seed + 1).normal(0, 1, n)
            )
            * 2.0**e
        ),
        st.integers(-1070, 1020),
        st.integers(0, 2**16),
        st.integers(100, 240),
    ),
    st.builds(
        lambda v, k, n: np.resize(np.array([v, v, v, -v][:k] or [v]), n),
        finite,
        st.integers(1, 4),
        st.integers(100, 240),
    ),
)


def _check(result) -> None:
    v = result.variance
    lo, hi = result.ci95
    assert math.isfinite(v) and v >= 0
    assert math.isfinite(lo) and math.isfinite(hi)
    assert lo <= v <= hi


@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=12, suppress_health_check=[HealthCheck.too_slow])
@given(z=records)
def test_any_finite_record_gives_a_finite_answer_or_one_clear_error(method, z):
    try:
        result = nv.estimate(z, method=method)
    except NoisevarError as exc:
        assert str(exc) and "\n" not in str(exc)
        return
    _check(result)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("scale", [1e-150, 1e-100, 1e-40, 1e40, 1e100, 1e150])
def test_scale_equivariance(method, scale):
    rng = np.random.default_rng(3)
    z = np.cumsum(rng.normal(0, 0.05, 2000)) + np.sin(np.arange(2000) / 80) * 5
    z = z + rng.normal(0, 1, 2000)
    ref = nv.estimate(z, method=method)
    got = nv.estimate(z * scale, method=method)
    rel = LOOSE.get(method, 1e-9)
    assert got.variance / scale**2 == pytest.approx(ref.variance, rel=rel)
    assert got.ci95[0] / scale**2 == pytest.approx(ref.ci95[0], rel=rel)
    assert got.ci95[1] / scale**2 == pytest.approx(ref.ci95[1], rel=rel)


def test_ordinary_records_are_not_scaled_so_answers_are_bit_identical():
    z = np.random.default_rng(0).normal(0, 1, 1000)
    assert _scale.scale_exponent(z) == 0
    assert _scale.scale_exponent(z * 1e25) == 0
    assert _scale.scale_exponent(z * 1e40) != 0
    assert _scale.scale_exponent(z * 1e-40) != 0


def test_power_of_two_scaling_is_exact_so_results_scale_exactly():
    z = np.random.default_rng(1).normal(0, 1, 1000) * 2.0**200
    r = nv.estimate(z, method="rice")
    r0 = nv.estimate(z / 2.0**200, method="rice")
    assert r.variance == r0.variance * 2.0**400
    assert any("scaled by 2^" in n for n in r.notes)


@pytest.mark.parametrize("scale", [1e-300, 1e300])
def test_unrepresentable_noise_variance_is_one_clear_error(scale):
    z = np.random.default_rng(2).normal(0, 1, 500) * scale
    with pytest.raises(NoisevarError, match="floating-point number"):
        nv.estimate(z, method="rice")


def test_quantised_record_mad_diff_is_an_error_not_zero():
    with pytest.raises(NoisevarError, match="quantised"):
        nv.estimate([0.0] * 1999 + [1.0], method="mad-diff")


@pytest.mark.parametrize("method", ["mle-level", "mle-trend"])
def test_mle_degenerate_fit_is_an_error(method):
    with pytest.raises(NoisevarError):
        nv.estimate([0.0] * 1999 + [1.0], method=method)


@pytest.mark.parametrize(
    ("z", "phrase"),
    [
        (np.arange(200) + 1j, "complex"),
        ([complex(i, 1) for i in range(200)], "complex"),
        (np.arange(200).astype("datetime64[s]"), "dates"),
        (np.arange(200).astype("timedelta64[ms]"), "dates"),
        (pd.Series(pd.date_range("2024", periods=200, freq="s")), "dates"),
        (pd.Series(pd.date_range("2024", periods=200, freq="s", tz="UTC")), "dates"),
        (pd.to_timedelta(np.arange(200), unit="s"), "dates"),
        (list(pd.date_range("2024", periods=200, freq="s")), "not numeric"),
    ],
)
def test_wrong_types_are_refused(z, phrase):
    with pytest.raises(NoisevarError, match=phrase):
        nv.estimate(z, method="rice")


def test_masked_samples_are_gaps():
    z = np.random.default_rng(4).normal(0, 1, 1000)
    mask = np.zeros(1000, bool)
    mask[300:360] = mask[700:740] = True
    zm = np.ma.masked_array(z.copy(), mask=mask)
    zm.data[mask] = 1e6  # garbage under the mask must never be used
    with pytest.raises(NoisevarError, match="non-finite"):
        nv.estimate(zm, method="rice")
    got = nv.estimate(zm, method="rice", drop_nonfinite=True)
    assert got.n_total == 900
    assert [g.index for g in got.diagnostics.gaps] == [300, 640]
    parts = [z[:300], z[360:700], z[740:]]
    # pooled per segment, weights their samples: never spliced across the gaps
    want = sum(p.size * nv.estimate(p, method="rice").variance for p in parts) / 900
    assert got.variance == pytest.approx(want, rel=0.01)


def test_a_negative_reference_variance_result_is_refused():
    rng = np.random.default_rng(5)
    s = np.cumsum(rng.normal(0, 0.1, 3000))
    a, b = s + rng.normal(0, 1, 3000), s + rng.normal(0, 1, 3000)
    with pytest.raises(NoisevarError, match="not positive"):
        nv.estimate(a, method="somd-redundant", reference=b, reference_variance=1e6)
    with pytest.raises(NoisevarError):
        nv.estimate(a, method="somd-redundant", reference=b, reference_variance=-1)
    with pytest.raises(NoisevarError):
        nv.estimate(a, method="somd-redundant", reference=b, reference_variance=math.inf)
