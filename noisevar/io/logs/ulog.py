"""PX4 ULog (``.ulg``), through ``pyulog``.

A topic is a logged message (``sensor_combined``); a second instance of a message is
``name/1`` and so on. Fields are the message's numeric fields as ULog names them
(``gyro_rad[0]``). Times are the message's ``timestamp_sample`` (the sensor's sample time)
when it has one, else its ``timestamp``: microseconds since boot, in seconds. pyulog
parses the whole file; only the chosen topics' data is kept, and several topics are
read from one parse (:func:`read_many`). The raw IMU FIFO topics
(``sensor_gyro_fifo``, ``sensor_accel_fifo``) are unpacked to one row per sample, fields
``x``, ``y``, ``z`` in rad/s or m/s² (:mod:`noisevar.io.logs.ulog_fifo`).
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs import ulog_fifo
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo

#: Units of PX4 messages' fields (their ``.msg`` definitions), in pint syntax; a field's
#: array index is ignored (``gyro_rad[2]`` is a ``gyro_rad``).
TOPIC_UNITS: dict[str, dict[str, str]] = {
    "sensor_combined": {
        "gyro_rad": "rad/s",
        "accelerometer_m_s2": "m/s**2",
        "magnetometer_ga": "gauss",
        "gyro_integral_dt": "us",
        "accelerometer_integral_dt": "us",
    },
    "sensor_gyro": {"x": "rad/s", "y": "rad/s", "z": "rad/s", "temperature": "degC"},
    "sensor_accel": {"x": "m/s**2", "y": "m/s**2", "z": "m/s**2", "temperature": "degC"},
    "sensor_mag": {"x": "gauss", "y": "gauss", "z": "gauss", "temperature": "degC"},
    "vehicle_angular_velocity": {"xyz": "rad/s"},
    "vehicle_angular_acceleration": {"xyz": "rad/s**2"},
    "vehicle_imu": {"delta_angle": "rad", "delta_velocity": "m/s"},
    "vehicle_gps_position": {"eph": "m", "epv": "m", "vel_m_s": "m/s", "s_variance_m_s": "m/s"},
    "sensor_gps": {"eph": "m", "epv": "m", "vel_m_s": "m/s", "s_variance_m_s": "m/s"},
    "vehicle_local_position": {
        **{k: "m" for k in ("x", "y", "z", "delta_xy", "delta_z", "eph", "epv", "dist_bottom")},
        **{k: "m/s" for k in ("vx", "vy", "vz", "z_deriv", "delta_vxy", "delta_vz")},
        **{k: "m/s" for k in ("evh", "evv")},
        **{k: "m/s**2" for k in ("ax", "ay", "az")},
        "heading": "rad",
        "ref_alt": "m",
        "ref_lat": "deg",
        "ref_lon": "deg",
    },
}
#: Units of integer fields (PX4 before v1.14 logged positions as integers: ``int32 lat``
#: in 1e-7 degrees, ``int32 alt`` in millimetres); a float field of the same name (later
#: versions) is not given this unit.
INT_UNITS: dict[str, dict[str, str]] = {
    name: {"lat": "1e-7 deg", "lon": "1e-7 deg", "alt": "mm", "alt_ellipsoid": "mm"}
    for name in ("vehicle_gps_position", "sensor_gps")
}
#: Unit suffixes of PX4 field names (``true_airspeed_m_s``, ``baro_pressure_pa``).
SUFFIX_UNITS: tuple[tuple[str, str], ...] = (
    ("_m_s2", "m/s**2"),
    ("_m_s_s", "m/s**2"),
    ("_rad_s", "rad/s"),
    ("_m_s", "m/s"),
    ("_ga", "gauss"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_m", "m"),
    ("_pa", "Pa"),
    ("_celsius", "degC"),
    ("_celcius", "degC"),
    ("_meter", "m"),
)
#: What PX4 fields named so are (their ``.msg`` definitions): no measured signal, so left
#: out of a table's signals (``sensor_combined``'s ``gyro_integral_dt``, ``vehicle_imu``'s
#: ``delta_angle_dt``: an integration interval in us; ``ekf2_timestamps``' offsets).
SIDE_SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_integral_dt", "the sensor's integration interval (us)"),
    ("_dt", "an integration interval (us)"),
    ("_timestamp_rel", "a timestamp relative to the message's (us)"),
    ("_timestamp_relative", "a timestamp relative to the message's (us)"),
    (".timestamp", "a timestamp (us)"),
    ("_clipping", "a clipping bit field"),
    ("_flags", "a bit field of flags"),
    ("_status", "a status code"),
    ("device_id", "the sensor's device id"),
)
_INDEX = re.compile(r"\[\d+\]$")
_TIME_FIELDS = ("timestamp", "timestamp_sample")


def _unit(topic: str, field: str, kind: str = "f") -> str | None:
    """The unit of ``field`` of message ``topic`` (``kind``: its dtype's kind), or None."""
    base = _INDEX.sub("", field)
    if kind in "iu" and (hit := INT_UNITS.get(topic, {}).get(base)) is not None:
        return hit
    hit = TOPIC_UNITS.get(topic, {}).get(base)
    if hit is not None:
        return hit
    return next((u for s, u in SUFFIX_UNITS if base.endswith(s)), None)


def _side(fields: Sequence[str]) -> dict[str, str]:
    """The fields of :data:`SIDE_SUFFIXES`, each with what it is."""
    out = {}
    for f in fields:
        base = _INDEX.sub("", f)
        if (what := next((w for s, w in SIDE_SUFFIXES if base.endswith(s)), None)) is not None:
            out[f] = what
    return out


def _name(data, several: bool) -> str:
    return f"{data.name}/{data.multi_id}" if several or data.multi_id else data.name


def _parse(path: Path, only: Sequence[str] | None = None):
    from pyulog import ULog

    return ULog(str(path), message_name_filter_list=None if only is None else list(only))


def _fields(data) -> tuple[str, ...]:
    if ulog_fifo.is_fifo(data.name, data.data):
        return ulog_fifo.AXES
    names = [f.field_name for f in data.field_data]
    keep = [
        n
        for n in names
        if n not in _TIME_FIELDS
        and not n.startswith("_padding")
        and data.data[n].dtype.kind in "biuf"
    ]
    return tuple(keep[:MAX_FIELDS])


def _time_field(data) -> str:
    stamps = data.data.get("timestamp_sample")
    return "timestamp" if stamps is None or not np.any(stamps) else "timestamp_sample"


def _times(data) -> np.ndarray:
    return np.asarray(data.data[_time_field(data)], dtype=np.float64) / 1e6


def _samples(data, names: Sequence[str]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The times (s) and the named fields: a FIFO topic unpacked to one row per sample."""
    if ulog_fifo.is_fifo(data.name, data.data):
        t, values = ulog_fifo.unpack(data.data, _time_field(data))
        return t, {f: values[f] for f in names}
    return _times(data), {f: np.asarray(data.data[f], dtype=float) for f in names}


def _info(data, name: str) -> TopicInfo:
    """The topic's listing; a FIFO topic counts its samples, at ``1e6 / dt`` Hz."""
    fields = _fields(data)
    if ulog_fifo.is_fifo(data.name, data.data):
        units = ulog_fifo.units(data.name, data.data)
        n, rate = ulog_fifo.count(data.data), ulog_fifo.rate(data.data)
        return TopicInfo(name, data.name, n, rate, fields, units)
    t = _times(data)
    n = int(t.size)
    span = float(t[-1] - t[0]) if n > 1 else 0.0
    rate = (n - 1) / span if span > 0 else None
    kinds = {f: data.data[f].dtype.kind for f in fields}
    units = {f: u for f in fields if (u := _unit(data.name, f, kinds[f])) is not None}
    return TopicInfo(name, data.name, n, rate, fields, units, side=_side(fields))


def topics(path: Path) -> list[TopicInfo]:
    """Every logged message (and instance), its count, mean rate, fields and their units."""
    ulog = _parse(path)
    if not ulog.message_formats:
        raise ValueError("no message format could be parsed: the file is corrupt")
    counts: dict[str, int] = {}
    for d in ulog.data_list:
        counts[d.name] = counts.get(d.name, 0) + 1
    out = []
    for d in sorted(ulog.data_list, key=lambda d: (d.name, d.multi_id)):
        out.append(_info(d, _name(d, counts[d.name] > 1)))
    return out


def _find(ulog, topic: str):
    """The parsed data of ``topic`` (``name`` or ``name/instance``), or None."""
    base, _, inst = topic.partition("/")
    if inst and not inst.isdigit():
        return None
    multi = int(inst) if inst else 0
    return next((d for d in ulog.data_list if d.name == base and d.multi_id == multi), None)


def _chunks(data, names: Sequence[str]) -> Iterator[Chunk]:
    t, values = _samples(data, names)
    for lo in range(0, t.size, CHUNK):
        hi = lo + CHUNK
        yield Chunk(t[lo:hi], {f: v[lo:hi] for f, v in values.items()})


def read_many(path: Path, wanted: Sequence[str]) -> dict[str, tuple[TopicInfo, Iterator[Chunk]]]:
    """Several topics from one parse of the log (pyulog's message filter): each one's listing
    and its chunks (all its fields); a topic not in the log is left out."""
    ulog = _parse(path, list(dict.fromkeys(t.partition("/")[0] for t in wanted)))
    counts: dict[str, int] = {}
    for d in ulog.data_list:
        counts[d.name] = counts.get(d.name, 0) + 1
    out = {}
    for topic in wanted:
        data = _find(ulog, topic)
        if data is not None and _name(data, counts[data.name] > 1) == topic:
            out[topic] = (_info(data, topic), _chunks(data, _fields(data)))
    return out


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The topic's fields in chunks; times in seconds since boot."""
    data = _find(_parse(path, [topic.partition("/")[0]]), topic)
    if data is None:
        raise NoisevarError(f"no message {echo(topic)!r} in {echo(path.name)}")
    names = tuple(fields) if fields is not None else _fields(data)
    have = set(_fields(data))
    for f in names:
        if f not in have:
            raise NoisevarError(
                f"message {echo(topic)!r} has no numeric field {echo(f)!r}; fields: "
                + ", ".join(sorted(have)[:40])
            )
    yield from _chunks(data, names)


def parameters(path: Path) -> dict[str, float]:
    """The log's initial parameters (the configuration the flight started with), and its
    information fields that are whole numbers (``ver_sw_release``, the firmware's release
    ``0xMMmmppTT``: what a parameter the release lacks defaulted to); no message read."""
    ulog = _parse(path, ())
    out = {str(k): float(v) for k, v in ulog.initial_parameters.items()}
    info = {str(k): float(v) for k, v in ulog.msg_info_dict.items() if type(v) is int}
    return info | out


READER = LogReader(
    name="ulog",
    title="PX4 ULog",
    suffixes=(".ulg", ".ulog"),
    magic=(b"ULog\x01\x12\x35",),
    topics=topics,
    read=read,
    read_many=read_many,
    time_note="times from timestamp_sample (else timestamp), seconds since boot",
    repair="a log cut short while recording loses only its end: check it with ulog_info; "
    "else copy the file from the vehicle again",
    in_folders=True,
    parameters=parameters,
)
