"""ArduPilot DataFlash logs (binary ``.bin``, text ``.log``), through ``pymavlink``'s DFReader.

A topic is a message type (``IMU``, ``GPS``, ``BARO``); a type logged by several sensors
(its FMTU marks an instance field) is one topic per instance, ``IMU[0]``, ``IMU[1]``.
Fields are the numeric columns, scaled as pymavlink scales them; units come from the
log's own FMTU/UNIT/MULT messages. Times are ``TimeUS`` (microseconds since boot), in
seconds. A binary log is indexed by pymavlink, then each topic's columns are taken from the
mapped file at once (numpy), not message by message; a text log is read once, line by
line, and only the asked types' fields are converted (:mod:`noisevar.io.logs.dataflash_text`).
"""

from __future__ import annotations

import contextlib
import functools
import os
import re
import struct
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs import dataflash_text
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo

#: DataFlash unit names (the log's UNIT messages) in pint syntax; others are left out.
UNITS = {
    "rad/s": "rad/s",
    "m/s/s": "m/s**2",
    "m/s": "m/s",
    "m": "m",
    "Pa": "Pa",
    "degC": "degC",
    "deg": "deg",
    "deg/s": "deg/s",
    "rad": "rad",
    "s": "s",
    "V": "V",
    "A": "A",
    "Hz": "Hz",
    "Gauss": "gauss",
    "deglatitude": "deg",  # ArduPilot's names for degrees of latitude, longitude, heading
    "deglongitude": "deg",
    "degheading": "deg",
    "%": "percent",
}
_IMU = {**dict.fromkeys(("GyrX", "GyrY", "GyrZ"), "rad/s"),
        **dict.fromkeys(("AccX", "AccY", "AccZ"), "m/s**2"), "T": "degC",
        "GHz": "Hz", "AHz": "Hz"}  # fmt: skip
_MAG = dict.fromkeys(("MagX", "MagY", "MagZ", "OfsX", "OfsY", "OfsZ"), "milligauss")
_ANGLES = dict.fromkeys(("Roll", "Pitch", "Yaw", "DesRoll", "DesPitch", "DesYaw"), "deg")
#: Units of ArduPilot's sensor messages as its ``LogStructure.h`` defines them, for a log
#: written before ArduPilot logged them (no FMTU: pymavlink's own test.BIN opened on
#: ``AETR``, not its IMU, and gave no unit to convert); a log's own units come first.
STRUCTURE_UNITS: dict[str, dict[str, str]] = {
    **dict.fromkeys(("IMU", "IMU2", "IMU3"), _IMU),
    **dict.fromkeys(("MAG", "MAG2", "MAG3"), _MAG),
    "BARO": {"Alt": "m", "Press": "Pa", "Temp": "degC", "CRt": "m/s", "GndTemp": "degC"},
    "GPS": {"Lat": "deg", "Lng": "deg", "Alt": "m", "Spd": "m/s", "GCrs": "deg", "VZ": "m/s"},
    "POS": {"Lat": "deg", "Lng": "deg", "Alt": "m", "RelHomeAlt": "m", "RelOriginAlt": "m"},
    "ATT": _ANGLES,
    "AHR2": {**_ANGLES, "Alt": "m", "Lat": "deg", "Lng": "deg"},
}
_PREFIX = {"": "", "d": "d", "c": "c", "m": "m", "µ": "u", "n": "n"}
_TOPIC = re.compile(r"^(?P<type>[A-Za-z0-9_]+)(\[(?P<inst>\d+)\])?$")
_NUMERIC_FORMATS = set("bBhHiIqQfdcCeELM")


def _pint(unit: str) -> str | None:
    if unit in UNITS:
        return UNITS[unit]
    prefix, rest = unit[:1], unit[1:]
    if prefix in _PREFIX and rest in UNITS and "/" not in UNITS[rest]:
        return _PREFIX[prefix] + UNITS[rest]
    return None


@functools.cache
def _reader_classes() -> tuple[type, type]:
    """pymavlink's binary and text readers without its clock search: pymavlink walks the
    whole log for a GPS time base when none comes early (a bench log without a fix), and
    noisevar uses TimeUS, not that clock."""
    from pymavlink import DFReader

    def init_clock(self) -> None:
        self.clock = DFReader.DFReaderClock_usec()
        self._rewind(keep_messages=True)

    binary = type("Binary", (DFReader.DFReader_binary,), {"init_clock": init_clock})
    text = type("Text", (DFReader.DFReader_text,), {"init_clock": init_clock})
    return binary, text


@contextlib.contextmanager
def _open(path: Path):
    with path.open("rb") as fh:
        binary = fh.read(2) == b"\xa3\x95"
    # pymavlink's compiled indexer prints skipped corrupt bytes from C, past any Python
    # redirection; its Python indexer reports them through print, which the registry keeps
    saved = os.environ.get("PYMAVLINK_FAST_INDEX")
    os.environ["PYMAVLINK_FAST_INDEX"] = "0"
    try:
        dfr = _reader_classes()[0 if binary else 1](str(path), zero_time_base=True)
    finally:
        if saved is None:
            os.environ.pop("PYMAVLINK_FAST_INDEX", None)
        else:
            os.environ["PYMAVLINK_FAST_INDEX"] = saved
    try:
        yield dfr
    finally:
        with contextlib.suppress(Exception):
            dfr.close() if binary else dfr.filehandle.close()


#: The log's own bookkeeping messages (formats, units, multipliers): not topics.
META = ("FMT", "FMTU", "UNIT", "MULT")


def _fields(fmt) -> tuple[str, ...]:
    if fmt.name in META:
        return ()
    cols = [
        c
        for c, f in zip(fmt.columns, fmt.format, strict=False)
        if f in _NUMERIC_FORMATS and c != "TimeUS" and c != fmt.instance_field
    ]
    return tuple(cols[:MAX_FIELDS])


def _units(fmt, fields: Sequence[str]) -> dict[str, str]:
    """The fields' units from the log's FMTU; with none logged, :data:`STRUCTURE_UNITS`."""
    out = {}
    for f in fields:
        u = _pint(fmt.get_unit(f) or "")
        if u is not None:
            out[f] = u
    if out or any(fmt.get_unit(f) for f in fields):
        return out
    known = STRUCTURE_UNITS.get(fmt.name, {})
    return {f: known[f] for f in fields if f in known}


#: numpy types of pymavlink's struct codes (``FORMAT_TO_STRUCT``), little-endian.
_NP = {
    "b": "i1",
    "B": "u1",
    "h": "<i2",
    "H": "<u2",
    "i": "<i4",
    "I": "<u4",
    "q": "<i8",
    "Q": "<u8",
    "f": "<f4",
    "d": "<f8",
    "e": "<f2",
}


def _columns(dfr, fmt, names: Sequence[str], offsets: np.ndarray) -> dict[str, np.ndarray]:
    """Columns ``names`` of the binary messages starting at ``offsets``, scaled as pymavlink
    scales them, read from the mapped file at once."""
    from pymavlink.DFReader import FORMAT_TO_STRUCT

    buf = np.frombuffer(dfr.data_map, dtype=np.uint8)
    try:
        offsets = offsets[offsets + fmt.len <= buf.size]  # a message cut by the file's end
        body = buf[(offsets + 3)[:, None] + np.arange(fmt.len - 3)]
    finally:
        del buf  # the map is closed later: no view of it may outlive this
    out, pos = {}, 0
    for col, ch in zip(fmt.columns, fmt.format, strict=False):
        code, mult, _ = FORMAT_TO_STRUCT[ch]
        size = struct.calcsize(code)
        if col in names and code in _NP:
            v = body[:, pos : pos + size].copy().view(np.dtype(_NP[code])).ravel().astype(float)
            out[col] = v / round(1 / mult) if mult is not None and 0 < mult < 1 else v
        pos += size
    return out


def _binary_records(dfr) -> dict[tuple[str, int | None], np.ndarray]:
    """Per (type, instance): the TimeUS of its messages, from the index and the mapped file."""
    seen = {}
    for fmt in dfr.formats.values():
        offs = dfr.offsets[fmt.type] if fmt.type < len(dfr.offsets) else []
        if not offs or "TimeUS" not in fmt.colhash or not _fields(fmt):
            continue
        wanted = ["TimeUS", *([fmt.instance_field] if fmt.instance_field else [])]
        cols = _columns(dfr, fmt, wanted, np.asarray(offs, dtype=np.int64))
        if fmt.instance_field is None:
            seen[(fmt.name, None)] = cols["TimeUS"]
            continue
        inst = cols[fmt.instance_field]
        for i in np.unique(inst):
            seen[(fmt.name, int(i))] = cols["TimeUS"][inst == i]
    return seen


def _is_text(path: Path) -> bool:
    with path.open("rb") as fh:
        return fh.read(2) != b"\xa3\x95"


def _topics(dfr) -> list[TopicInfo]:
    """The topics of an open log: a binary log's reader, or a :class:`TextLog`."""
    if isinstance(dfr, dataflash_text.TextLog):
        return _topic_infos(dataflash_text.records(dfr, _fields), dfr.formats)
    spans = {k: (len(t), t[0], t[-1]) for k, t in _binary_records(dfr).items() if len(t)}
    return _topic_infos(spans, {f.name: f for f in dfr.formats.values()})


def _topic_infos(records: dict, formats: dict) -> list[TopicInfo]:
    """Each (type, instance)'s listing from its count and first and last TimeUS."""
    out = []
    for (name, inst), (count, first, last) in sorted(records.items(), key=lambda kv: str(kv[0])):
        fmt = formats[name]
        fields = _fields(fmt)
        span = float(last - first) / 1e6 if count > 1 else 0.0
        rate = float((count - 1) / span) if span > 0 else None
        topic = name if inst is None else f"{name}[{inst}]"
        out.append(TopicInfo(topic, name, count, rate, fields, _units(fmt, fields)))
    return out


def topics(path: Path) -> list[TopicInfo]:
    """Every message type (per instance) with TimeUS and numeric columns: counts, rates, units."""
    with _log(path) as dfr:
        return _topics(dfr)


@contextlib.contextmanager
def _log(path: Path):
    """The open log: a text log parsed (:func:`~noisevar.io.logs.dataflash_text.text_log`),
    a binary one through pymavlink (:func:`_open`)."""
    if _is_text(path):
        yield dataflash_text.text_log(path)
        return
    with _open(path) as dfr:
        yield dfr


def parameters(path: Path) -> dict[str, float]:
    """The log's ``PARM`` messages, name -> the first value logged (the configuration the
    flight started with; a value changed in flight is logged again, later)."""
    out: dict[str, float] = {}
    with _log(path) as dfr:
        if isinstance(dfr, dataflash_text.TextLog):
            if "PARM" in dfr.formats:
                cols = dfr.formats["PARM"].colhash
                for row in dfr.elements("PARM"):
                    name = row[cols["Name"]].strip().decode("utf-8", "replace")
                    with contextlib.suppress(ValueError):
                        out.setdefault(name, float(row[cols["Value"]]))
            return out
        while (m := dfr.recv_match(type="PARM")) is not None:
            out.setdefault(str(m.Name), float(m.Value))
    return out


def read_many(path: Path, wanted: Sequence[str]) -> dict[str, tuple[TopicInfo, Iterator[Chunk]]]:
    """Several topics from one opening (one index pass) of the log: each one's listing and
    its chunks (all its fields, read before the log is closed); a topic not in the log is
    left out."""
    out = {}
    with _log(path) as dfr:
        infos = {t.name: t for t in _topics(dfr)}
        for topic in wanted:
            if topic in infos:
                chunks = list(_read(dfr, path, topic, None))
                out[topic] = (infos[topic], iter(chunks))
    return out


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The topic's fields in chunks; times in seconds since boot (TimeUS)."""
    with _log(path) as dfr:
        yield from _read(dfr, path, topic, fields)


def _read(dfr, path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """:func:`read` on an open log."""
    m = _TOPIC.match(topic)
    if m is None:
        raise NoisevarError(f"no message {echo(topic)!r} in {echo(path.name)}")
    name, inst = m["type"], None if m["inst"] is None else int(m["inst"])
    text = isinstance(dfr, dataflash_text.TextLog)
    fmt = dfr.formats.get(name) if text else None
    fmt = fmt or next((f for f in dfr.formats.values() if f.name == name), None)
    if fmt is None or "TimeUS" not in fmt.colhash:
        raise NoisevarError(f"no message {echo(topic)!r} with TimeUS in {echo(path.name)}")
    names = tuple(fields) if fields is not None else _fields(fmt)
    have = set(_fields(fmt))
    bad = [f for f in names if f not in have]
    if bad:
        raise NoisevarError(
            f"message {echo(name)} has no numeric field {echo(bad[0])!r}; fields: "
            + ", ".join(sorted(have))
        )
    if text:
        for times, values in dataflash_text.read(dfr, name, names, inst, CHUNK):
            yield Chunk(times, values)
        return
    yield from _read_binary(dfr, fmt, names, inst)


def _read_binary(dfr, fmt, names: Sequence[str], inst: int | None) -> Iterator[Chunk]:
    """A binary log's topic, :data:`CHUNK` messages at a time, straight from the mapped file."""
    offs = np.asarray(dfr.offsets[fmt.type], dtype=np.int64)
    extra = [fmt.instance_field] if inst is not None else []
    for lo in range(0, offs.size, CHUNK):
        cols = _columns(dfr, fmt, ["TimeUS", *names, *extra], offs[lo : lo + CHUNK])
        keep = cols[fmt.instance_field] == inst if inst is not None else slice(None)
        if inst is not None and not np.any(keep):
            continue
        yield Chunk(cols["TimeUS"][keep] / 1e6, {f: cols[f][keep] for f in names})


READER = LogReader(
    name="dataflash",
    title="ArduPilot DataFlash log",
    suffixes=(".bin", ".log"),
    magic=(b"\xa3\x95\x80", b"FMT, ", b"FMT,"),
    topics=topics,
    read=read,
    read_many=read_many,
    time_note="times from TimeUS, seconds since boot",
    repair="download the log from the vehicle again (a log cut short keeps what was "
    "written), or convert it with mavlogdump.py",
    in_folders=True,
    parameters=parameters,
)
