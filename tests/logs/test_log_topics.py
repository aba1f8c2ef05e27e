"""Several topics of one log into one IMU model (issue 27): PX4's gyroscope and
accelerometer FIFOs at their own rates (noisevar/io/logs/record.py, ``noisevar imu --topic A
--topic B``), on a ULog written by pyulog's own writer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from logfiles import write_ulog_imu_fifos

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_topics

PX4 = Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg"
GYRO, ACCEL = "sensor_gyro_fifo", "sensor_accel_fifo"


@pytest.fixture(scope="module")
def fifo_log(tmp_path_factory) -> tuple[Path, dict[str, float]]:
    """Gyroscope FIFO at 800 Hz, accelerometer FIFO at 400 Hz, 40 s, known N."""
    path = tmp_path_factory.mktemp("fifos") / "two_fifos.ulg"
    return path, write_ulog_imu_fifos(path, PX4, seconds=40.0, rates=(800.0, 400.0), seed=7)


def test_each_column_keeps_its_topic_time_base(fifo_log):
    path, _ = fifo_log
    rec = load_topics(path, [GYRO, ACCEL])
    assert rec.columns == [f"{t}/{a}" for t in (GYRO, ACCEL) for a in "xyz"]  # x y z clash
    g, a = rec.column(f"{GYRO}/x"), rec.column(f"{ACCEL}/z")
    assert (g.rate, a.rate) == (pytest.approx(800.0), pytest.approx(400.0))
    assert (g.values.size, a.values.size) == (32_000, 16_000)  # nothing resampled
    assert g.times.size == g.values.size and a.times.size == a.values.size
    assert (g.unit, a.unit) == ("rad/s", "m/s**2")
    # the samples are the topic's own, bit for bit
    one = load_topics(path, [ACCEL]).column("z")
    np.testing.assert_array_equal(one.values, a.values)
    np.testing.assert_array_equal(one.times, a.times)
    # a field one topic has keeps its bare name; by topic/field too
    mixed = load_topics(path, [GYRO, "sensor_combined"])
    assert "x" in mixed.columns and "gyro_rad[0]" in mixed.columns
    assert mixed.resolve(f"{GYRO}/x") == mixed.resolve("x") == (GYRO, "x")


@pytest.mark.parametrize(
    ("topics", "column", "said"),
    [
        ([GYRO, ACCEL], "x", f"is in topics {GYRO}, {ACCEL}: name it {GYRO}/x or {ACCEL}/x"),
        ([GYRO, ACCEL], f"{GYRO}/w", f"no column '{GYRO}/w' in topics {GYRO}, {ACCEL}"),
        ([GYRO, "no_such_topic"], "x", "no topic 'no_such_topic' in"),
        ([], "x", "no topic of"),
    ],
)
def test_bad_names_are_one_error(fifo_log, topics, column, said):
    with pytest.raises(NoisevarError) as err:
        load_topics(fifo_log[0], topics).column(column)
    assert said in str(err.value)


def test_cli_two_topics_to_a_px4_file_with_each_rate(fifo_log, tmp_path, capsys):
    """gyro 800 Hz, accel 400 Hz of known N: each N within 5 %; PX4 gets both sensors."""
    path, truth = fifo_log
    gyro = [f"{GYRO}/{a}" for a in "xyz"]
    accel = [f"{ACCEL}/{a}" for a in "xyz"]
    argv = ["imu", str(path), "--topic", GYRO, "--topic", ACCEL, "--gyro", *gyro]
    argv += ["--accel", *accel, "--export", "px4", "--out", str(tmp_path), "--no-report"]
    assert main([*argv, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for cols, topic, rate in ((gyro, GYRO, 800.0), (accel, ACCEL, 400.0)):
        for c in cols:
            fit = out["columns"][c]
            assert fit["rate"] == pytest.approx(rate)
            assert fit["terms"]["random_walk"]["value"] == pytest.approx(truth[topic], rel=0.05)
    text = (tmp_path / "px4_ekf2.params").read_text()
    values = {r.split("\t")[2]: float(r.split("\t")[3]) for r in text.splitlines() if r[:1] == "1"}
    ekf_rate = 100.0  # 1/EKF2_PREDICT_US, as the file says
    assert "1/EKF2_PREDICT_US = 100 Hz" in text  # the template ULog says v1.11: 10 ms
    model = out["model"]
    assert values["EKF2_GYR_NOISE"] == pytest.approx(model["gyroscope"]["N"] * ekf_rate**0.5)
    assert values["EKF2_ACC_NOISE"] == pytest.approx(model["accelerometer"]["N"] * ekf_rate**0.5)
    assert model["gyroscope"]["N"] == pytest.approx(truth[GYRO], rel=0.05)
    assert model["accelerometer"]["N"] == pytest.approx(truth[ACCEL], rel=0.05)
    assert "the accelerometer at 400 Hz" in text  # the two rates are said


@pytest.mark.parametrize(
    ("extra", "said"),
    [
        (["--topic", GYRO, "--topic", "nope", "--columns", "x"], "no topic 'nope'"),
        (["--topic", GYRO, "--topic", ACCEL, "--gyro", "x"], "name it sensor_gyro_fifo/x or"),
        (["--topic", GYRO, "--topic", ACCEL, "--accel", "w"], "no column 'w' in topics"),
        (["--topic", GYRO, "--topic", ACCEL, "--rate", "100"], "--rate sets one rate"),
    ],
)
def test_cli_bad_combinations_exit_2_with_one_line(fifo_log, capsys, extra, said):
    assert main(["imu", str(fifo_log[0]), *extra]) == 2
    err = capsys.readouterr().err
    assert said in err and err.count("\n") == 1 and "Traceback" not in err


def test_cli_one_topic_unchanged(fifo_log, capsys):
    """One --topic: the topic's fields by their own names, as before."""
    argv = ["imu", str(fifo_log[0]), "--topic", ACCEL, "--columns", "x", "--format", "json"]
    assert main(argv) == 0
    assert list(json.loads(capsys.readouterr().out)["columns"]) == ["x"]


def test_one_imu_rate_stated_with_a_note_when_the_sensors_differ():
    """Kalibr and every consumer state the gyroscope's rate and say the accelerometer's."""
    from noisevar.noise_model import exports, inertial_noise
    from noisevar.noise_model.kalibr import kalibr_imu

    rng = np.random.default_rng(5)
    g800 = inertial_noise(rng.normal(0, 0.01, 4_000), 800.0, unit="rad/s")
    g400 = inertial_noise(rng.normal(0, 0.01, 2_000), 400.0, unit="rad/s")
    a400 = inertial_noise(rng.normal(0, 0.05, 2_000), 400.0, unit="m/s^2")
    imu = kalibr_imu(g800, a400)
    model = exports.imu_model(g800, a400)
    assert imu.update_rate == model.rate == 800.0
    said = "the gyroscope was sampled at 800 Hz, the accelerometer at 400 Hz"
    assert any(said in n for n in imu.notes) and any(said in n for n in model.notes)
    assert not any("sampled at" in n for n in exports.imu_model(g400, a400).notes)
    with pytest.raises(NoisevarError, match="gyroscope axes were fitted at different rates"):
        exports.imu_model([g800, g400], a400)


def _same_tables(many: dict, path: Path) -> None:
    from noisevar.io import load_table

    for topic, tab in many.items():
        one = load_table(path, topic=topic)  # the topic read on its own, as before
        assert list(tab.columns) == list(one.columns) and tab.units == one.units
        assert (tab.kind, tab.time_column, tab.notes) == (one.kind, one.time_column, one.notes)
        assert tab.sample_period == one.sample_period
        for c in one.columns:
            np.testing.assert_array_equal(tab.columns[c], one.columns[c])


@pytest.mark.parametrize(
    "topics",
    [
        [GYRO, ACCEL],  # pyulog's writer, FIFO topics unpacked
        ["sensor_combined", "sensor_accel/1", "sensor_gyro/0", "vehicle_gps_position"],  # PX4's
    ],
)
def test_several_topics_from_one_parse_equal_each_read_alone(fifo_log, topics, monkeypatch):
    """load_topics parses a ULog once for all its topics; each table equals the one read alone."""
    import pyulog

    from noisevar.io.load import load_log_tables

    path = fifo_log[0] if topics[0] == GYRO else PX4
    parses = []
    real = pyulog.ULog.__init__

    def counted(self, *args, **kwargs):
        parses.append(kwargs.get("message_name_filter_list"))
        real(self, *args, **kwargs)

    monkeypatch.setattr(pyulog.ULog, "__init__", counted)
    many = load_log_tables(path, topics)
    assert parses == [list(dict.fromkeys(t.partition("/")[0] for t in topics))]  # one parse
    assert list(many) == topics
    monkeypatch.setattr(pyulog.ULog, "__init__", real)
    _same_tables(many, path)
    rec = load_topics(path, topics)
    assert rec.columns == combine_names(many)
    with open(path, "rb") as fh:  # an upload's bytes: the same tables
        _same_tables(load_log_tables(fh.read(), topics, path.name), path)


def combine_names(tables: dict) -> list[str]:
    from noisevar.io.logs.record import combine_topics

    return combine_topics("x", tables).columns


@pytest.mark.parametrize(
    ("topics", "said"),
    [
        (["sensor_combined", "sensor_accel"], "no topic 'sensor_accel' in"),  # 3 instances
        (["sensor_combined", "sensor_combined/1"], "no topic 'sensor_combined/1' in"),
        (["sensor_combined", "sensor_accel/x"], "no topic 'sensor_accel/x' in"),
        (["sensor_combined", GYRO], f"no topic '{GYRO}' in"),
    ],
)
def test_one_parse_refuses_what_one_topic_refuses(topics, said):
    with pytest.raises(NoisevarError, match=said) as err:
        load_topics(PX4, topics)
    assert "topics:" in str(err.value)  # the listing, as load_log gives it


BIN = Path(__file__).resolve().parents[1] / "data" / "ardupilot_pymavlink_test.BIN"


def test_dataflash_topics_from_one_opening_equal_each_read_alone(monkeypatch):
    """A DataFlash log is opened (and indexed by pymavlink) once for several messages."""
    from noisevar.io.load import load_log_tables
    from noisevar.io.logs import dataflash

    opened = []
    real = dataflash._open

    def counted(path):
        opened.append(path)
        return real(path)

    topics = ["IMU", "IMU2", "BARO", "GPS"]
    monkeypatch.setattr(dataflash, "_open", counted)
    many = load_log_tables(BIN, topics)
    assert len(opened) == 1 and list(many) == topics
    monkeypatch.setattr(dataflash, "_open", real)
    _same_tables(many, BIN)
    with pytest.raises(NoisevarError, match="no topic 'IMU9' in .*; topics: AETR"):
        load_log_tables(BIN, ["IMU", "IMU9"])
