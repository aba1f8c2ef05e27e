"""Consumer exports (docs §E7): every file round-trips through its own format, and each
value is the model's term by the consumer's documented conversion."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from noisevar.errors import NoisevarError
from noisevar.noise_model import exports, inertial_noise
from noisevar.noise_model.exports import ImuModel, SensorTerms
from noisevar.noise_model.exports.base import ascii_text
from noisevar.noise_model.exports.filterpy import exact_q
from noisevar.noise_model.simulate import simulate_inertial

RATE = 400.0
GYRO = SensorTerms(N=1.888e-4, K=2.557e-6, B=3e-5, unit="rad/s")
ACCEL = SensorTerms(N=2.502e-3, K=6.97e-5, B=4e-4, unit="m/s^2")
MODEL = ImuModel(GYRO, ACCEL, RATE, gnss={"position": 1.2, "velocity": 0.15})
TOL = 1e-9

#: Each consumer's values by its documented conversion (the writer's docstring cites it).
F_PX4, F_AP = 1e6 / 10000, 1 / 0.012
EXPECTED = {
    "kalibr": {
        "gyroscope_noise_density": GYRO.N,
        "gyroscope_random_walk": GYRO.K,
        "accelerometer_noise_density": ACCEL.N,
        "accelerometer_random_walk": ACCEL.K,
        "update_rate": RATE,
    },
    "openvins": {
        "gyroscope_noise_density": GYRO.N,
        "gyroscope_random_walk": GYRO.K,
        "accelerometer_noise_density": ACCEL.N,
        "accelerometer_random_walk": ACCEL.K,
        "update_rate": RATE,
    },
    "vins": {
        "gyr_n": GYRO.N * math.sqrt(RATE),
        "acc_n": ACCEL.N * math.sqrt(RATE),
        "gyr_w": GYRO.K * math.sqrt(RATE),
        "acc_w": ACCEL.K * math.sqrt(RATE),
    },
    "orbslam3": {
        "IMU.NoiseGyro": GYRO.N,
        "IMU.NoiseAcc": ACCEL.N,
        "IMU.GyroWalk": GYRO.K,
        "IMU.AccWalk": ACCEL.K,
        "IMU.Frequency": RATE,
    },
    "robot_localization": {
        "angular_velocity_covariance": GYRO.N**2 * RATE,
        "linear_acceleration_covariance": ACCEL.N**2 * RATE,
        "process_noise_covariance[vyaw]": 0.02 + GYRO.K**2,
        "process_noise_covariance[az]": 0.015 + ACCEL.K**2,
        "process_noise_covariance[x]": 0.05,
    },
    "px4": {
        "EKF2_GYR_NOISE": GYRO.N * math.sqrt(F_PX4),
        "EKF2_ACC_NOISE": ACCEL.N * math.sqrt(F_PX4),
        "EKF2_GYR_B_NOISE": GYRO.K * math.sqrt(F_PX4),
        "EKF2_ACC_B_NOISE": ACCEL.K * math.sqrt(F_PX4),
        "EKF2_GPS_P_NOISE": 1.2,
        "EKF2_GPS_V_NOISE": 0.15,
    },
    "ardupilot": {
        "EK3_GYRO_P_NSE": GYRO.N * math.sqrt(F_AP),
        "EK3_ACC_P_NSE": ACCEL.N * math.sqrt(F_AP),
        "EK3_GBIAS_P_NSE": GYRO.K * math.sqrt(F_AP),
        "EK3_ABIAS_P_NSE": ACCEL.K * math.sqrt(F_AP),
        "EK3_POSNE_M_NSE": 1.2,
        "EK3_VELNE_M_NSE": 0.15,
    },
    "matlab": {
        "gyro.NoiseDensity": GYRO.N,
        "gyro.RandomWalk": GYRO.K,
        "gyro.BiasInstability": GYRO.B,
        "accel.NoiseDensity": ACCEL.N,
        "accel.RandomWalk": ACCEL.K,
        "accel.BiasInstability": ACCEL.B,
    },
    "filterpy": {
        "N_GYRO": GYRO.N,
        "K_GYRO": GYRO.K,
        "N_ACCEL": ACCEL.N,
        "K_ACCEL": ACCEL.K,
        "DT": 1 / RATE,
    },
}


def test_every_consumer_is_checked() -> None:
    assert set(EXPECTED) == set(exports.CONSUMERS)


@pytest.mark.parametrize("key", list(exports.CONSUMERS))
def test_round_trip_and_documented_conversion(key: str) -> None:
    (f,) = exports.export(MODEL, key)
    back = exports.consumer(key).parse(f.text)  # the consumer's own format
    for name, want in EXPECTED[key].items():
        assert back[name] == pytest.approx(want, rel=TOL), name
    for v in f.values:  # every value written says its unit, kind and conversion
        assert back[v.name] == pytest.approx(v.value, rel=TOL)
        assert v.unit and v.kind and v.how
        assert v.name in f.text and (v.unit in f.text or ascii_text(v.unit) in f.text)
    assert "BEST FIT" in f.text and "default of noisevar: best" in f.text
    if key not in ("kalibr", "robot_localization", "filterpy"):  # read by OpenCV, GCS, MATLAB
        assert f.text.isascii()


@pytest.mark.parametrize("key", ["vins", "px4", "ardupilot", "robot_localization"])
def test_ambiguity_said_in_the_file(key: str) -> None:
    (f,) = exports.export(MODEL, key)
    assert "AMBIGUOUS" in f.text


def test_yaml_files_load_and_params_lines_parse() -> None:
    files = {f.consumer: f for f in exports.export(MODEL, "all")}
    for key in ("kalibr", "robot_localization"):
        assert isinstance(yaml.safe_load(files[key].text), dict)
    rows = [ln.split("\t") for ln in files["px4"].text.splitlines() if not ln.startswith("#")]
    assert all(len(r) == 5 and r[:2] == ["1", "1"] and r[4] == "9" for r in rows)
    rows = [ln for ln in files["ardupilot"].text.splitlines() if not ln.startswith("#")]
    assert all(ln.startswith("EK3_") and ln.count(",") == 1 for ln in rows)


def test_matlab_parser_refuses_other_syntax() -> None:
    parse = exports.consumer("matlab").parse
    with pytest.raises(ValueError):
        parse("gyro = gyroparams('NoiseDensity', 1e-3, 'RandomWalk');")
    with pytest.raises(ValueError):
        parse("x = 1 +")


def test_filterpy_module_builds_the_exact_q() -> None:
    (f,) = exports.export(MODEL, "filterpy")
    ns: dict = {}
    exec(compile(f.text, "imu_filterpy.py", "exec"), ns)  # noqa: S102 - our own output
    kf = ns["gyro_axis"]()
    q11, q12, q22 = exact_q(GYRO.N, GYRO.K, 1 / RATE)
    np.testing.assert_allclose(kf.Q, [[q11, q12], [q12, q22]], rtol=TOL)


def test_unknown_consumer_and_variant_refused() -> None:
    with pytest.raises(NoisevarError, match="unknown consumer 'nope'"):
        exports.consumers("px4,nope")
    with pytest.raises(NoisevarError, match="variant"):
        exports.imu_model([], [], variant="safe")
    assert exports.consumers("all") == list(exports.CONSUMERS)


@pytest.fixture(scope="module")
def fits():
    gyro = [
        inertial_noise(
            simulate_inertial(
                40_000,
                100.0,
                random_walk=2e-4,
                rate_random_walk=2e-5,
                bias_instability=5e-5,
                seed=i,
            ),
            100.0,
            unit="deg/s",
        )
        for i in range(2)
    ]
    accel = inertial_noise(
        simulate_inertial(40_000, 100.0, random_walk=2e-3, rate_random_walk=1e-4, seed=9),
        100.0,
        unit="mg",
    )
    return gyro, accel


def test_model_converts_units_and_keeps_the_largest_axis(fits) -> None:
    gyro, accel = fits
    m = exports.imu_model(gyro, accel)
    n = max(max(g.random_walk, g.white_level) for g in gyro)
    assert m.gyro.N == pytest.approx(n * math.pi / 180, rel=TOL)
    assert m.accel.K == pytest.approx(accel.rate_random_walk * 9.80665e-3, rel=TOL)
    assert m.gyro.unit == "rad/s" and any("deg/s to rad/s" in x for x in m.notes)


def test_conservative_raises_never_lowers_and_is_labelled(fits) -> None:
    gyro, accel = fits
    best = exports.imu_model(gyro, accel)
    safe = exports.imu_model(gyro, accel, variant="conservative")
    assert safe.gyro.N >= best.gyro.N * (1 - 1e-9) and safe.gyro.K >= best.gyro.K
    assert safe.gyro.factors["K"] > 1  # the bias instability B has to go somewhere
    (f,) = exports.export(safe, "kalibr")
    assert "CONSERVATIVE" in f.text and "factors over the best fit" in f.text


def test_px4_warns_outside_its_documented_range() -> None:
    loud = ImuModel(GYRO, SensorTerms(N=2.5e-3, K=5e-2, B=0.0, unit="m/s^2"), RATE)
    (f,) = exports.export(loud, "px4")
    assert "WARNING: EKF2_ACC_B_NOISE is outside" in f.text  # 0.5 m/s³ > 0.01
    assert "WARNING: EKF2_GYR_NOISE" not in f.text
    assert exports.consumer("px4").parse(f.text)["EKF2_ACC_B_NOISE"] == pytest.approx(0.5)


@pytest.fixture(scope="module")
def axes():
    """Two gyroscope axes (deg/s) and one accelerometer axis (mg): data, Allan and composite
    fits of the same data."""
    gyro = [
        simulate_inertial(40_000, 100.0, random_walk=2e-4, rate_random_walk=2e-5, seed=20 + i)
        for i in range(2)
    ]
    accel = [simulate_inertial(40_000, 100.0, random_walk=2e-3, rate_random_walk=1e-4, seed=29)]
    allan_g = [inertial_noise(z, 100.0, unit="deg/s") for z in gyro]
    allan_a = [inertial_noise(z, 100.0, unit="mg") for z in accel]
    comp_g = exports.composite_fits(gyro, [100.0, 100.0], unit="deg/s")
    comp_a = exports.composite_fits(accel, [100.0], unit="mg")
    return allan_g, allan_a, comp_g, comp_a, gyro


def test_k_from_the_composite_fit_n_from_the_allan_fit(axes) -> None:
    """K is the composite fit's bias as one random walk (largest axis, converted), N stays the
    Allan fit's; each file's header says which fit gave K; every file still round-trips."""
    allan_g, allan_a, comp_g, comp_a, _ = axes
    allan = exports.imu_model(allan_g, allan_a)
    m = exports.imu_model(allan_g, allan_a, gyro_bias=comp_g, accel_bias=comp_a)
    k_eq = max(c.filter_bias.random_walk for c in comp_g)
    assert m.gyro.K == pytest.approx(k_eq * math.pi / 180, rel=TOL)
    assert m.accel.K == pytest.approx(comp_a[0].filter_bias.random_walk * 9.80665e-3, rel=TOL)
    assert m.gyro.K != allan.gyro.K and (m.gyro.N, m.accel.N) == (allan.gyro.N, allan.accel.N)
    for f in exports.export(m):
        assert "K (bias random walk) from: the composite fit (GMWM" in f.text, f.consumer
        parsed = exports.consumer(f.consumer).parse(f.text)
        for v in f.values:
            assert parsed[v.name] == pytest.approx(v.value, rel=TOL), (f.consumer, v.name)
    for f in exports.export(allan, "kalibr,px4"):
        assert "K (bias random walk) from: the IEEE-952 fit" in f.text
    assert m.to_dict()["k_from"].startswith("the composite fit")


def test_composite_k_of_a_gauss_markov_bias_is_its_equivalent_walk(axes) -> None:
    """A chosen model with a GM bias: K is K_eq over the fit's horizon, and the file says so."""
    from noisevar.noise_model import fit_imu_model

    allan_g, allan_a, _, comp_a, gyro = axes
    gm = [fit_imu_model(z, 100.0, models=["WN+GM"], horizon=5.0) for z in gyro]
    m = exports.imu_model(allan_g, allan_a, gyro_bias=gm, accel_bias=comp_a)
    fb = [g.filter_bias for g in gm]
    assert m.gyro.K == pytest.approx(max(b.random_walk for b in fb) * math.pi / 180, rel=TOL)
    assert all(b.gm_sigma for b in fb) and m.gyro.K > 0
    assert "gyroscope WN+GM" in m.k_from and "over T = 5, 10 s" in m.k_from


def test_conservative_k_from_the_composite_fit_still_overbounds(axes) -> None:
    from noisevar.noise_model.overbound import NK, overbound

    allan_g, allan_a, comp_g, comp_a, _ = axes
    kw = {"gyro_bias": comp_g, "accel_bias": comp_a}
    best = exports.imu_model(allan_g, allan_a, **kw)
    safe = exports.imu_model(allan_g, allan_a, variant="conservative", **kw)
    bound = max(overbound(a, free=NK).values["K"] for a in allan_g) * math.pi / 180
    assert safe.gyro.K >= best.gyro.K and safe.gyro.K >= bound * (1 - 1e-12)
    assert safe.gyro.factors["K"] == pytest.approx(safe.gyro.K / best.gyro.K, rel=TOL)
    with pytest.raises(NoisevarError, match="1 composite fits for 2 axes"):
        exports.imu_model(allan_g, allan_a, gyro_bias=comp_g[:1])


def test_kalibr_imu_takes_the_same_k_as_the_exports(axes) -> None:
    """The Kalibr block (``kalibr_imu``, CLI --kalibr, the page's imu.yaml) and the exports'
    Kalibr file hold the same K from the same composite fits."""
    from noisevar.noise_model.kalibr import kalibr_imu

    allan_g, allan_a, comp_g, comp_a, _ = axes
    # the same unit for both writers: kalibr_imu writes the fits' unit as it is
    g = [inertial_noise(z, 100.0, unit="rad/s") for z in axes[4]]
    imu = kalibr_imu(g, allan_a, gyro_bias=comp_g, accel_bias=comp_a)
    m = exports.imu_model(g, allan_a, gyro_bias=comp_g, accel_bias=comp_a, accel_unit="m/s^2")
    assert imu.gyroscope_random_walk == pytest.approx(m.gyro.K, rel=TOL)
    assert any(n.startswith("random walks from: the composite fit") for n in imu.notes)
    plain = kalibr_imu(g, allan_a)
    assert plain.gyroscope_random_walk == max(a.rate_random_walk for a in g)
