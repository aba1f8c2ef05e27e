"""Parameter specs, the method registry, N-D input (axis=), sample times and batch SOMD."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.estimators import METHODS, estimate_chunked, register, unregister
from noisevar.estimators.params import PARAMS
from noisevar.estimators.results import VarianceEstimate, VarianceEstimates
from noisevar.estimators.somd import somd_variance_records, somd_variance_windows
from noisevar.estimators.spec import MethodSpec
from noisevar.params import ParamSpec

RNG = np.random.default_rng(40)
N = 1500
CHANNELS = np.stack(
    [
        nv.generate("fast-slow", n=N, seed=1).measured,
        nv.generate("random-jerk", n=N, seed=2).measured,
        RNG.normal(5.0, 2.0, N),
        nv.generate("noise-ramp", n=N, seed=3).measured,
    ]
).reshape(2, 2, N)
REFERENCE = nv.generate("fast-slow", n=N, seed=1).clean


# -------------------------------------------------------------------------- ParamSpec
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6))
def test_paramspec_range_is_open_closed(x):
    spec = ParamSpec("g", "float", lo=0.0, hi=1.0)
    if 0.0 < x <= 1.0:
        assert spec.validate(x) == x
    else:
        with pytest.raises(NoisevarError, match=r"g=.* is out of range: it must be in \(0, 1\]"):
            spec.validate(x)


@given(st.integers(min_value=-50, max_value=50))
def test_paramspec_int_with_closed_low_bound(k):
    spec = ParamSpec("k", "int", lo=8, lo_closed=True)
    if k >= 8:
        assert spec.validate(float(k)) == k and isinstance(spec.validate(float(k)), int)
    else:
        with pytest.raises(NoisevarError, match="out of range"):
            spec.validate(k)


def test_paramspec_kinds():
    assert PARAMS["h_smooth"].validate([1e-5, 2e-5]) == (1e-5, 2e-5)
    assert PARAMS["h_smooth"].validate(1e-5) == 1e-5
    assert PARAMS["select"].validate(np.bool_(False)) is False
    assert PARAMS["trim"].validate(math.inf) == math.inf  # trim=inf: no trimming
    with pytest.raises(NoisevarError, match="must be finite"):
        PARAMS["gamma_amp"].validate(math.inf)
    with pytest.raises(NoisevarError, match="must be a number"):
        PARAMS["window"].validate(True)
    with pytest.raises(NoisevarError, match="integer"):
        PARAMS["window"].validate(40.5)
    ref = np.arange(3.0)
    assert PARAMS["reference"].validate(ref) is ref  # data passes through
    with pytest.raises(NoisevarError, match="one of scaled, paper"):
        PARAMS["angle"].validate("radians")


# ------------------------------------------------------------- refusing foreign names
@pytest.mark.parametrize("method", [m for m in nv.methods()])
def test_a_parameter_the_method_does_not_take_is_refused(method):
    spec = METHODS[method]
    foreign = sorted(set(PARAMS) - set(spec.param_specs))[0]
    with pytest.raises(NoisevarError) as info:
        nv.estimate(CHANNELS[0, 0], method=method, **{foreign: 1})
    msg = str(info.value)
    assert f"{method!r} does not take parameter(s) {foreign}" in msg
    for name in spec.param_specs:
        assert name in msg  # the message names the method's parameters


@pytest.mark.parametrize("method", [m for m in nv.methods() if m != "somd-redundant"])
def test_drop_nonfinite_is_accepted_by_every_method(method):
    z = CHANNELS[0, 0].copy()
    z[7] = np.nan
    est = nv.estimate(z, method=method, drop_nonfinite=True)
    assert est.n_total == N - 1


# ---------------------------------------------------------------------------- axis=
def _params(method):
    return {"reference": REFERENCE} if method == "somd-redundant" else {}


@pytest.mark.parametrize("method", nv.methods())
def test_each_channel_equals_the_1d_estimate(method):
    if method.startswith("mle"):
        Z = CHANNELS[:1, :2]  # slow: two channels are enough
    else:
        Z = CHANNELS
    params = _params(method)
    if method.startswith("somd") and method != "somd-redundant":
        params = {"select": False}
    res = nv.estimate(np.moveaxis(Z, -1, 1), method=method, axis=1, **params)
    assert isinstance(res, VarianceEstimates)
    assert res.variance.shape == Z.shape[:-1] and res.ci95.shape == Z.shape[:-1] + (2,)
    for idx in np.ndindex(*Z.shape[:-1]):
        one = nv.estimate(Z[idx], method=method, **params)
        assert res[idx].variance == pytest.approx(one.variance, rel=1e-12, abs=0)
        assert res.variance[idx] == pytest.approx(one.variance, rel=1e-12, abs=0)
        assert res.n_used[idx] == one.n_used
        assert res[idx].params == one.params
        np.testing.assert_allclose(res[idx].ci95, one.ci95, rtol=1e-12)


@pytest.mark.parametrize("method", ["somd", "somd-paper"])
def test_somd_with_selection_per_channel(method):
    res = nv.estimate(CHANNELS[0], method=method)
    for i, est in enumerate(res):
        one = nv.estimate(CHANNELS[0, i], method=method)
        assert est.variance == pytest.approx(one.variance, rel=1e-12)
        np.testing.assert_array_equal(est.details.kept_windows, one.details.kept_windows)


def test_variance_estimates_container():
    res = nv.estimate(CHANNELS, method="diff2")
    assert len(res) == 4 and res.shape == (2, 2)
    assert res[3] is res[1, 1]
    assert all(isinstance(e, VarianceEstimate) for e in res)
    np.testing.assert_allclose(res.std, np.sqrt(res.variance))
    frame = res.to_frame()
    assert list(frame["channel"]) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    np.testing.assert_array_equal(frame["variance"], res.variance.ravel())
    assert res.params == {"method": "diff2"}


def test_nd_channel_errors_name_the_channel():
    Z = CHANNELS[0].copy()
    Z[1] = 3.0
    with pytest.raises(NoisevarError, match=r"channel \(1,\): the signal is constant"):
        nv.estimate(Z, method="rice")


def test_nd_drop_nonfinite_falls_back_to_channel_by_channel():
    Z = CHANNELS[0].copy()
    Z[0, 10] = np.inf
    res = nv.estimate(Z, method="rice", drop_nonfinite=True)
    assert res[0].n_total == N - 1 and res[1].n_total == N
    assert res[0].variance == nv.estimate(Z[0], method="rice", drop_nonfinite=True).variance


def test_one_column_arrays_stay_one_signal():
    z = CHANNELS[0, 0]
    for shaped in (z[:, None], z[None, :]):
        for axis in (0, -1):
            assert nv.estimate(shaped, method="rice", axis=axis).variance == pytest.approx(
                nv.estimate(z, method="rice").variance, rel=1e-15
            )


# ------------------------------------------------------------------------------- t=
def test_uniform_times_are_accepted_and_change_nothing():
    z = CHANNELS[0, 0]
    t = 1e9 + 0.1 * np.arange(N)
    assert nv.estimate(z, t=t).variance == nv.estimate(z).variance


@pytest.mark.parametrize(
    ("t", "phrase"),
    [
        (np.arange(N - 1.0), "one time per sample"),
        (np.r_[np.arange(N - 1.0), N - 2.0], "strictly increasing"),
        (np.r_[np.arange(N - 1.0), np.nan], "NaN or Inf"),
    ],
)
def test_bad_times_are_refused(t, phrase):
    with pytest.raises(NoisevarError, match=phrase):
        nv.estimate(CHANNELS[0, 0], t=t)


def test_non_uniform_times_split_the_record_instead_of_being_spliced():
    z = CHANNELS[0, 0]
    t = np.arange(z.size, dtype=float)
    t[z.size // 2 :] += 7.0  # seven samples missing half way
    est = nv.estimate(z, t=t)
    (gap,) = est.diagnostics.gaps
    assert (gap.index, gap.missing, gap.kind) == (z.size // 2, 7, "gap")
    assert any("uniform segments" in note for note in est.notes)
    assert est.variance == pytest.approx(nv.estimate(z).variance, rel=0.05)


# ------------------------------------------------------------------------ batch SOMD
@pytest.mark.parametrize("paper", [False, True])
def test_somd_variance_records_equals_the_unselected_estimate(paper):
    Z = CHANNELS.reshape(4, N)
    got = somd_variance_records(Z, 3e-5, paper=paper)
    method = "somd-paper" if paper else "somd"
    for b in range(4):
        one = nv.estimate(Z[b], method=method, h_smooth=3e-5, select=False, gamma_ang=10.0)
        assert got[b] == pytest.approx(one.variance, rel=1e-12)


@pytest.mark.parametrize("paper", [False, True])
def test_somd_variance_windows_equals_the_unselected_estimate(paper):
    Z = CHANNELS.reshape(4, N)
    bounds = [(0, 600), (0, 1500), (200, 900), (1400, 1500), (300, 1500)]
    got = somd_variance_windows(Z, bounds, 1e-3, paper=paper)
    method = "somd-paper" if paper else "somd"
    for i, (a, b) in enumerate(bounds):
        for r in range(4):
            try:
                one = nv.estimate(Z[r, a:b], method=method, h_smooth=1e-3, select=False)
            except NoisevarError:
                assert np.isnan(got[r, i])  # too short for the filters to settle
                continue
            assert got[r, i] == pytest.approx(one.variance, rel=1e-12)


# ------------------------------------------------------------------------- registry
def test_a_new_estimator_is_one_spec_and_one_registration():
    """A trivial estimator (sample variance) with a parameter of its own, registered
    through the public path: estimate, methods, config and validation all know it."""
    scale = ParamSpec("scale", "float", 1.0, "multiply the variance", lo=0.0)

    def func(z, notes, scale=1.0):
        v = scale * np.var(z, axis=-1)
        return [
            VarianceEstimate("sample-var", float(x), (x, x), N, N, 1.0, {"scale": scale}, nt)
            for x, nt in zip(v, notes, strict=True)
        ]

    spec = MethodSpec("sample-var", "plain sample variance", "peer", func, (scale,), True)
    register(spec)
    try:
        assert "sample-var" in nv.methods("peer")
        z = CHANNELS[0, 0]
        est = nv.estimate(z, method="sample-var", scale=2.0)
        assert est.variance == pytest.approx(2.0 * np.var(z))
        assert est.params == {"method": "sample-var", "scale": 2.0}
        assert nv.estimate(CHANNELS, method="sample-var").variance.shape == (2, 2)
        with pytest.raises(NoisevarError, match="scale=-1 is out of range"):
            nv.estimate(z, method="sample-var", scale=-1)
        with pytest.raises(NoisevarError, match="does not take parameter"):
            nv.estimate(z, method="sample-var", window=40)
        from noisevar.config import validate_config

        assert validate_config({"method": "sample-var", "scale": 3}) == {
            "method": "sample-var",
            "scale": 3.0,
        }
        with pytest.raises(ValueError, match="already registered"):
            register(spec)
    finally:
        unregister("sample-var")
    assert "sample-var" not in nv.methods()


class _RiceInChunks:
    """A toy chunked engine (Rice's first difference): a Record for the pipeline."""

    def __init__(self, read, n, *, probe=None, chunk=None, workers=2, note="streamed", notes=()):
        self.read, self.n, self.chunk = read, n, chunk or 1000
        self.notes = [*notes, f"{note} in chunks of {self.chunk} samples"]
        self.exponent = 0

    def estimate(self, params):
        total = 0.0
        for a in range(0, self.n - 1, self.chunk):  # chunks overlap by one sample
            total += float(np.sum(np.diff(self.read(a, min(a + self.chunk + 1, self.n))) ** 2))
        var = total / (2 * (self.n - 1))
        return VarianceEstimate("rice-chunks", var, (0.9 * var, 1.1 * var), self.n, self.n,
                                self.n / 1.5, {}, list(self.notes))  # fmt: skip

    def diagnose(self, result):
        from noisevar.diagnostics import diagnose

        return diagnose(self.read(0, self.n))

    def reader(self):
        return self.read


def test_a_method_with_a_chunked_engine_and_a_finishing_step_is_one_spec():
    """Who streams or finishes asks the spec: the pipeline names no method (issue 25)."""

    def func(z, notes):
        var = float(np.sum(np.diff(z) ** 2) / (2 * (z.size - 1)))
        return VarianceEstimate("rice-chunks", var, (0.9 * var, 1.1 * var), z.size, z.size,
                                z.size / 1.5, {}, notes)  # fmt: skip

    def finish(result, diag, record):
        assert record is not None and record(0, 3).size == 3
        return replace(result, notes=[*result.notes, "finished"])

    spec = MethodSpec("rice-chunks", "Rice in chunks", "peer", func,
                      chunked=_RiceInChunks, finish=finish)  # fmt: skip
    register(spec)
    try:
        z = CHANNELS[1, 0]
        one = nv.estimate(z, method="rice-chunks")
        many = estimate_chunked(lambda a, b: z[max(a, 0) : b], z.size, method="rice-chunks")
        assert many.variance == pytest.approx(one.variance, rel=1e-12)
        assert one.notes[-1] == "finished" and many.notes[0].startswith("streamed in chunks")
        assert many.params == one.params == {"method": "rice-chunks"}
        assert many.diagnostics.verdict == one.diagnostics.verdict
        with pytest.raises(NoisevarError, match="cannot read a record in chunks"):
            estimate_chunked(lambda a, b: z[a:b], z.size, method="rice")
    finally:
        unregister("rice-chunks")


def test_registry_is_the_list_of_methods():
    from noisevar.estimators import REGISTRY

    assert [s.name for s in REGISTRY] == nv.methods()
    assert nv.methods()[0] == "auto"
    assert set(nv.describe_methods()) == set(nv.methods())


@settings(max_examples=20)
@given(st.integers(min_value=2, max_value=5), st.integers(min_value=0, max_value=2**16))
def test_difference_estimators_vectorise_exactly(k, seed):
    Z = np.random.default_rng(seed).normal(0.0, 1.0, (k, 300)).cumsum(axis=1)
    for method in ("rice", "diff2", "hkt3", "mad-diff"):
        res = nv.estimate(Z, method=method)
        for i in range(k):
            assert res[i].variance == pytest.approx(
                nv.estimate(Z[i], method=method).variance, rel=1e-12
            )
