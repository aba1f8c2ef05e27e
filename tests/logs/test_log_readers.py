"""Log readers (noisevar.io.logs): each format written by its own writer, read back exactly,
with the log's timestamps; a real PX4 log nobody here wrote; bad logs give one clear error."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from logfiles import RATE, T0_NS, imu_values, level, write_bag, write_dataflash

from noisevar.errors import NoisevarError
from noisevar.io import load_table
from noisevar.io.logs import list_topics, log_suffixes, read_topic, reader_for

DATA = Path(__file__).resolve().parents[1] / "data"
PX4 = DATA / "px4_sample_log_small.ulg"
AXES = ("angular_velocity.x", "angular_velocity.y", "angular_velocity.z")


@pytest.mark.parametrize("kind", ["ros1", "mcap", "sqlite3"])
def test_bag_round_trip(tmp_path, kind):
    z = imu_values(300)
    path = write_bag(tmp_path / ("b.bag" if kind == "ros1" else "b"), z, kind)
    topics = {t.name: t for t in list_topics(path)}
    imu = topics["/imu"]
    assert imu.message == "sensor_msgs/msg/Imu" and imu.count == 300
    assert imu.rate == pytest.approx(RATE, rel=0.01)
    assert set(AXES) <= set(imu.fields) and "linear_acceleration.z" in imu.fields
    assert imu.units["angular_velocity.x"] == "rad/s"
    assert imu.units["linear_acceleration.y"] == "m/s**2"
    assert "orientation.w" not in imu.units  # a quaternion has no unit
    tab = load_table(path, topic="/imu")
    assert tab.kind == "rosbag" and tab.time_column == "time"
    np.testing.assert_array_equal(tab.columns["angular_velocity.y"], z[:, 1])
    np.testing.assert_array_equal(tab.columns["linear_acceleration.z"], z[:, 5])
    # header.stamp, from the first message: exactly i / rate
    np.testing.assert_allclose(tab.columns["time"], np.arange(300) / RATE, atol=1e-9)
    assert tab.sample_period == pytest.approx(1 / RATE)
    assert tab.units["angular_velocity.z"] == "rad/s"


def test_single_mcap_file_upload_and_array_element(tmp_path):
    z = imu_values(50)
    bag = write_bag(tmp_path / "b", z, "mcap")
    mcap = next(bag.glob("*.mcap"))
    tab = load_table(
        mcap.read_bytes(),
        "upload.mcap",
        topic="/imu",
        fields=["angular_velocity.x", "angular_velocity_covariance.4"],
    )
    assert tab.data_columns == ["angular_velocity.x", "angular_velocity_covariance.4"]
    np.testing.assert_array_equal(tab.columns["angular_velocity.x"], z[:, 0])
    assert np.all(tab.columns["angular_velocity_covariance.4"] == 0.5)
    with pytest.raises(NoisevarError, match="no numeric field 'angular_velocity.w'"):
        load_table(mcap, topic="/imu", fields=["angular_velocity.w"])


@pytest.mark.parametrize("kind", ["ros1", "mcap"])
def test_flat_decoder_equals_rosbags_deserialiser(tmp_path, kind, monkeypatch):
    """The direct read of fixed-layout messages gives what rosbags' deserialiser gives, for
    every frame_id length (every alignment of the CDR body), fields in any order."""
    from noisevar.io.logs import rosbag

    z = imu_values(60)
    bag = write_bag(tmp_path / ("b.bag" if kind == "ros1" else "b"), z, kind, frames=True)
    fields = ["linear_acceleration.z", "orientation_covariance.4", "angular_velocity.x"]
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if kind == "ros1" else Stores.ROS2_HUMBLE)
    assert rosbag.FlatDecoder.of(store, "sensor_msgs/msg/Imu", fields, kind == "ros1")
    fast = load_table(bag, topic="/imu", fields=fields)
    monkeypatch.setattr(rosbag.FlatDecoder, "of", classmethod(lambda cls, *a, **k: None))
    slow = load_table(bag, topic="/imu", fields=fields)
    for c in ["time", *fields]:
        np.testing.assert_array_equal(fast.columns[c], slow.columns[c])
    np.testing.assert_array_equal(fast.columns["angular_velocity.x"], z[:, 0])


def test_topic_without_header_uses_record_time(tmp_path):
    bag = write_bag(tmp_path / "b", imu_values(40), "mcap")
    tab = load_table(bag, topic="/level")
    np.testing.assert_array_equal(tab.columns["data"], [level(i) for i in range(0, 40, 4)])
    np.testing.assert_allclose(tab.columns["time"], np.arange(0, 40, 4) / RATE, atol=1e-9)


def test_bag_gaps_and_jitter_reach_the_table(tmp_path):
    """The log's own timestamps are kept: a dropout shows in the notes and the estimate."""
    import noisevar

    n = 800
    ns = T0_NS + np.round(np.arange(n) * 1e9 / RATE).astype(np.int64)
    ns[400:] += 50_000_000  # 50 ms of lost messages
    z = imu_values(n)
    tab = load_table(write_bag(tmp_path / "g", z, "mcap", stamps_ns=ns, extra=False), topic="/imu")
    assert any("not uniform" in note for note in tab.notes)
    est = noisevar.estimate(tab.columns["angular_velocity.x"], t=tab.time())
    assert est.diagnostics.flags["gaps"]


def test_ulog_real_sample():
    """PX4's own sample log (pyulog's tests, BSD-3; tests/data/README.md)."""
    topics = {t.name: t for t in list_topics(PX4)}
    sc = topics["sensor_combined"]
    assert sc.count == 1298 and "gyro_rad[0]" in sc.fields
    assert sc.units["gyro_rad[2]"] == "rad/s" and sc.units["accelerometer_m_s2[0]"] == "m/s**2"
    assert {"sensor_gyro/0", "sensor_gyro/1", "vehicle_gps_position"} <= set(topics)
    tab = load_table(PX4, topic="sensor_combined")
    assert tab.kind == "ulog" and tab.n_rows == 1298
    t = tab.time()
    assert np.all(np.diff(t) > 0) and 20 < t[0] < 21  # seconds since boot
    assert tab.sample_period == pytest.approx(0.004888, rel=1e-3)  # ~200 Hz
    assert np.all(np.abs(tab.columns["accelerometer_m_s2[2]"]) < 40)  # m/s^2, gravity near z
    gyro = load_table(PX4, topic="sensor_gyro/1", fields=["x"])
    assert gyro.data_columns == ["x"] and gyro.n_rows == 6


@pytest.mark.parametrize("name", ["x.bin", "x.log"])
def test_dataflash(tmp_path, name):
    z = imu_values(200)
    path = write_dataflash(tmp_path / "x.bin", z)
    if name == "x.log":  # the same bytes under the NMEA-shared suffix: claimed by content
        path = path.rename(tmp_path / name)
    topics = {t.name: t for t in list_topics(path)}
    assert topics["IMU[0]"].count == 200 and topics["IMU[1]"].rate == pytest.approx(RATE)
    assert topics["IMU[0]"].units == {
        **dict.fromkeys(("GyrX", "GyrY", "GyrZ"), "rad/s"),
        **dict.fromkeys(("AccX", "AccY", "AccZ"), "m/s**2"),
    }
    tab = load_table(path, topic="IMU[1]")
    assert tab.kind == "dataflash"
    np.testing.assert_allclose(tab.columns["AccY"], z[:, 4] + 1, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(tab.time(), 1 + np.arange(200) / RATE, atol=1e-6)


def test_dataflash_corrupt_header_is_a_note_not_a_print(tmp_path, capfd):
    """pymavlink reports skipped bytes by printing: the reader keeps them for the notes."""
    raw = bytearray(write_dataflash(tmp_path / "x.bin", imu_values(300)).read_bytes())
    raw[4542] = 0x1D  # the second header byte of a message
    bad = tmp_path / "bad.bin"
    bad.write_bytes(bytes(raw))
    tab = load_table(bad, topic="IMU[0]")
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    assert tab.n_rows >= 299
    assert any("reported" in n and "bad header" in n for n in tab.notes), tab.notes


def test_dataflash_text_log(tmp_path):
    """The text form (mavlogdump's and Mission Planner's .log): FMT lines, then records."""
    z = imu_values(100)
    lines = [
        "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns",
        "FMT, 132, 23, BARO, Qff, TimeUS,Press,Temp",
        *(
            f"BARO, {1_000_000 + i * 20_000}, {float(101325 + z[i, 0])!r}, {float(20 + z[i, 1])!r}"
            for i in range(100)
        ),
    ]
    path = tmp_path / "flight.log"
    path.write_text("\n".join(lines) + "\n")
    (info,) = list_topics(path)
    assert (info.name, info.count, info.fields) == ("BARO", 100, ("Press", "Temp"))
    tab = load_table(path, topic="BARO")
    np.testing.assert_allclose(tab.columns["Press"], 101325 + z[:, 0], rtol=1e-12)
    assert tab.sample_period == pytest.approx(0.02) and tab.time()[0] == pytest.approx(1.0)


def test_parquet_streamed_by_row_group(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    n = 1000
    z = imu_values(n)[:, 0]
    t = 5 + np.arange(n) / 100.0
    schema = pa.schema(
        [
            pa.field("time", pa.float64()),
            pa.field("gyro", pa.float64(), metadata={"unit": "deg/s"}),
            pa.field("count", pa.int32()),
            pa.field("label", pa.string()),
        ]
    )
    table = pa.table(
        {"time": t, "gyro": z, "count": np.arange(n, dtype=np.int32), "label": ["a"] * n},
        schema=schema,
    )
    path = tmp_path / "d.parquet"
    pq.write_table(table, path, row_group_size=128)
    (info,) = list_topics(path)
    assert info.name == "table" and info.fields == ("gyro", "count")
    assert info.units == {"gyro": "deg/s"} and info.rate == pytest.approx(100.0)
    chunks = list(read_topic(path, "table", ["gyro"]))
    assert len(chunks) >= 1 and sum(c.times.size for c in chunks) == n
    tab = load_table(path)  # one topic: no --topic needed
    np.testing.assert_array_equal(tab.columns["gyro"], z)
    np.testing.assert_array_equal(tab.time(), t)
    assert tab.units == {"gyro": "deg/s"} and tab.sample_period == pytest.approx(0.01)


def test_hdf5_tables_groups_and_arrays(tmp_path):
    import h5py

    n = 500
    z = imu_values(n)
    path = tmp_path / "d.h5"
    with h5py.File(path, "w") as f:
        rec = np.zeros(n, dtype=[("timestamp", "f8"), ("gx", "f4"), ("gy", "f8")])
        rec["timestamp"], rec["gx"], rec["gy"] = np.arange(n) / 50.0, z[:, 0], z[:, 1]
        f["imu"] = rec
        g = f.create_group("baro")
        g["t"] = np.arange(n) / 10.0
        g["pressure"] = z[:, 2]
        g["pressure"].attrs["units"] = "Pa"
        f["raw"] = z[:, :3]
        other = tmp_path / "other.h5"
        with h5py.File(other, "w") as o:
            o["secret"] = np.ones(n)
        f["linked"] = h5py.ExternalLink(str(other), "/secret")
    topics = {t.name: t for t in list_topics(path)}
    assert set(topics) == {"/imu", "/baro", "/raw"}  # the external link is not followed
    assert topics["/imu"].fields == ("gx", "gy") and topics["/imu"].rate == pytest.approx(50.0)
    assert topics["/baro"].units == {"pressure": "Pa"}
    tab = load_table(path, topic="/baro")
    np.testing.assert_array_equal(tab.columns["pressure"], z[:, 2])
    assert tab.sample_period == pytest.approx(0.1) and tab.units == {"pressure": "Pa"}
    raw = load_table(path, topic="/raw")
    assert raw.data_columns == ["col0", "col1", "col2"] and raw.time_column is None
    np.testing.assert_allclose(load_table(path, topic="/imu").columns["gx"], z[:, 0], rtol=1e-6)


def test_unknown_topic_lists_the_topics(tmp_path):
    bag = write_bag(tmp_path / "b", imu_values(10), "mcap")
    with pytest.raises(NoisevarError, match=r"no topic '/gyro'.*topics: /imu \(sensor_msgs"):
        load_table(bag, topic="/gyro")
    with pytest.raises(NoisevarError, match="holds several topics: choose one"):
        load_table(bag)
    csv = tmp_path / "a.csv"
    csv.write_text("t,x\n0,1\n1,2\n")
    with pytest.raises(NoisevarError, match="not a log"):
        load_table(csv, topic="/imu")


def _cut(path: Path, keep: float) -> Path:
    raw = path.read_bytes()
    out = path.with_name("cut_" + path.name)
    out.write_bytes(raw[: int(len(raw) * keep)])
    return out


@pytest.mark.parametrize("fmt", ["ros1", "mcap", "ulog", "dataflash", "parquet", "hdf5"])
def test_truncated_or_corrupt_logs_give_one_clear_error(tmp_path, fmt):
    z = imu_values(200)
    if fmt == "ros1":
        bad = _cut(write_bag(tmp_path / "b.bag", z, "ros1"), 0.5)
    elif fmt == "mcap":
        bad = _cut(next(write_bag(tmp_path / "b", z, "mcap").glob("*.mcap")), 0.5)
    elif fmt == "ulog":
        bad = tmp_path / "x.ulg"
        bad.write_bytes(b"ULog\x01\x12\x35" + bytes(range(256)) * 4)
    elif fmt == "dataflash":
        bad = tmp_path / "x.bin"
        bad.write_bytes(b"\xa3\x95\x80" + b"\xff" * 500)
    elif fmt == "parquet":
        bad = tmp_path / "x.parquet"
        bad.write_bytes(b"PAR1" + b"\x00" * 100)
    else:
        bad = tmp_path / "x.h5"
        bad.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\x00" * 100)
    with pytest.raises(NoisevarError) as err:
        load_table(bad, topic="/imu" if fmt in ("ros1", "mcap") else "IMU[0]")
    msg = str(err.value)
    assert "\n" not in msg and len(msg) < 600
    told = ("could not be read as", "no whole message")  # the last: a bag cut short
    assert any(t in msg for t in told) or ("no " in msg and "topics" in msg), msg


def test_registry():
    assert {".bag", ".mcap", ".db3", ".ulg", ".bin", ".parquet", ".h5"} <= set(log_suffixes())
    assert reader_for("x.csv", b"t,x\n") is None
    assert reader_for("x.log", b"$GPGGA,") is None  # NMEA keeps .log
    assert reader_for("anything", b"\x89MCAP0\r\n").name == "rosbag"
