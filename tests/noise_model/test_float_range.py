"""The float range and every dtype at the noise-model and streamed entry points (issue 29
item 3): the hostile-API contract of ``estimate`` (tests/test_hostile_api.py) extended, one
fuzz class per entry point. Every number finite and right, or one NoisevarError (one line);
from the CLI, exit 0 with strict JSON or exit 2 with one line."""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import noisevar as nv
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.noise_model import allan, fit_coloured_noise, fit_kalman, inertial_noise
from noisevar.stream import estimate_file

FUZZ = settings(
    max_examples=10,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
N = (240, 320)
COLOURED = ("white", "white+rw")  # the scaling is the models' common path; these are fast


def _base(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(0, 0.05, n)) + rng.normal(0, 1, n)


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
lengths = st.integers(*N)
#: Every magnitude (subnormals and 1e±154, 1e±300 included), raw doubles, float32 records,
#: int64 records beyond 2**53.
records = st.one_of(
    st.builds(
        lambda e, s, n: _base(s, n) * 2.0**e, st.integers(-1074, 1020), st.integers(0, 99), lengths
    ),
    st.builds(
        lambda x, s, n: _base(s, n) * x,
        st.sampled_from([1e154, 1e-154, 1e300, 1e-300, 1e-160, 1e-310, 1e30]),
        st.integers(0, 99),
        lengths,
    ),
    arrays(np.float64, lengths, elements=finite),
    st.builds(
        lambda e, s, n: (_base(s, n) * 2.0**e).astype(np.float32),
        st.integers(-149, 126),
        st.integers(0, 99),
        lengths,
    ),
    st.builds(
        lambda off, s, n: (off + np.random.default_rng(s).integers(0, 1000, n)).astype(np.int64),
        st.integers(2**53, 2**62),
        st.integers(0, 99),
        lengths,
    ),
)  # fmt: skip
rates = st.one_of(
    st.sampled_from([1e300, 1e-300, 5e-324, 1.7e308, 2.0**-64, 2.0**64, 100.0]),
    st.floats(min_value=1e-300, max_value=1e300),
)


def _finite(*values) -> bool:
    return all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in values)


def _refused(call) -> object | None:
    """The result, or None after checking a refusal is one NoisevarError of one line."""
    try:
        return call()
    except NoisevarError as exc:
        assert str(exc) and "\n" not in str(exc)
        return None


class TestAllan:
    @FUZZ
    @given(z=records, rate=rates, data=st.sampled_from(["phase", "rate"]))
    def test_finite_or_one_error(self, z, rate, data):
        res = _refused(lambda: allan(z, rate=rate, data=data))
        if res is not None:
            assert _finite(res.taus, res.deviation, *res.interval) and np.all(res.deviation > 0)

    @pytest.mark.parametrize("e", [-1000, -530, 510, 1000])
    @pytest.mark.parametrize("data", ["phase", "rate"])
    def test_powers_of_two_scale_exactly(self, e, data):
        z = _base(1, 2000)
        ref = allan(z, rate=50.0, data=data)
        got = allan(z * 2.0**e, rate=50.0, data=data)
        np.testing.assert_array_equal(got.deviation, ref.deviation * 2.0**e)
        np.testing.assert_array_equal(got.taus, ref.taus)
        fast = allan(z, rate=50.0 * 2.0**900, data=data)  # the rate scaled too
        np.testing.assert_array_equal(fast.taus, ref.taus * 2.0**-900)
        power = 900 if data == "phase" else 0
        np.testing.assert_array_equal(fast.deviation, ref.deviation * 2.0**power)


class TestInertialNoise:
    @FUZZ
    @given(z=records, rate=rates)
    def test_finite_or_one_error(self, z, rate):
        fit = _refused(lambda: inertial_noise(z, rate))
        if fit is not None:
            for t in fit.terms:
                assert _finite(t.value, t.interval, t.discrete) and t.value >= 0
            assert _finite(fit.white_level, fit.allan.deviation)

    @pytest.mark.parametrize("x", [1e154, 1e300, 1e-160, 1e-300])
    def test_scaled_records_give_scaled_terms(self, x):
        z = _base(2, 3000)
        ref, got = inertial_noise(z, 100.0), inertial_noise(z * x, 100.0)
        for a, b in zip(ref.terms, got.terms, strict=True):
            assert b.value == pytest.approx(a.value * x, rel=1e-9, abs=1e-300 * x)


class TestFitColouredNoise:
    @FUZZ
    @given(z=records, rate=rates)
    def test_finite_or_one_error(self, z, rate):
        fit = _refused(lambda: fit_coloured_noise(z, rate=rate, models=COLOURED))
        if fit is not None:
            assert _finite(fit.r, fit.q) and fit.r >= 0

    @pytest.mark.parametrize("x", [1e154, 1e-150, 2.0**-500])
    def test_scaled_records_give_scaled_variances(self, x):
        z = _base(3, 400)
        ref = fit_coloured_noise(z, models=COLOURED)
        got = fit_coloured_noise(z * x, models=COLOURED)
        assert got.model == ref.model
        assert got.r == pytest.approx(ref.r * x * x, rel=1e-6)

    @pytest.mark.parametrize("x", [1e300, 1e-300, 1e-160])
    def test_unrepresentable_variance_is_one_error(self, x):
        with pytest.raises(NoisevarError, match="floating-point number"):
            fit_coloured_noise(_base(3, 400) * x, models=COLOURED)


class TestFitKalman:
    @FUZZ
    @given(z=records, rate=rates, model=st.sampled_from(["rw", "cv"]))
    def test_finite_or_one_error(self, z, rate, model):
        t = _refused(lambda: fit_kalman(z, model=model, rate=rate))
        if t is not None:
            assert _finite(t.q, t.r, t.gain, t.loglik) and t.q > 0 and t.r > 0

    @pytest.mark.parametrize("x", [2.0**100, 1e30, 1e154, 1e-120])
    def test_scaled_records_give_scaled_q_and_r(self, x):
        z = np.cumsum(np.cumsum(np.random.default_rng(4).normal(0, 0.01, 1500))) * 0.01
        z = z + np.random.default_rng(5).normal(0, 1, 1500)
        ref, got = fit_kalman(z, "cv", rate=10.0), fit_kalman(z * x, "cv", rate=10.0)
        assert got.r == pytest.approx(ref.r * x * x, rel=1e-4)
        assert got.q == pytest.approx(ref.q * x * x, rel=1e-4)
        assert got.h == pytest.approx(ref.h, rel=1e-4)

    def test_a_covariance_beyond_the_float_range_is_said_and_json_safe(self):
        import json
        import warnings

        z = np.cumsum(np.cumsum(np.random.default_rng(4).normal(0, 0.01, 1500))) * 0.01
        z = z + np.random.default_rng(5).normal(0, 1, 1500)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no overflow warning: said in a note instead
            t = fit_kalman(z * 1e154, "cv", rate=10.0)
        assert any("exceeds the largest floating-point number" in n for n in t.notes)
        json.dumps(t.to_dict(), allow_nan=False)


class TestStreamedFile:
    @FUZZ
    @given(z=records)
    def test_finite_or_one_error(self, z):
        with tempfile.TemporaryDirectory() as tmp:
            np.save(Path(tmp) / "z.npy", z)
            res = _refused(lambda: estimate_file(Path(tmp) / "z.npy"))
        if res is not None:
            assert _finite(res.variance, res.ci95) and res.variance >= 0
            assert res.ci95[0] <= res.variance <= res.ci95[1]
            if z.dtype.kind == "f":  # the same number as in memory
                assert res.variance == pytest.approx(nv.estimate(z).variance, rel=1e-9)


def _cli(*args: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


COMMANDS = {
    "allan": lambda f, r: ("allan", f, "--rate", r, "--format", "json"),
    "imu": lambda f, r: ("imu", f, "--rate", r, "--format", "json"),
    "fit": lambda f, r: ("fit", f, "--rate", r, "--model", "rw", "--format", "json"),
    "estimate --stream": lambda f, r: ("estimate", f, "--stream", "--format", "json"),
}


class TestCommandLine:
    @pytest.mark.parametrize("command", list(COMMANDS))
    @settings(
        max_examples=6,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    @given(z=records, rate=rates)
    def test_exit_0_with_strict_json_or_2_with_one_line(self, command, z, rate):
        with tempfile.TemporaryDirectory() as tmp:
            path = str(Path(tmp) / "z.npy")
            np.save(path, z)
            code, out, err = _cli(*COMMANDS[command](path, repr(float(rate))))
        if code == 0:
            data = json.loads(out, parse_constant=lambda c: pytest.fail(f"bare {c} in JSON"))
            assert not _nulls_in_numbers(data, command)
        else:
            assert code == 2, err
            assert err.count("\n") == 1 and err.startswith("noisevar: error:")


def _nulls_in_numbers(data, command: str) -> list[str]:
    """Keys whose value is null (NaN) or "inf" where a number is expected."""
    keys = {
        "allan": ("deviation", "taus"),
        "imu": ("value", "white_level"),
        "fit": ("q", "r", "loglik"),
        "estimate --stream": ("variance", "ci95_low", "ci95_high"),
    }[command]
    bad = []

    def walk(node, key=None):
        if isinstance(node, dict) and node.get("variance") is None and node.get("reason"):
            return  # a level absent with its reason said (diagnostics.quiet_level), not NaN
        if isinstance(node, dict):
            for k, v in node.items():
                if k != "units":  # the names of the units, not numbers
                    walk(v, k)
        elif isinstance(node, list):
            for v in node:
                walk(v, key)
        elif key in keys and (node is None or isinstance(node, str)):
            bad.append(key)
        elif key in keys and isinstance(node, float) and not math.isfinite(node):
            bad.append(key)

    walk(data)
    return bad
