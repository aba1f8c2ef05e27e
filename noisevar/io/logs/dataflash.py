"""ArduPilot DataFlash logs (binary ``.bin``, text ``.log``), through ``pymavlink``'s DFReader.

A topic is a message type (``IMU``, ``GPS``, ``BARO``); a type logged by several sensors
(its FMTU marks an instance field) is one topic per instance, ``IMU[0]``, ``IMU[1]``.
Fields are the numeric columns, scaled as pymavlink scales them; units come from the
log's own FMTU/UNIT/MULT messages. Times are ``TimeUS`` (microseconds since boot), in
seconds.
"""

from __future__ import annotations

import contextlib
import io
import re
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
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
    "%": "percent",
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


@contextlib.contextmanager
def _open(path: Path):
    from pymavlink import DFReader

    binary = path.open("rb").read(2) == b"\xa3\x95"
    with contextlib.redirect_stdout(io.StringIO()):  # pymavlink prints warnings
        dfr = (DFReader.DFReader_binary if binary else DFReader.DFReader_text)(
            str(path), zero_time_base=True
        )
    try:
        yield dfr
    finally:
        with contextlib.suppress(Exception):
            dfr.close() if binary else dfr.filehandle.close()


def _fields(fmt) -> tuple[str, ...]:
    cols = [
        c
        for c, f in zip(fmt.columns, fmt.format, strict=False)
        if f in _NUMERIC_FORMATS and c != "TimeUS" and c != fmt.instance_field
    ]
    return tuple(cols[:MAX_FIELDS])


def _units(fmt, fields: Sequence[str]) -> dict[str, str]:
    out = {}
    for f in fields:
        u = _pint(fmt.get_unit(f) or "")
        if u is not None:
            out[f] = u
    return out


def _records(dfr) -> dict[tuple[str, int | None], list[float]]:
    """Per (type, instance): the TimeUS of every message (one pass over the log)."""
    seen: dict[tuple[str, int | None], list[float]] = {}
    dfr.rewind()
    while (m := dfr.recv_msg()) is not None:
        fmt = m.fmt
        if "TimeUS" not in fmt.colhash or not _fields(fmt):
            continue
        inst = int(getattr(m, fmt.instance_field)) if fmt.instance_field else None
        seen.setdefault((fmt.name, inst), []).append(m.TimeUS)
    return seen


def topics(path: Path) -> list[TopicInfo]:
    """Every message type (per instance) with TimeUS and numeric columns: counts, rates, units."""
    with _open(path) as dfr:
        formats = {f.name: f for f in dfr.formats.values()}
        out = []
        for (name, inst), times in sorted(_records(dfr).items(), key=lambda kv: str(kv[0])):
            fmt = formats[name]
            fields = _fields(fmt)
            span = (times[-1] - times[0]) / 1e6 if len(times) > 1 else 0.0
            rate = (len(times) - 1) / span if span > 0 else None
            topic = name if inst is None else f"{name}[{inst}]"
            out.append(TopicInfo(topic, name, len(times), rate, fields, _units(fmt, fields)))
    return out


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The topic's fields in chunks; times in seconds since boot (TimeUS)."""
    m = _TOPIC.match(topic)
    if m is None:
        raise NoisevarError(f"no message {echo(topic)!r} in {echo(path.name)}")
    name, inst = m["type"], None if m["inst"] is None else int(m["inst"])
    with _open(path) as dfr:
        fmt = next((f for f in dfr.formats.values() if f.name == name), None)
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
        rows: list[list[float]] = []
        dfr.rewind()
        while (msg := dfr.recv_match(type=name)) is not None:
            if inst is not None and int(getattr(msg, fmt.instance_field)) != inst:
                continue
            rows.append([msg.TimeUS, *(getattr(msg, f) for f in names)])
            if len(rows) == CHUNK:
                yield _chunk(rows, names)
                rows = []
        if rows:
            yield _chunk(rows, names)


def _chunk(rows: list[list[float]], names: Sequence[str]) -> Chunk:
    arr = np.asarray(rows, dtype=float)
    return Chunk(arr[:, 0] / 1e6, {f: arr[:, i + 1] for i, f in enumerate(names)})


READER = LogReader(
    name="dataflash",
    title="ArduPilot DataFlash log",
    suffixes=(".bin", ".log"),
    magic=(b"\xa3\x95\x80", b"FMT, ", b"FMT,"),
    topics=topics,
    read=read,
    time_note="times from TimeUS, seconds since boot",
    repair="download the log from the vehicle again (a log cut short keeps what was "
    "written), or convert it with mavlogdump.py",
)
