"""ROS 1 bags (``.bag``) and ROS 2 bags (sqlite3 ``.db3``, ``.mcap``, or their directory),
through ``rosbags`` (pure Python, no ROS install).

Fields are the message's numeric leaves by dotted path (``angular_velocity.x``); a fixed
array's elements by index (``orientation_covariance.4``) can be read by naming them. A
message with a ``header`` is timed by its ``header.stamp`` (the driver's sensor time),
else by the bag's record time; times are seconds from the topic's first message, taken
in integer nanoseconds before the conversion, so no precision is lost to the epoch. The
bag's own message definitions are checked before ``rosbags`` compiles them
(:mod:`noisevar.io.logs.msgdefs`).
"""

from __future__ import annotations

import operator
import struct
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.mcap_cut import cut_short, recovered
from noisevar.io.logs.msgdefs import open_bag
from noisevar.io.logs.repaired import unclosed_dir
from noisevar.io.logs.ros_declared import declared_fields
from noisevar.io.logs.rosbag1_cut import recovered as reindexed
from noisevar.io.logs.rosbag1_cut import unindexed
from noisevar.io.logs.rosbag_spans import topic_span
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo, report

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
    # poses, velocities and forces, whose definitions state no unit: REP 103's SI units
    # (metre, m/s, rad/s, newton); a key may be a dotted path (a quaternion has no unit)
    "geometry_msgs/PointStamped": {"point": "m"},
    "geometry_msgs/PoseStamped": {"pose.position": "m"},
    "geometry_msgs/PoseWithCovarianceStamped": {"pose.pose.position": "m"},
    "geometry_msgs/TwistStamped": {"twist.linear": "m/s", "twist.angular": "rad/s"},
    "geometry_msgs/Twist": {"linear": "m/s", "angular": "rad/s"},
    "geometry_msgs/AccelStamped": {"accel.linear": "m/s**2", "accel.angular": "rad/s**2"},
    "geometry_msgs/Wrench": {"force": "N", "torque": "N*m"},
    "geometry_msgs/WrenchStamped": {"wrench.force": "N", "wrench.torque": "N*m"},
    "nav_msgs/Odometry": {
        "pose.pose.position": "m",
        "twist.twist.linear": "m/s",
        "twist.twist.angular": "rad/s",
    },
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
        parts = f.split(".")
        for k in range(len(parts), 0, -1):  # the longest key that is the field or above it
            unit = table.get(".".join(parts[:k]))
            if unit is not None:
                out[f] = unit
                break
    return out


def _open(path: Path):
    """The bag's ``AnyReader``; opening it checks the bag's own message definitions before
    ``rosbags`` compiles them (:mod:`noisevar.io.logs.msgdefs`).

    An MCAP file cut short and a ROS 1 bag without its index are read through their
    repaired copies (:mod:`noisevar.io.logs.mcap_cut`, :mod:`noisevar.io.logs.rosbag1_cut`);
    what was kept joins the loaded table's notes.
    """
    from rosbags.typesys import Stores, get_typestore

    lone = unclosed_dir(path)
    if lone is not None:
        report(
            f"the bag directory has no metadata.yaml (a recording that never closed): its "
            f"one file {lone.name} is read"
        )
        path = lone
    if path.suffix.lower() == ".mcap" and cut_short(path):
        path, note = recovered(path)
        report(note)
    elif unindexed(path):  # also a recorder's .bag.active
        path, note = reindexed(path)
        report(note)
    store = Stores.ROS1_NOETIC if path.suffix.lower() == ".bag" else Stores.LATEST
    return open_bag(path, get_typestore(store))


def topics(path: Path) -> list[TopicInfo]:
    """Every topic of the bag, its type, count, mean rate, numeric fields and their units.

    The rate is the count over the topic's own span of record times when the bag's index
    gives it (:func:`~noisevar.io.logs.rosbag_spans.topic_span`), else over the bag's.
    """
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
            own = topic_span(info.connections) if count > 1 else None
            if own is not None and own[1] > own[0]:  # its own first and last record times
                rate = (count - 1) / ((own[1] - own[0]) / 1e9)
            declared = declared_fields(msgtype, fields)
            out.append(
                TopicInfo(name, msgtype, count, rate, fields, _units(msgtype, fields), declared)
            )
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
        fast = FlatDecoder.of(bag.typestore, msgtype, names, ros1=not bag.is2)
        order = fast.order if fast is not None else list(range(len(names)))
        back = np.argsort(order)  # rows are kept in wire order (the fast path's), then put back
        t0 = None
        stamps: list[int] = []
        rows: list = []
        for conn, stamp, raw in bag.messages(connections=conns):
            got = fast.decode(raw) if fast is not None else None
            if got is not None:
                sec, nsec, row = got
            else:  # not a flat message, or one the layout does not fit: rosbags decodes it
                msg = bag.deserialize(raw, conn.msgtype)
                sec, nsec = (msg.header.stamp.sec, msg.header.stamp.nanosec) if stamped else (0, 0)
                asked = [g(msg) for g in getters]
                row = [asked[j] for j in order]
            if sec or nsec:
                stamp = sec * 1_000_000_000 + nsec
            t0 = stamp if t0 is None else t0
            stamps.append(stamp - t0)
            rows.append(row)
            if len(rows) == CHUNK:
                yield _chunk(stamps, rows, names, back)
                stamps, rows = [], []
        if rows:
            yield _chunk(stamps, rows, names, back)


def _chunk(stamps: list[int], rows: list, names: Sequence[str], back: np.ndarray) -> Chunk:
    vals = np.array(rows, dtype=float).reshape(len(rows), len(names))[:, back]
    times = np.array(stamps, dtype=np.int64) / 1e9
    return Chunk(times, {f: np.ascontiguousarray(vals[:, i]) for i, f in enumerate(names)})


#: struct codes and sizes of ROS primitive types.
_CODES = {
    "bool": "?",
    "byte": "B",
    "char": "B",
    "int8": "b",
    "uint8": "B",
    "int16": "h",
    "uint16": "H",
    "int32": "i",
    "uint32": "I",
    "float32": "f",
    "int64": "q",
    "uint64": "Q",
    "float64": "d",
}


def _flat(typestore, fdefs: list, prefix: str = "", depth: int = 0) -> list | None:
    """``[(path, type)]`` of every primitive of the fields ``fdefs`` in wire order, or None
    if they hold a string or a sequence (no fixed layout)."""
    from rosbags.interfaces import Nodetype

    if depth > 8:
        return None
    out: list[tuple[str, str]] = []
    for fname, (kind, detail) in fdefs:
        path = f"{prefix}{fname}"
        if kind == Nodetype.BASE and detail[0] in _CODES:
            out.append((path, detail[0]))
        elif kind == Nodetype.NAME:
            sub = _flat(typestore, typestore.fielddefs[detail][1], f"{path}.", depth + 1)
            if sub is None:
                return None
            out += sub
        elif kind == Nodetype.ARRAY and detail[0][0] == Nodetype.BASE and detail[0][1][0] in _CODES:
            out += [(f"{path}.{i}", detail[0][1][0]) for i in range(detail[1])]
        else:
            return None
    return out


class FlatDecoder:
    """The wanted fields of a message with a fixed layout after its optional
    ``std_msgs/Header``, read straight from the serialised bytes (ROS 1, or little-endian
    CDR with its alignment rules) without building message objects: ``sensor_msgs/Imu`` and
    most sensor messages. The layout depends only on where the body starts (after the
    header's ``frame_id``), so one ``struct.Struct`` per start is built and kept.
    """

    def __init__(self, leaves: list, wanted: Sequence[str], header: bool, ros1: bool):
        self.leaves, self.header, self.ros1 = leaves, header, ros1
        where = {path: i for i, (path, _) in enumerate(leaves)}
        self.wanted = [where[w] for w in wanted]
        #: the asked fields' positions in wire order (what :meth:`decode` returns)
        self.order = sorted(range(len(wanted)), key=lambda j: self.wanted[j])
        self.structs: dict[int, struct.Struct] = {}

    @classmethod
    def of(cls, typestore, msgtype: str, wanted: Sequence[str], ros1: bool):
        """The decoder of ``wanted`` fields of ``msgtype``, or None (no fixed layout)."""
        fdefs = typestore.fielddefs[msgtype][1]
        header = bool(fdefs) and fdefs[0][0] == "header"
        if header and fdefs[0][1][1] != "std_msgs/msg/Header":
            return None
        leaves = _flat(typestore, fdefs[1:] if header else fdefs)
        if not leaves or len(set(wanted)) != len(wanted):
            return None
        if not set(wanted) <= {p for p, _ in leaves}:
            return None
        return cls(leaves, wanted, header, ros1)

    def _struct(self, start: int) -> struct.Struct:
        """The struct of the wanted fields for a body starting at byte ``start``."""
        fmt, pos, wanted = ["<"], start, set(self.wanted)
        for i, (_, typ) in enumerate(self.leaves):
            code = _CODES[typ]
            size = struct.calcsize(code)
            if not self.ros1:  # CDR: aligned to its size, counted after the 4-byte preamble
                pad = -(pos - 4) % size
                fmt.append("x" * pad)
                pos += pad
            fmt.append(code if i in wanted else "x" * size)
            pos += size
        return struct.Struct("".join(fmt))

    def decode(self, raw: bytes) -> tuple[int, int, tuple] | None:
        """``(sec, nanosec, values)`` of one message, the values in wire order
        (:attr:`order`), or None if the message does not fit the layout."""
        sec = nsec = 0
        try:
            if not self.ros1 and raw[:2] != b"\x00\x01":  # little-endian CDR only
                return None
            if self.header:  # ROS 1: seq, sec, nsec, len; CDR: preamble, sec, nsec, len
                sec, nsec, slen = struct.unpack_from("<4xIII" if self.ros1 else "<4xiII", raw)
                start = 16 + slen
            else:
                start = 0 if self.ros1 else 4
            st = self.structs.get(start)
            if st is None:
                st = self.structs[start] = self._struct(start)
            values = st.unpack_from(raw, start)
        except struct.error:
            return None
        return sec, nsec, values


READER = LogReader(
    name="rosbag",
    title="ROS bag",
    suffixes=(".bag", ".mcap", ".db3", ".active"),  # .bag.active: a recorder's unclosed bag
    magic=(b"#ROSBAG V2.0", b"\x89MCAP0\r\n"),
    topics=topics,
    read=read,
    time_note="times from header.stamp (else the bag's record time), seconds from the "
    "topic's first message",
    repair="a ROS 1 bag damaged inside can be re-indexed (rosbag reindex), an MCAP file "
    "recovered (mcap recover; a bag only cut short is read up to its cut), a ROS 2 bag checked "
    "with ros2 bag info; else copy the file again",
    in_folders=True,
)
