"""``noisevar imu --export ... --out DIR [--conservative]`` and ``--unit``/``--unit-out`` (§E7)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.noise_model import exports
from noisevar.noise_model.simulate import simulate_inertial

RATE = 100.0


@pytest.fixture(scope="module")
def imu_csv(tmp_path_factory) -> str:
    deg = 180 / math.pi
    cols = {  # gyro in deg/s, accel in g
        "gx": deg
        * simulate_inertial(20_000, RATE, random_walk=2e-4, rate_random_walk=2e-5, seed=1),
        "ax": simulate_inertial(20_000, RATE, random_walk=2e-4, rate_random_walk=1e-5, seed=2),
    }
    path = tmp_path_factory.mktemp("imu") / "imu.csv"
    np.savetxt(
        path,
        np.column_stack(list(cols.values())),
        delimiter=",",
        header=",".join(cols),
        comments="",
    )
    return str(path)


def _error(capsys, argv: list[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("noisevar: error:")
    return err


BASE = [
    "--rate",
    "100",
    "--gyro",
    "gx",
    "--accel",
    "ax",
    "--gyro-unit",
    "deg/s",
    "--accel-unit",
    "g",
]


def test_export_all_then_conservative(capsys, imu_csv, tmp_path) -> None:
    out = tmp_path / "cfg"
    assert main(["imu", imu_csv, *BASE, "--export", "all", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    files = {p.name for p in out.iterdir()}
    assert files == {exports.consumer(k).filename for k in exports.CONSUMERS} | {"report.html"}
    assert f"report (verdict, units, conversions) written to {out / 'report.html'}" in printed
    assert "deg/s/√Hz" in printed and "g/√Hz" in printed  # every number with its unit
    px4 = exports.consumer("px4").parse((out / "px4_ekf2.params").read_text())
    kalibr = exports.consumer("kalibr").parse((out / "imu.yaml").read_text())
    # degrees in, radians out; PX4's value is Kalibr's density at the 100 Hz EKF step
    assert px4["EKF2_GYR_NOISE"] == pytest.approx(kalibr["gyroscope_noise_density"] * 10, 1e-9)
    assert kalibr["gyroscope_noise_density"] == pytest.approx(2e-4, rel=0.1)
    assert kalibr["accelerometer_noise_density"] == pytest.approx(2e-4 * 9.80665, rel=0.1)
    safe = tmp_path / "safe"
    argv = ["imu", imu_csv, *BASE, "--export", "px4,kalibr", "--out", str(safe), "--conservative"]
    assert main([*argv, "--format", "json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert len(report["exports"]) == 2
    factors = report["model"]["gyroscope"]["factors"]
    assert report["model"]["variant"] == "conservative" and min(factors.values()) >= 1.0
    text = (safe / "imu.yaml").read_text()
    assert "CONSERVATIVE" in text
    safe_k = exports.consumer("kalibr").parse(text)
    assert safe_k["gyroscope_random_walk"] >= kalibr["gyroscope_random_walk"]
    # K from the composite fit of the same columns (its bias as one random walk)
    said = "K (bias random walk) from: the composite fit (GMWM"
    assert said in (out / "imu.yaml").read_text() and said in text
    assert report["model"]["k_from"].startswith("the composite fit")
    from noisevar.noise_model import fit_imu_model

    gx = np.loadtxt(imu_csv, delimiter=",", skiprows=1)[:, 0] * math.pi / 180
    k_eq = fit_imu_model(gx, RATE).filter_bias.random_walk
    assert kalibr["gyroscope_random_walk"] == pytest.approx(k_eq, rel=1e-9)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--export", "px4,nope", "--out", "d"], "unknown consumer 'nope'"),
        (["--export", "px4"], "--out DIR"),
        (["--gyro-unit", "furlong/"], "unknown unit 'furlong/'"),
        (["--unit-out", "rad/s"], "--unit-out needs --unit"),
    ],
)
def test_bad_export_or_unit_exit_2(capsys, imu_csv, extra, message) -> None:
    assert message in _error(capsys, ["imu", imu_csv, *BASE[:6], *extra])


def test_unit_out_converts(capsys, imu_csv) -> None:
    argv = ["imu", imu_csv, "--rate", "100", "--columns", "gx", "--format", "json"]
    assert main([*argv, "--unit", "deg/s"]) == 0
    deg = json.loads(capsys.readouterr().out)["columns"]["gx"]["terms"]["random_walk"]
    assert main([*argv, "--unit", "deg/s", "--unit-out", "rad/s"]) == 0
    rad = json.loads(capsys.readouterr().out)["columns"]["gx"]["terms"]["random_walk"]
    assert deg["unit"] == "deg/s/√Hz" and rad["unit"] == "rad/s/√Hz"
    assert rad["value"] == pytest.approx(deg["value"] * math.pi / 180, rel=1e-6)


def test_allan_and_fit_carry_the_unit(capsys, imu_csv) -> None:
    argv = ["allan", imu_csv, "--rate", "100", "--data", "rate", "--column", "gx"]
    assert main([*argv, "--unit", "deg/s"]) == 0
    assert "deviations in deg/s" in capsys.readouterr().out
    assert main([*argv, "--unit", "deg/s", "--unit-out", "rad/s", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["unit"] == "rad/s"
    assert "unknown unit" in _error(capsys, [*argv, "--unit", "parsec/"])
    fit = ["fit", imu_csv, "--column", "ax", "--rate", "100", "--model", "rw", "--unit", "g"]
    assert main(fit) == 0
    out = capsys.readouterr().out
    assert "r " in out and "g²" in out and "u²" not in out


def test_estimate_carries_and_converts_the_unit(capsys, imu_csv) -> None:
    argv = ["estimate", imu_csv, "--column", "gx", "--method", "rice"]
    assert main([*argv, "--unit", "deg/s"]) == 0
    out = capsys.readouterr().out
    assert "(deg/s)²" in out and "std" in out
    assert main([*argv, "--unit", "deg/s", "--format", "json"]) == 0
    deg = json.loads(capsys.readouterr().out)
    assert main([*argv, "--unit", "deg/s", "--unit-out", "rad/s", "--format", "json"]) == 0
    rad = json.loads(capsys.readouterr().out)
    assert rad["unit"] == "rad/s"
    assert rad["variance"] == pytest.approx(deg["variance"] * (math.pi / 180) ** 2, rel=1e-9)
    assert "unknown unit" in _error(capsys, [*argv, "--unit", "lightyear/"])


def test_gnss_columns_give_px4_and_ardupilot_their_stds(capsys, imu_csv, tmp_path) -> None:
    rng = np.random.default_rng(5)
    t = np.arange(3000) / 5.0
    pos = 0.3 * t + rng.normal(0, 1.5, t.size)  # m, a slow drift plus white noise
    gnss = tmp_path / "gnss.csv"
    np.savetxt(gnss, np.column_stack([t, pos]), delimiter=",", header="time,north", comments="")
    out = tmp_path / "cfg"
    argv = [
        "imu",
        imu_csv,
        *BASE,
        "--export",
        "px4,ardupilot",
        "--out",
        str(out),
        "--gnss-file",
        str(gnss),
        "--gnss-pos",
        "north",
    ]
    assert main(argv) == 0
    px4 = exports.consumer("px4").parse((out / "px4_ekf2.params").read_text())
    ap = exports.consumer("ardupilot").parse((out / "ardupilot_ekf3.param").read_text())  # no log
    assert px4["EKF2_GPS_P_NOISE"] == pytest.approx(1.5, rel=0.1)
    assert ap["EK3_POSNE_M_NSE"] == px4["EKF2_GPS_P_NOISE"]
    assert "EKF2_GPS_V_NOISE" not in px4


def test_report_holds_the_verdict_units_and_conversions(capsys, imu_csv, tmp_path) -> None:
    """Issue 27 item 5: report.html beside the files: the verdict, each exported value with
    its unit, its kind and its conversion line, the pint conversions; every string escaped."""
    import html

    out = tmp_path / "cfg"
    argv = ["imu", imu_csv, *BASE, "--export", "px4,vins", "--out", str(out), "--format", "json"]
    assert main(argv) == 0
    said = json.loads(capsys.readouterr().out)
    text = (out / "report.html").read_text(encoding="utf-8")
    assert said["report"] == str(out / "report.html")
    assert text.count("Verdict, ") == 2 and "white Gaussian noise" in text
    assert "(deg/s)²" in text  # the record's answer in the unit the axis was read in
    assert html.escape("converted from deg/s to rad/s (x0.01745329252, by pint)") in text
    units = {"EKF2_GYR_NOISE": "rad/s", "EKF2_ACC_NOISE": "m/s^2", "gyr_n": "rad/s"}
    for key in ("px4", "vins"):
        f = exports.consumer(key)
        for name in f.parse((out / f.filename).read_text()):
            row = f"<td>{name}</td><td>"
            assert row in text, name
            cells = text.split(row, 1)[1].split("</tr>", 1)[0].split("</td><td>")
            assert len(cells) == 4 and ("discrete at" in cells[2] or "density" in cells[2])
            assert name not in units or cells[1] == html.escape(units[name])
            assert "sqrt(" in cells[3] or "as fitted" in cells[3], cells  # the conversion line
    assert "<script" in text and "Allan deviation of gx" in text  # the fits, drawn
    skip = tmp_path / "no_report"
    assert main([*argv[:-4], "--out", str(skip), "--no-report", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["report"] is None
    assert not (skip / "report.html").exists() and (skip / "px4_ekf2.params").exists()


def test_every_consumer_file_says_each_columns_verdict(capsys, imu_csv, tmp_path) -> None:
    """The verdict is in the exports (issue 28): each file's header, with --no-report too."""
    from noisevar import estimate

    out = tmp_path / "verdicts"
    args = ["imu", imu_csv, *BASE, "--export", "all", "--out", str(out), "--no-report"]
    assert main(args) == 0
    capsys.readouterr()
    table = np.loadtxt(imu_csv, delimiter=",", skiprows=1)
    gx = estimate(table[:, 0] * math.pi / 180).diagnostics.verdict.split(":")[0]
    for key in exports.CONSUMERS:
        text = (out / exports.consumer(key).filename).read_text(encoding="utf-8")
        assert "verdict, column gx: " + gx in text and "verdict, column ax: " in text, key
        exports.consumer(key).parse(text)  # still the consumer's own format
