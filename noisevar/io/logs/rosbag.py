"""ROS 1 bags (``.bag``) and ROS 2 bags (sqlite3 ``.db3``, ``.mcap``, or their directory),
through ``rosbags`` (pure Python, no ROS install).

Fields are the message's numeric leaves by dotted path (``angular_velocity.x``); a fixed
array's elements by index (``orientation_covariance.4``) can be read by naming them. A
message with a ``header`` is timed by its ``header.stamp`` (the driver's sensor time),
else by the bag's record time; times are seconds from the topic's first message, taken
in integer nanoseconds before the conversion, so no precision is lost to the epoch.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo

#: Units of standard messages' fields, from their message definitions' documentation
#: (``sensor_msgs/Imu``: rad/sec, m/s^2; ``MagneticField``: tesla...), in pint syntax.
#: Keys are the type without ``/msg/``; a unit covers the field and everything below it.
MESSAGE_UNITS: dict[str, dict[str, str]] = {
    "sensor_msgs/Imu": {
        "angular_velocity": "rad/s",
        "linear_acceleration": "m/s**2",
        "angular_velocity_covariance": "rad**2/s**2",
        "linear_acceleration_covariance": "m**2/s**4",
    },
    "sensor_msgs/MagneticField": {"magnetic_field": "T", "magnetic_field_covariance": "T**2"},
    "sensor_msgs/FluidPressure": {"fluid_pressure": "Pa", "variance": "Pa**2"},
    "sensor_msgs/Temperature": {"temperature": "degC", "variance": "delta_degC**2"},
    "sensor_msgs/Range": {"range": "m", "min_range": "m", "max_range": "m", "field_of_view": "rad"},
    "sensor_msgs/NavSatFix": {"latitude": "deg", "longitude": "deg", "altitude": "m"},
    "geometry_msgs/Vector3Stamped": {},
}
_NUMERIC = {
    "bool",
    "byte",
    "char",
    "int8",
    "uint8",
    "int16",
    "uint16",
    "int32",
    "uint32",
    "int64",
    "uint64",
    "float32",
    "float64",
}


def _short(msgtype: str) -> str:
    return msgtype.replace("/msg/", "/")


def _leaves(typestore, msgtype: str, prefix: str = "", depth: int = 0) -> Iterator[str]:
    """Numeric scalar leaf fields of ``msgtype`` by dotted path (header excluded at the top;
    fixed arrays' elements are read by naming them, not listed)."""
    from rosbags.interfaces import Nodetype

    if depth > 8:  # a definition nesting deeper is not a sensor message worth a column
        return
    for fname, (kind, detail) in typestore.fielddefs[msgtype][1]:
        path = f"{prefix}{fname}"
        if depth == 0 and fname == "header":
            continue
        if kind == Nodetype.BASE and detail[0] in _NUMERIC:
            yield path
        elif kind == Nodetype.NAME:
            yield from _leaves(typestore, detail, f"{path}.", depth + 1)


def _units(msgtype: str, fields: Sequence[str]) -> dict[str, str]:
    table = MESSAGE_UNITS.get(_short(msgtype), {})
    out = {}
    for f in fields:
        top = f.split(".", 1)[0]
        if top in table:
            out[f] = table[top]
    return out


def _open(path: Path):
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    store = Stores.ROS1_NOETIC if path.suffix.lower() == ".bag" else Stores.LATEST
    return AnyReader([path], default_typestore=get_typestore(store))


def topics(path: Path) -> list[TopicInfo]:
    """Every topic of the bag, its type, count, mean rate, numeric fields and their units."""
    out = []
    with _open(path) as bag:
        span = max(bag.duration, 1) / 1e9
        for name, info in sorted(bag.topics.items()):
            msgtype = info.msgtype or "?"
            fields: tuple[str, ...] = ()
            if msgtype in bag.typestore.fielddefs:
                fields = tuple(_leaves(bag.typestore, msgtype))[:MAX_FIELDS]
            count = int(info.msgcount)
            rate = (count - 1) / span if count > 1 and bag.duration > 0 else None
            out.append(TopicInfo(name, msgtype, count, rate, fields, _units(msgtype, fields)))
    return out


def _getter(field: str) -> Callable[[object], float]:
    """``msg -> value`` for a dotted path; a numeric last part indexes an array."""
    head, _, last = field.rpartition(".")
    if last.isdigit() and head:
        arr, idx = operator.attrgetter(head), int(last)
        return lambda m: arr(m)[idx]
    return operator.attrgetter(field)


def _check_fields(bag, msgtype: str, fields: Sequence[str]) -> list[Callable]:
    """A getter per field, each tried on the type's definition first (unknown paths refused)."""
    listed = set(_leaves(bag.typestore, msgtype))
    getters = []
    for f in fields:
        if f not in listed and not _is_path(bag.typestore, msgtype, f):
            some = ", ".join(sorted(listed)[:30])
            raise NoisevarError(f"{echo(msgtype)} has no numeric field {echo(f)!r}; fields: {some}")
        getters.append(_getter(f))
    return getters


def _is_path(typestore, msgtype: str, field: str) -> bool:
    """Whether ``field`` names a numeric leaf or a fixed array's element of ``msgtype``."""
    from rosbags.interfaces import Nodetype

    kind, detail = Nodetype.NAME, msgtype
    for part in field.split("."):
        if kind == Nodetype.ARRAY:
            (sub_kind, sub_detail), length = detail
            if not (part.isdigit() and int(part) < length):
                return False
            kind, detail = sub_kind, sub_detail
            continue
        if kind != Nodetype.NAME or detail not in typestore.fielddefs:
            return False
        hit = dict(typestore.fielddefs[detail][1]).get(part)
        if hit is None:
            return False
        kind, detail = hit
    return kind == Nodetype.BASE and detail[0] in _NUMERIC


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The topic's fields in chunks of :data:`CHUNK` messages; times in seconds from its first."""
    with _open(path) as bag:
        conns = [c for c in bag.connections if c.topic == topic]
        if not conns:
            raise NoisevarError(f"no topic {echo(topic)!r} in {echo(path.name)}")
        msgtype = conns[0].msgtype
        names = tuple(fields) if fields is not None else tuple(_leaves(bag.typestore, msgtype))
        getters = _check_fields(bag, msgtype, names)
        stamped = "header" in dict(bag.typestore.fielddefs[msgtype][1])
        t0 = None
        ns = np.empty(CHUNK, dtype=np.int64)
        vals = np.empty((CHUNK, len(names)))
        k = 0
        for conn, stamp, raw in bag.messages(connections=conns):
            msg = bag.deserialize(raw, conn.msgtype)
            if stamped and (msg.header.stamp.sec or msg.header.stamp.nanosec):
                stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
            t0 = stamp if t0 is None else t0
            ns[k] = stamp - t0
            vals[k] = [g(msg) for g in getters]
            k += 1
            if k == CHUNK:
                yield _chunk(ns, vals, names, k)
                ns, vals, k = np.empty_like(ns), np.empty_like(vals), 0
        if k:
            yield _chunk(ns, vals, names, k)


def _chunk(ns: np.ndarray, vals: np.ndarray, names: Sequence[str], k: int) -> Chunk:
    return Chunk(ns[:k] / 1e9, {f: vals[:k, i] for i, f in enumerate(names)})


READER = LogReader(
    name="rosbag",
    title="ROS bag",
    suffixes=(".bag", ".mcap", ".db3"),
    magic=(b"#ROSBAG V2.0", b"\x89MCAP0\r\n"),
    topics=topics,
    read=read,
    time_note="times from header.stamp (else the bag's record time), seconds from the "
    "topic's first message",
    repair="a ROS 1 bag cut short can be re-indexed (rosbag reindex), a ROS 2 bag checked "
    "with ros2 bag info; else copy the file again",
)
