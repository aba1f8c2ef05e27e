"""Hostile input on what issues 26/29's last rounds added (brief hostile29b): the composite
IMU fits (``fit_imu_model``, ``fit_imu_records``, ``composite_fits``), ``regimes='still'``
on every noise model, the still levels, and the numbers' formatter. Every number finite and
right, or one NoisevarError of one line (the contract of tests/test_hostile_api.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.format import eng
from noisevar.noise_model import fit_coloured_noise, fit_imu_model, fit_imu_records
from noisevar.noise_model.exports.model import composite_fits
from noisevar.synth import still_start

FUZZ = settings(
    max_examples=8,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def _base(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(0, 0.01, n)) + rng.normal(0, 1, n)


def _numbers(fit) -> list[float]:
    out: list[float] = []

    def walk(node):
        if isinstance(node, dict):
            for v in node.values():
                walk(v)
        elif isinstance(node, list | tuple):
            for v in node:
                walk(v)
        elif isinstance(node, float):
            out.append(node)

    walk(fit.to_dict())
    return out


def _refused(call):
    """The result, or None after checking a refusal is one NoisevarError of one line."""
    try:
        return call()
    except NoisevarError as exc:
        assert str(exc) and "\n" not in str(exc)
        return None


#: Magnitudes across the float range (subnormals, 1e±154, 1e±300 included).
scales = st.one_of(
    st.builds(lambda e: 2.0**e, st.integers(-1074, 1020)),
    st.sampled_from([1e154, 1e-154, 1e300, 1e-300, 1e-160, 1e-310, 1e30]),
)


class TestCompositeFitFloatRange:
    """fit_imu_model raised ValueError ('Residuals are not finite') at 1e±154, 1e300 and
    1e-160, and gave inf at rate 1e300; it now fits a copy scaled by a power of two."""

    @FUZZ
    @given(x=scales, regimes=st.sampled_from(["all", "still"]))
    def test_finite_or_one_error(self, x, regimes):
        z = still_start(2000, 4000, rng=3) if regimes == "still" else _base(1, 3000)
        fit = _refused(lambda: fit_imu_model(z * x, 100.0, regimes=regimes))
        if fit is not None:
            assert all(math.isfinite(v) for v in _numbers(fit))

    @pytest.mark.parametrize("e", [-400, -120, 120, 450])
    def test_power_of_two_scales_exactly(self, e):
        z = _base(2, 6000)
        ref, got = fit_imu_model(z, 100.0), fit_imu_model(z * 2.0**e, 100.0)
        assert got.model == ref.model
        for a, b in zip(ref.parameters, got.parameters, strict=True):
            power = 0 if a.name.endswith("tau_c") else e
            assert b.value == pytest.approx(a.value * 2.0**power, rel=1e-12)
        assert got.filter_bias.random_walk == pytest.approx(
            ref.filter_bias.random_walk * 2.0**e, rel=1e-12
        )
        np.testing.assert_allclose(got.model_wv(), ref.model_wv() * 4.0**e, rtol=1e-12)

    @pytest.mark.parametrize("x", [1e154, 1e-160, 1e300])
    def test_records_and_composite_fits(self, x):
        z = _base(3, 3000)
        for call in (
            lambda: fit_imu_records([z * x, z[:1000] * x], 100.0),
            lambda: composite_fits([z * x, z[::-1] * x], [100.0, 100.0]),
        ):
            fit = _refused(call)
            fits = fit if isinstance(fit, list) else [fit] if fit is not None else []
            assert all(math.isfinite(v) for f in fits for v in _numbers(f))

    @pytest.mark.parametrize("rate", [1e300, 1e-300, 5e-324])
    def test_extreme_rate_is_one_error(self, rate):
        with pytest.raises(NoisevarError, match="Hz"):
            fit_imu_model(_base(4, 1000), rate)

    def test_int64_beyond_2_53_is_one_error(self):
        z = (2**60 + np.round(_base(5, 1000) * 1e4)).astype(np.int64)
        with pytest.raises(NoisevarError, match="2\\*\\*53"):
            fit_imu_model(z, 100.0)
        with pytest.raises(NoisevarError, match="2\\*\\*53"):
            fit_imu_records([z, z], 100.0)


class TestSubnormalVariances:
    """A record whose variance is subnormal: ``eng`` divided by 10**-324 == 0."""

    @pytest.mark.parametrize("v", [5e-324, 1e-322, -1e-320, 2.2e-308])
    def test_eng_formats_subnormals(self, v):
        text = eng(v)
        assert "×10⁻³" in text and float(text.split("×")[0]) != 0

    def test_still_start_record_at_1e_160(self):
        z = still_start(1500, 3000, rng=2) * 1e-160
        est = nv.estimate(z)
        assert math.isfinite(est.variance) and est.variance > 0
        _refused(lambda: fit_coloured_noise(z, rate=100.0, models=("white",), regimes="still"))


def test_px4_range_warning_names_a_one_sided_bound():
    """A tiny record's PX4 file said "range [0.0001, None]" (Python's None in the file)."""
    from noisevar.noise_model import inertial_noise
    from noisevar.noise_model.exports import export, imu_model

    z = [_base(i, 4000) * 2.0**-300 for i in range(2)]
    model = imu_model(inertial_noise(z[0], 100.0), inertial_noise(z[1], 100.0))
    (px4,) = export(model, "px4")
    assert "None" not in px4.text and "documented minimum 0.0001" in px4.text


@pytest.mark.parametrize("x", [1e300, 1e-300, 1e-160])
def test_inertial_model_curve_at_the_float_range_edges(x):
    """InertialNoise.model squared each term as a Python float: OverflowError at 1e300
    (the Noise model page's Allan figure crashed)."""
    from noisevar.noise_model import inertial_noise

    z = still_start(2000, 4000, rng=3)
    ref = inertial_noise(z, 100.0).model()[1]
    got = inertial_noise(z * x, 100.0).model()[1]
    np.testing.assert_allclose(got, ref * x, rtol=1e-9)


@pytest.mark.parametrize("regimes", ["all", "still"])
def test_kalman_r_interval_when_q_is_at_its_bound(regimes):
    """With q at the bottom of its range the 2x2 curvature failed and r's interval was
    (nan, nan) (JSON nulls from ``noisevar fit --regimes still``); r's own curvature
    bounds it, q's is (0, inf) as when not identified."""
    from noisevar.noise_model import fit_kalman

    white = np.random.default_rng(0).normal(0, 1e-3, 3000)
    z = still_start(2000, 4000, rng=3) if regimes == "still" else white
    t = fit_kalman(z, "rw", rate=100.0, regimes=regimes)
    assert t.r_interval[0] < t.r < t.r_interval[1] < 1.2 * t.r
    assert t.q_interval == (0.0, math.inf)


@pytest.mark.parametrize("x", [1e154, 1e-160, 2.0**-400])
@pytest.mark.parametrize("regimes", ["all", "still"])
def test_cli_imu_model_auto_exit_0_or_2(tmp_path, x, regimes):
    """``noisevar imu --model auto`` exited 3 (internal error: ValueError) at 1e154 and
    1e-160, with or without ``--regimes still``."""
    import contextlib
    import io
    import json

    from noisevar.cli import main

    np.save(tmp_path / "z.npy", still_start(2000, 4000, rng=3) * x)
    out, err = io.StringIO(), io.StringIO()
    args = ["imu", str(tmp_path / "z.npy"), "--rate", "100", "--model", "auto"]
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([*args, "--regimes", regimes, "--format", "json"])
    if code == 0:
        json.loads(out.getvalue(), parse_constant=lambda c: pytest.fail(f"bare {c}"))
    else:
        assert code == 2 and err.getvalue().count("\n") == 1, err.getvalue()


def test_still_composite_fit_whose_whole_record_variance_overflows():
    """regimes='still' found the still stretch on the record as given: at 1e154 its whole
    R (motion included) is beyond a float, so the still fit was refused; it is found on the
    scaled record now, as allan and inertial_noise do."""
    rng = np.random.default_rng(6)
    motion = 30 * np.sin(np.arange(2000) / 3.0) + rng.normal(0, 30, 2000)
    z = np.concatenate([rng.normal(0, 1, 3000), motion])
    ref = fit_imu_model(z, 100.0, regimes="still")
    got = fit_imu_model(z * 1e154, 100.0, regimes="still")
    assert got.model == ref.model and got.notes[0] == ref.notes[0]
    for a, b in zip(ref.parameters, got.parameters, strict=True):
        power = 0 if a.name.endswith("tau_c") else 1
        assert b.value == pytest.approx(a.value * 1e154**power, rel=1e-9)


def test_still_coloured_fit_whose_whole_record_variance_overflows():
    """As for the composite fit: fit_coloured_noise(regimes='still') refused a record whose
    still R is a float but whose whole R (motion included) is not."""
    rng = np.random.default_rng(6)
    motion = 30 * np.sin(np.arange(2000) / 3.0) + rng.normal(0, 30, 2000)
    z = np.concatenate([rng.normal(0, 1, 3000), motion])
    ref = fit_coloured_noise(z, rate=100.0, models=("white",), regimes="still")
    got = fit_coloured_noise(z * 2.0**510, rate=100.0, models=("white",), regimes="still")
    assert got.r == pytest.approx(ref.r * 4.0**510, rel=1e-12)
    assert got.notes == ref.notes
