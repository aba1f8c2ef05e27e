"""Logs written by each format's own writer (rosbags, pyarrow, h5py; DataFlash by its
documented layout, as pymavlink has no writer), in the test's tmp_path."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

RATE = 400.0
T0_NS = 1_700_000_000_000_000_000


def imu_values(n: int, seed: int = 0) -> np.ndarray:
    """``(n, 6)``: three rate axes, three acceleration axes."""
    return np.random.default_rng(seed).normal(size=(n, 6))


def write_bag(
    path: Path,
    z: np.ndarray,
    kind: str = "mcap",
    rate: float = RATE,
    stamps_ns: np.ndarray | None = None,
    extra: bool = True,
    frames: bool = False,
) -> Path:
    """``z`` (n, 6) as sensor_msgs/Imu on /imu, plus a std_msgs/Float64 on /level without a
    header: a ROS 1 bag (``kind="ros1"``) or a ROS 2 bag directory (mcap or sqlite3)."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    ty = store.types
    imu, hdr = ty["sensor_msgs/msg/Imu"], ty["std_msgs/msg/Header"]
    tm, vec = ty["builtin_interfaces/msg/Time"], ty["geometry_msgs/msg/Vector3"]
    quat, flt = ty["geometry_msgs/msg/Quaternion"], ty["std_msgs/msg/Float64"]
    if ros1:
        w = Writer1(path)
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        w = Writer(path, version=9, storage_plugin=plugin)
    ser = store.serialize_ros1 if ros1 else store.serialize_cdr
    w.open()
    c_imu = w.add_connection("/imu", imu.__msgtype__, typestore=store)
    c_lvl = w.add_connection("/level", flt.__msgtype__, typestore=store) if extra else None
    if stamps_ns is None:
        stamps_ns = T0_NS + np.round(np.arange(len(z)) * 1e9 / rate).astype(np.int64)
    cov = np.zeros(9)
    cov[4] = 0.5
    for i, ns in enumerate(int(s) for s in stamps_ns):
        stamp = tm(sec=ns // 10**9, nanosec=ns % 10**9)
        seq = {"seq": i} if ros1 else {}
        frame = "imu" + "_" * (i % 9) if frames else "imu"  # every CDR alignment of the body
        header = hdr(**seq, stamp=stamp, frame_id=frame)
        a, b = z[i, :3], z[i, 3:]
        msg = imu(
            header=header,
            orientation=quat(x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=cov,
            angular_velocity=vec(x=a[0], y=a[1], z=a[2]),
            angular_velocity_covariance=cov,
            linear_acceleration=vec(x=b[0], y=b[1], z=b[2]),
            linear_acceleration_covariance=cov,
        )
        w.write(c_imu, ns + 1000, ser(msg, imu.__msgtype__))  # record time: 1 us after the stamp
        if extra and i % 4 == 0:
            w.write(c_lvl, ns + 2000, ser(flt(data=level(i)), flt.__msgtype__))
    w.close()
    return path


def level(i: int) -> float:
    """The /level topic's value at IMU sample ``i``: a ramp with a wobble (not a counter,
    which the estimator refuses as no measurement)."""
    return float(i) + 0.25 * (i % 3)


def _df_record(mtype: int, fmt: str, *values) -> bytes:
    return b"\xa3\x95" + bytes([mtype]) + struct.pack("<" + fmt, *values)


def _pad(text: str, n: int) -> bytes:
    return text.encode().ljust(n, b"\0")


def write_dataflash(path: Path, z: np.ndarray, rate: float = RATE) -> Path:
    """A binary DataFlash log: FMT, UNIT, MULT, FMTU and IMU messages (two instances), as
    ArduPilot's AP_Logger lays them out (header A3 95, type byte, packed fields)."""
    out = bytearray()

    def fmt(mtype: int, length: int, name: str, form: str, cols: str) -> None:
        packed = (_pad(name, 4), _pad(form, 16), _pad(cols, 64))
        out.extend(_df_record(0x80, "BB4s16s64s", mtype, length, *packed))

    fmt(0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns")
    fmt(0x81, 3 + 8 + 1 + 64, "UNIT", "QbZ", "TimeUS,Id,Label")
    fmt(0x82, 3 + 8 + 1 + 8, "MULT", "Qbd", "TimeUS,Id,Mult")
    fmt(0x83, 3 + 8 + 1 + 16 + 16, "FMTU", "QBNN", "TimeUS,FmtType,UnitIds,MultIds")
    fmt(0x84, 3 + 8 + 1 + 24, "IMU", "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ")
    for uid, label in (("s", "s"), ("#", "instance"), ("E", "rad/s"), ("o", "m/s/s")):
        out.extend(_df_record(0x81, "Qb64s", 0, ord(uid), _pad(label, 64)))
    for mid, mult in (("-", 0.0), ("F", 1e-6)):
        out.extend(_df_record(0x82, "Qbd", 0, ord(mid), mult))
    out.extend(_df_record(0x83, "QB16s16s", 0, 0x84, _pad("s#EEEooo", 16), _pad("F-------", 16)))
    for i in range(len(z)):
        us = 1_000_000 + int(round(i * 1e6 / rate))
        for inst in (0, 1):
            out.extend(_df_record(0x84, "QB6f", us, inst, *(z[i] + inst)))
    path.write_bytes(bytes(out))
    return path


#: PX4's ``sensor_gyro_fifo`` layout (msg/SensorGyroFifo.msg) as ULog writes formats.
FIFO_FORMAT = (
    "uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float dt;float scale;"
    "uint8_t samples;int16_t[32] x;int16_t[32] y;int16_t[32] z;"
)


def write_ulog_fifo(
    path: Path,
    counts: np.ndarray,
    samples: np.ndarray,
    dt_us: float,
    scale: float | None,
    stamps_us: np.ndarray,
    name: str = "sensor_gyro_fifo",
    base: Path | None = None,
) -> Path:
    """A ULog with a FIFO topic, written by pyulog's own writer (``ULog.write_ulog``) into
    a copy of ``base`` (a real PX4 log: its header, formats and topics stay); ``scale=None``
    leaves the ``scale`` field out (older PX4).

    ``counts`` (messages, 3, 32) raw int16; ``samples`` valid per message; ``stamps_us`` each
    message's ``timestamp_sample``."""
    from pyulog import ULog

    ulog = ULog(str(base))
    layout = FIFO_FORMAT if scale is not None else FIFO_FORMAT.replace("float scale;", "")
    fmt = ULog.MessageFormat(f"{name}:{layout}".encode(), None)
    ulog._message_formats[name] = fmt  # noqa: SLF001 - pyulog has no public builder
    msg_id = 1 + max(d.msg_id for d in ulog.data_list)
    add = ULog._MessageAddLogged(  # noqa: SLF001
        struct.pack("<BH", 0, msg_id) + name.encode(), None, ulog._message_formats
    )
    rows = np.zeros(len(samples), dtype=add.dtype)
    rows["timestamp"] = stamps_us + 50
    rows["timestamp_sample"] = stamps_us
    rows["device_id"] = 2621474
    rows["dt"] = dt_us
    if scale is not None:
        rows["scale"] = scale
    rows["samples"] = samples
    for a, ax in enumerate("xyz"):
        for i in range(32):
            rows[f"{ax}[{i}]"] = counts[:, a, i]
    add.buffer = bytearray(rows.tobytes())
    ulog._data_list.append(ULog.Data(add))  # noqa: SLF001
    ulog.write_ulog(str(path))
    return path


#: rad/s and m/s² per count of :func:`write_ulog_imu_fifos` (float32, as PX4 logs them).
GYRO_SCALE = float(np.float32(1.0e-3 * np.pi / 180))
ACCEL_SCALE = float(np.float32(1.0e-3 * 9.80665))


def write_ulog_imu_fifos(
    path: Path,
    base: Path,
    seconds: float = 40.0,
    rates: tuple[float, float] = (800.0, 400.0),
    sigmas: tuple[float, float] = (300.0, 200.0),
    per_message: int = 8,
    seed: int = 0,
) -> dict[str, float]:
    """A ULog with ``sensor_gyro_fifo`` and ``sensor_accel_fifo`` at their own rates (pyulog's
    writer, :func:`write_ulog_fifo`), white counts of std ``sigmas``; the true white-noise
    densities N (rad/s/√Hz, m/s²/√Hz): ``sigma · scale / √rate``."""
    rng = np.random.default_rng(seed)
    truth = {}
    src = base
    for name, rate, sigma, scale in zip(
        ("sensor_gyro_fifo", "sensor_accel_fifo"),
        rates,
        sigmas,
        (GYRO_SCALE, ACCEL_SCALE),
        strict=True,
    ):
        m = int(seconds * rate / per_message)
        counts = np.clip(np.round(sigma * rng.standard_normal((m, 3, 32))), -32768, 32767)
        samples = np.full(m, per_message)
        dt_us = 1e6 / rate
        stamps = 5_000_000 + np.cumsum(samples * dt_us).astype(np.int64)
        out = path.with_name(f"{path.stem}_{name}.ulg") if name == "sensor_gyro_fifo" else path
        write_ulog_fifo(out, counts.astype(np.int16), samples, dt_us, scale, stamps, name, src)
        src = out
        truth[name] = float(sigma * scale / np.sqrt(rate))
    return truth


def rechunked_mcap(src: Path, dst: Path, compression: str = "ZSTD", chunk: int = 20_000) -> Path:
    """The MCAP file ``src`` written again in small chunks (``chunk`` bytes), as a recorder does."""
    from mcap.reader import make_reader
    from mcap.writer import CompressionType, Writer

    with src.open("rb") as fh, dst.open("wb") as out:
        reader = make_reader(fh)
        w = Writer(out, chunk_size=chunk, compression=CompressionType[compression])
        w.start(profile="ros2", library="test")
        ids_s, ids_c = {}, {}
        for schema, channel, msg in reader.iter_messages():
            if schema.id not in ids_s:
                ids_s[schema.id] = w.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in ids_c:
                ids_c[channel.id] = w.register_channel(
                    channel.topic, channel.message_encoding, ids_s[schema.id], channel.metadata
                )
            w.add_message(ids_c[channel.id], msg.log_time, msg.data, msg.publish_time)
        w.finish()
    return dst


def write_ros1_chunked(
    path: Path, z: np.ndarray, compression: str | None = None, chunk: int = 40_000
) -> Path:
    """``z`` (n, 6) as sensor_msgs/Imu on /imu in a ROS 1 bag of small chunks (``chunk``
    bytes; a recorder's are 768 KB), optionally BZ2 or LZ4 compressed."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    ty = store.types
    imu, hdr = ty["sensor_msgs/msg/Imu"], ty["std_msgs/msg/Header"]
    tm, vec = ty["builtin_interfaces/msg/Time"], ty["geometry_msgs/msg/Vector3"]
    quat = ty["geometry_msgs/msg/Quaternion"]
    w = Writer(path)
    if compression:
        w.set_compression(Writer.CompressionFormat[compression])
    w.chunk_threshold = chunk
    w.open()
    conn = w.add_connection("/imu", imu.__msgtype__, typestore=store)
    zero = np.zeros(9)
    for i in range(len(z)):
        ns = T0_NS + i * 2_500_000
        msg = imu(
            header=hdr(seq=i, stamp=tm(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="imu"),
            orientation=quat(x=0.0, y=0.0, z=0.0, w=1.0), orientation_covariance=zero,
            angular_velocity=vec(x=z[i, 0], y=z[i, 1], z=z[i, 2]),
            angular_velocity_covariance=zero,
            linear_acceleration=vec(x=z[i, 3], y=z[i, 4], z=z[i, 5]),
            linear_acceleration_covariance=zero,
        )  # fmt: skip
        w.write(conn, ns, store.serialize_ros1(msg, imu.__msgtype__))
    w.close()
    return path
