"""``noisevar topics LOG`` and ``--topic`` on the loading commands; a synthetic IMU written into
a ROS 2 bag gives back its white-noise density N and rate random walk K."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from logfiles import imu_values, write_bag, write_dataflash

import noisevar
from noisevar.cli import main
from noisevar.io import load_table

PX4 = Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    return write_bag(tmp_path_factory.mktemp("bag") / "b", imu_values(800), "mcap")


def test_topics_table_and_json(capsys, bag):
    code, out, err = run(capsys, "topics", bag)
    assert code == 0 and not err
    assert "ROS bag" in out and "/imu" in out and "sensor_msgs/msg/Imu" in out
    assert "angular_velocity.x [rad/s]" in out and "linear_acceleration.z [m/s**2]" in out
    code, out, _ = run(capsys, "topics", bag, "--json")
    data = json.loads(out)
    assert code == 0 and data["format"] == "rosbag"
    imu = next(t for t in data["topics"] if t["topic"] == "/imu")
    assert imu["count"] == 800 and imu["rate_hz"] == pytest.approx(400, rel=0.01)
    assert imu["units"]["angular_velocity.y"] == "rad/s"


def test_topics_of_each_format(capsys, tmp_path):
    code, out, _ = run(capsys, "topics", PX4, "--json")
    assert code == 0 and json.loads(out)["format"] == "ulog"
    code, out, _ = run(capsys, "topics", write_dataflash(tmp_path / "x.bin", imu_values(20)))
    assert code == 0 and "IMU[1]" in out and "GyrZ [rad/s]" in out


def test_topics_refuses_what_is_not_a_log(capsys, tmp_path):
    csv = tmp_path / "a.csv"
    csv.write_text("t,x\n0,1\n1,2\n")
    code, _, err = run(capsys, "topics", csv)
    assert code == 2 and "not a log noisevar reads" in err and len(err.splitlines()) == 1
    code, _, err = run(capsys, "topics", tmp_path / "missing.bag")
    assert code == 2 and len(err.splitlines()) == 1


def test_estimate_with_topic_and_column(capsys, bag):
    z = load_table(bag, topic="/imu").columns["angular_velocity.y"]
    code, out, err = run(
        capsys,
        "estimate",
        bag,
        "--topic",
        "/imu",
        "--column",
        "angular_velocity.y",
        "--format",
        "json",
    )
    assert code == 0, err
    got = json.loads(out)
    assert got["variance"] == pytest.approx(noisevar.estimate(z).variance, rel=1e-9)
    code, out, _ = run(
        capsys,
        "estimate",
        bag,
        "--topic",
        "/imu",
        "--columns",
        "angular_velocity.x,linear_acceleration.z",
        "--format",
        "csv",
    )
    assert code == 0 and "linear_acceleration.z" in out


@pytest.mark.parametrize("command", ["estimate", "allan", "imu", "fit", "scan-h"])
def test_unknown_topic_exit_2_lists_topics(capsys, bag, command):
    extra = ["--rate", "400"] if command == "fit" else []
    code, out, err = run(capsys, command, bag, "--topic", "/gyro", *extra)
    assert code == 2 and not out
    assert len(err.splitlines()) == 1
    assert "no topic '/gyro'" in err and "topics: /imu (sensor_msgs/msg/Imu, 800)" in err


def test_allan_and_imu_read_the_logs_rate(capsys, bag):
    code, out, err = run(
        capsys,
        "allan",
        bag,
        "--topic",
        "/imu",
        "--column",
        "angular_velocity.x",
        "--data",
        "rate",
        "--format",
        "json",
    )
    assert code == 0, err
    assert json.loads(out)["rate"] == pytest.approx(400.0)
    code, out, err = run(
        capsys, "imu", bag, "--topic", "/imu", "--columns", "angular_velocity.x", "--format", "json"
    )
    assert code == 0, err


def test_fit_reads_the_logs_rate(capsys, bag):
    argv = ["fit", bag, "--topic", "/imu", "--column", "angular_velocity.x", "--model", "rw"]
    code, out, err = run(capsys, *argv, "--format", "json")
    assert code == 0, err
    assert json.loads(out)["rate"] == pytest.approx(400.0, rel=1e-6)


def test_topic_on_a_table_is_refused(capsys, tmp_path):
    csv = tmp_path / "a.csv"
    csv.write_text("t,x\n0,1\n1,2\n2,1.5\n")
    code, _, err = run(capsys, "estimate", csv, "--topic", "/imu")
    assert code == 2 and "not a log" in err


def test_synthetic_imu_in_a_bag_gives_back_n_and_k(tmp_path):
    """White rate noise of density N plus a rate random walk K, three gyro axes written as
    sensor_msgs/Imu into a ROS 2 mcap bag, read back with the bag's timestamps: N within 3 %,
    K within 20 % (noisevar.inertial_noise, docs/algorithms.md §E4)."""
    fs, n, dens_n, dens_k = 100.0, 100_000, 0.01, 0.01
    rng = np.random.default_rng(0)
    white = dens_n * np.sqrt(fs) * rng.normal(size=(n, 3))
    walk = np.cumsum(dens_k / np.sqrt(fs) * rng.normal(size=(n, 3)), axis=0)
    z = np.column_stack([white + walk, np.zeros((n, 3))])
    bag = write_bag(tmp_path / "imu", z, "mcap", rate=fs, extra=False)
    axes = ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"]
    tab = load_table(bag, topic="/imu", fields=axes)
    assert tab.sample_period == pytest.approx(1 / fs) and tab.units[axes[0]] == "rad/s"
    fits = noisevar.inertial_noise(
        np.stack([tab.columns[a] for a in axes]), 1 / tab.sample_period, unit="rad/s"
    )
    for fit in fits:
        terms = {t.symbol: t.value for t in fit.terms}
        assert terms["N"] == pytest.approx(dens_n, rel=0.03)
        assert terms["K"] == pytest.approx(dens_k, rel=0.20)


def test_the_units_a_bag_declares_reach_the_terms(capsys, bag):
    # sensor_msgs/Imu says rad/s and m/s^2: with no --unit, the terms carry them
    code, out, err = run(
        capsys, "imu", bag, "--topic", "/imu", "--columns", "angular_velocity.x",
        "linear_acceleration.z", "--format", "json",
    )  # fmt: skip
    assert code == 0, err
    cols = json.loads(out)["columns"]
    assert cols["angular_velocity.x"]["unit"] == "rad/s"
    assert cols["angular_velocity.x"]["terms"]["random_walk"]["unit"] == "rad/s/√Hz"
    assert cols["linear_acceleration.z"]["unit"].replace(" ", "") in ("m/s**2", "m/s²", "m/s^2")
    # the user's --unit still wins
    code, out, err = run(
        capsys, "imu", bag, "--topic", "/imu", "--columns", "angular_velocity.x",
        "--unit", "deg/s", "--format", "json",
    )  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["columns"]["angular_velocity.x"]["unit"] == "deg/s"


def test_batch_of_bags_with_a_topic_and_resume(capsys, tmp_path):
    from noisevar.batch import batch

    bags = [write_bag(tmp_path / f"u{i}.bag", imu_values(400, seed=i), "ros1") for i in (1, 2)]
    cols = "angular_velocity.x,linear_acceleration.z"
    out = tmp_path / "noise.csv"
    argv = ["batch", *bags, "--topic", "/imu", "--columns", cols, "--out", out, "--quiet"]
    code, _, err = run(capsys, *argv)
    assert code == 0, err
    frame = pd.read_csv(out)
    assert len(frame) == 4 and frame["error"].isna().all()
    assert set(frame["sample_rate_hz"]) == {400.0}
    table = load_table(bags[1], topic="/imu")
    one = noisevar.estimate(table.columns["linear_acceleration.z"])
    row = frame[(frame["file"] == str(bags[1])) & (frame["channel"] == "linear_acceleration.z")]
    assert row["variance"].iat[0] == pytest.approx(one.variance, rel=1e-12)
    todo = []  # the files each run has to do (progress's total)
    again = dict(columns=cols, out=out, progress=lambda k, n: todo.append(n))
    batch([str(b) for b in bags], topic="/imu", **again)
    assert max(todo, default=0) == 0  # the same topic: every file resumed
    other = batch([str(b) for b in bags], topic="/level", **again)
    assert max(todo) == 2 and other["error"].notna().all()  # another topic: both redone
    plain = batch([str(bags[0])], progress=False)  # no topic: the bag holds two
    assert "holds several topics" in plain["error"].iat[0]


def test_a_logs_degc_field_keeps_its_unit(capsys):
    """The log declares degC: the CLI shows it and converts it (main printed 'u' and refused
    ``--unit degC`` with an OffsetUnitCalculusError)."""
    args = (PX4, "--topic", "vehicle_air_data", "--column", "baro_temp_celcius")
    code, out, _ = run(capsys, "estimate", *args, "--format", "json")
    assert code == 0 and json.loads(out)["unit"] == "degC"
    r = json.loads(out)["variance"]
    code, out, _ = run(capsys, "estimate", *args, "--unit-out", "degF", "--format", "json")
    assert code == 0 and json.loads(out)["variance"] == pytest.approx(1.8**2 * r, rel=1e-9)
    code, out, err = run(capsys, "estimate", *args, "--unit", "degC", "--format", "json")
    assert code == 0, err


def test_ulog_gps_altitude_in_mm_converts_to_m(capsys):
    args = (PX4, "--topic", "vehicle_gps_position", "--column", "alt", "--format", "json")
    code, out, _ = run(capsys, "estimate", *args)
    mm = json.loads(out)
    code, out, _ = run(capsys, "estimate", *args, "--unit-out", "m")
    m = json.loads(out)
    assert code == 0 and (mm["unit"], m["unit"]) == ("mm", "m")
    assert m["variance"] == pytest.approx(1e-6 * mm["variance"], rel=1e-9)


def test_topics_takes_format_json_as_every_command(capsys):
    """``--format json`` as on estimate/allan/imu/fit (main: exit 2, unrecognized)."""
    code, out, err = run(capsys, "topics", PX4, "--format", "json")
    assert code == 0, err
    gps = next(t for t in json.loads(out)["topics"] if t["topic"] == "vehicle_gps_position")
    assert gps["units"]["alt"] == "mm"


def test_fit_takes_the_logs_unit_as_estimate_does(capsys):
    """``fit`` read the log's field as unitless ('u') and refused ``--unit-out`` ('needs
    --unit'), where estimate and allan take the unit the log declares (gauss here)."""
    args = (PX4, "--topic", "vehicle_magnetometer", "--column", "magnetometer_ga[0]")
    code, out, err = run(capsys, "fit", *args, "--format", "json")
    assert code == 0, err
    gauss = json.loads(out)
    code, out, err = run(capsys, "fit", *args, "--unit-out", "uT", "--format", "json")
    assert code == 0, err
    ut = json.loads(out)
    assert (gauss["unit"], ut["unit"]) == ("gauss", "uT")
    assert ut["r"] == pytest.approx(1e4 * gauss["r"], rel=1e-6)
