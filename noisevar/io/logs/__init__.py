"""Logs of robots and vehicles: ROS 1/2 bags, PX4 ULog, ArduPilot DataFlash, Parquet, HDF5.

A log holds several *topics* (ROS topics, ULog or DataFlash messages, HDF5 datasets,
the one table of a Parquet file), each a stream of records with numeric fields and the
log's own timestamps. :func:`list_topics` says what a log holds (names, fields, counts,
rates, units where the format defines them); :func:`read_topic` streams one topic's
fields in chunks; :func:`load_log` gathers one topic into a
:class:`~noisevar.io.table.LoadedTable` whose time column is the log's timestamps, so
gaps and jitter reach the diagnostics as they are. :func:`~noisevar.io.load.load_table`
calls it for any file a reader claims.

Each format is one module of this package defining ``READER`` (a :class:`LogReader`)
plus one line of :data:`READERS`. A reader imports its library (``rosbags``,
``pyulog``, ``pymavlink``, ``pyarrow``, ``h5py``) only when it reads.

Untrusted logs: nothing is unpickled or evaluated; a log the library cannot parse
(truncated, corrupt, not the format its name says) is one
:class:`~noisevar.errors.NoisevarError` saying so and what to do; the values held in
memory are capped (:data:`MAX_VALUES`), never the log's size, since only one topic is
held.
"""

from __future__ import annotations

import contextlib
import importlib
import io
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.repaired import bag_files, unclosed_dir
from noisevar.io.logs.spec import (
    CHUNK,
    MAX_FIELDS,
    MAX_VALUES,
    SHARED_SUFFIXES,
    Chunk,
    LogReader,
    TopicInfo,
    collecting,
)
from noisevar.units import sensor_of

__all__ = [
    "CHUNK",
    "MAX_FIELDS",
    "MAX_VALUES",
    "READERS",
    "SHARED_SUFFIXES",
    "Chunk",
    "LogReader",
    "TopicInfo",
    "default_topic",
    "find_topic",
    "is_ros2_dir",
    "list_topics",
    "load_log",
    "load_logs",
    "log_kinds",
    "log_suffixes",
    "read_topic",
    "reader_for",
    "reader_of",
    "readers",
]

#: The log readers: name -> module defining ``READER``. A new format is one module + one line.
READERS: dict[str, str] = {
    "rosbag": "noisevar.io.logs.rosbag",
    "ulog": "noisevar.io.logs.ulog",
    "dataflash": "noisevar.io.logs.dataflash",
    "parquet": "noisevar.io.logs.parquet",
    "hdf5": "noisevar.io.logs.hdf5",
    "matlab": "noisevar.io.logs.matlab",
    "workbook": "noisevar.io.logs.workbook",
}


def readers() -> list[LogReader]:
    """Every registered reader, in :data:`READERS` order."""
    return [importlib.import_module(mod).READER for mod in READERS.values()]


def log_kinds() -> str:
    """The formats the readers read, for help texts: ``"ROS bag, PX4 ULog, ... or
    spreadsheet workbook"``."""
    titles = [r.title for r in readers()]
    return ", ".join(titles[:-1]) + " or " + titles[-1]


def log_suffixes() -> tuple[str, ...]:
    """File suffixes some reader reads (for an upload widget)."""
    return tuple(dict.fromkeys(s for r in readers() for s in r.suffixes))


def reader_for(name: str, head: bytes = b"") -> LogReader | None:
    """The reader of a file (by its first bytes, else its name), or None: not a log."""
    return next((r for r in readers() if r.matches(name, head)), None)


def is_ros2_dir(path: Path) -> bool:
    """Whether ``path`` is a ROS 2 bag directory: ``metadata.yaml`` inside, or one bag file
    and no ``metadata.yaml`` (a recording that never closed: that file is read)."""
    return path.is_dir() and ((path / "metadata.yaml").is_file() or unclosed_dir(path) is not None)


def reader_of(path: Path, name: str) -> LogReader:
    """The reader of the log at ``path`` (by its content, else its name), or an error."""
    if is_ros2_dir(path):
        return next(r for r in readers() if r.name == "rosbag")
    if path.is_dir():  # not a bag directory (is_ros2_dir): say what it holds
        files = bag_files(path)
        held = (
            f"{len(files)} bag files and no metadata.yaml (a split recording that never "
            f"closed): give one file, e.g. {echo(files[0].name)}"
            if files
            else "no metadata.yaml and no .mcap or .db3 file: give a log file or a ROS 2 bag "
            "directory"
        )
        raise NoisevarError(f"{echo(name)} is a directory with {held}")
    try:
        with path.open("rb") as fh:
            head = fh.read(64)
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(name)}: {exc.strerror or exc}") from None
    reader = reader_for(name, head)
    if reader is None:
        raise NoisevarError(
            f"{echo(name)} is not a log noisevar reads: give a ROS bag (.bag, .mcap, .db3 or a "
            "ROS 2 bag directory), PX4 ULog (.ulg), ArduPilot DataFlash (.bin, .log), "
            "Parquet or HDF5 file"
        )
    return reader


def _failed(reader: LogReader, name: str, exc: BaseException) -> NoisevarError:
    what = f"{type(exc).__name__}: {echo(exc, 160)}" if str(exc) else type(exc).__name__
    return NoisevarError(
        f"{echo(name)} could not be read as {reader.article} {reader.title} ({what}): "
        f"{reader.repair}"
    )


def list_topics(path: str | Path, name: str | None = None) -> list[TopicInfo]:
    """The topics of a log.

    Parameters
    ----------
    path : str or path
        The log (a ROS 2 bag may be its directory).
    name : str, optional
        Name for messages and format detection (default: the path's name).

    Returns
    -------
    list of TopicInfo

    Raises
    ------
    NoisevarError
        Not a log, or a log its library cannot read (truncated, corrupt).
    """
    path = Path(path)
    name = name or path.name
    reader = reader_of(path, name)
    try:
        with _quiet(None):
            return reader.topics(path)
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - each library raises its own types on bad logs
        raise _failed(reader, name, exc) from None


def default_topic(topics: Sequence[TopicInfo]) -> TopicInfo | None:
    """The topic a log opens on: the first (in the log's order) whose fields hold both an
    angular rate and an acceleration (an IMU: a ROS ``sensor_msgs/Imu``, PX4's
    ``sensor_combined``), else the first with either, else the first with numbers; None
    when none has (the first topic in name order is a ROS log's ``/markers`` or PX4's
    ``actuator_armed``, seldom the sensor an engineer came for)."""
    usable = [t for t in topics if t.fields and t.count > 0]

    def kinds(t: TopicInfo) -> set[str]:
        return {k for f in t.fields if (k := sensor_of(t.units.get(f))) is not None}

    both = [t for t in usable if len(kinds(t)) == 2]
    either = [t for t in usable if kinds(t)]
    return next(iter(both + either + usable), None)


def find_topic(topics: Sequence[TopicInfo], topic: str | None, name: str) -> TopicInfo:
    """The topic called ``topic`` (the only one with fields when None), else an error that
    lists the topics."""
    usable = [t for t in topics if t.fields and t.count > 0]
    if topic is None and len(usable) == 1:
        return usable[0]
    hit = next((t for t in topics if t.name == topic), None)
    if hit is not None and hit.fields and hit.count > 0:
        return hit
    listed = ", ".join(
        f"{echo(t.name, 40)} ({echo(t.message, 40)}, {t.count})" for t in usable[:30]
    )
    more = f" and {len(usable) - 30} more" if len(usable) > 30 else ""
    if topic is None:
        what = f"{echo(name)} holds several topics: choose one (CLI --topic)"
    elif hit is not None:
        what = f"topic {echo(topic)!r} of {echo(name)} has no numeric field or no record"
    else:
        what = f"no topic {echo(topic)!r} in {echo(name)}"
    hint = f"; topics: {listed}{more}" if usable else "; it has no topic with numbers"
    raise NoisevarError(what + hint)


def read_topic(
    path: str | Path,
    topic: str,
    fields: Sequence[str] | None = None,
    name: str | None = None,
    problems: list[str] | None = None,
) -> Iterator[Chunk]:
    """One topic of a log, streamed: chunks of timestamps (seconds) and field values.

    Parameters
    ----------
    path : str or path
        The log.
    topic : str
        A topic of :func:`list_topics`.
    fields : sequence of str, optional
        Fields by dotted path (default: all the topic's fields).
    name : str, optional
        Name for messages (default: the path's name).
    problems : list, optional
        Receives what the library printed while reading (skipped corrupt stretches).

    Yields
    ------
    Chunk

    Raises
    ------
    NoisevarError
        Not a log, unreadable, unknown topic or field.
    """
    path = Path(path)
    name = name or path.name
    reader = reader_of(path, name)
    chunks = reader.read(path, topic, None if fields is None else tuple(fields))
    try:
        while True:
            with _quiet(problems):  # per step: the caller's own prints between chunks stay
                chunk = next(chunks, None)
            if chunk is None:
                return
            yield chunk
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - each library raises its own types on bad logs
        raise _failed(reader, name, exc) from None


class _Sink(io.TextIOBase):
    """Where a library's prints go while it reads: its first lines kept, the rest counted."""

    def __init__(self, problems: list[str] | None):
        self.problems = problems

    def write(self, text: str) -> int:
        line = text.strip()
        if line and self.problems is not None and len(self.problems) < 1000:
            self.problems.append(line)
        return len(text)


@contextlib.contextmanager
def _quiet(problems: list[str] | None) -> Iterator[None]:
    """Silence a library's prints to stdout/stderr (pyulog and pymavlink report skipped
    corrupt bytes there); keep them in ``problems``."""
    sink = _Sink(problems)
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        yield


def _gather(chunks: Iterator[Chunk], names: Sequence[str], max_values: int) -> tuple:
    times: list[NDArray] = []
    cols: dict[str, list[NDArray]] = {f: [] for f in names}
    held = 0
    timed = True
    for ch in chunks:
        rows = len(next(iter(ch.values.values()))) if ch.values else 0
        held += rows * (len(names) + 1)
        if held > max_values:
            raise NoisevarError(
                f"the topic holds over {max_values:,} numbers: read fewer fields "
                "(Python: load_log(..., fields=[...])) or a shorter log"
            )
        timed = timed and ch.times is not None
        times.append(np.asarray(ch.times if timed else np.arange(rows), dtype=float))
        for f in names:
            cols[f].append(np.asarray(ch.values[f], dtype=float))
    t = np.concatenate(times) if times else np.empty(0)
    cols = {f: (np.concatenate(v) if v else np.empty(0)) for f, v in cols.items()}
    return (t if timed else None), cols, t.size


def load_log(
    path: str | Path,
    topic: str | None = None,
    fields: Sequence[str] | None = None,
    name: str | None = None,
    *,
    max_values: int = MAX_VALUES,
):
    """One topic of a log as a table: column ``time`` (the log's timestamps) and its fields.

    Parameters
    ----------
    path : str or path
        The log.
    topic : str, optional
        The topic; may be omitted when the log has one topic with numbers.
    fields : sequence of str, optional
        Fields by dotted path (default: the topic's fields).
    name : str, optional
        Name for messages (default: the path's name).
    max_values : int
        Most numbers held (:data:`MAX_VALUES`).

    Returns
    -------
    LoadedTable
        ``kind`` the reader's name, ``units`` the fields' units where the format defines
        them, ``notes`` the topic and where its times come from.

    Raises
    ------
    NoisevarError
        Not a log, unreadable, unknown topic (the message lists the topics) or field.
    """
    path = Path(path)
    name = name or path.name
    info = find_topic(list_topics(path, name), topic, name)
    names = tuple(dict.fromkeys(fields)) if fields is not None else info.fields
    if not names:
        raise NoisevarError(f"no field asked of topic {echo(info.name)!r}")
    problems: list[str] = []
    # the fields that hold the asked fields' declared variances are read beside them
    extra = tuple(dict.fromkeys(v for f, v in info.declared.items() if f in names))
    extra = tuple(v for v in extra if v not in names)
    chunks = read_topic(path, info.name, names + extra, name, problems)
    reader = reader_of(path, name)
    return _table(reader, name, info, names + extra, chunks, problems, max_values, extra)


def with_time_unit(table, path: str | Path, topic: str | None, told):
    """A log's topic ``table`` with the time unit the user stated (``told``, a
    :class:`~noisevar.io.time_option.StatedTime`, or None: unchanged).

    An HDF5 topic without a time dataset takes the step its datasets declare (``dx``,
    ``dt``: :func:`~noisevar.io.logs.hdf5.declared_step`) in that unit as its period, only
    then; anywhere else a note says the unit is not used (the log's timestamps are read in
    the unit its format or the time field's name states, :func:`~noisevar.io.table.time_scale`).
    """
    from noisevar.io.logs import hdf5
    from noisevar.io.time_option import unused_note

    if told is None:
        return table
    if table.kind == hdf5.READER.name and table.time_column is None:
        info = find_topic(list_topics(path, table.name), topic, table.name)
        said = hdf5.declared_step(Path(path), info.name)
        if said is not None:
            table.sample_period, note = told.step(*said)
            table.notes = [n for n in table.notes if not n.startswith(hdf5.STEP_NOTE)]
            table.notes.append(note)
            return table
    why = (
        "the log's timestamps are read as its format or field names state"
        if table.time_column
        else "the topic has no time field and declares no step (dx, dt)"
    )
    table.notes.append(unused_note(told, why))
    return table


def load_logs(
    path: str | Path,
    topics: Sequence[str],
    name: str | None = None,
    *,
    max_values: int = MAX_VALUES,
) -> dict:
    """Several topics of a log, each as :func:`load_log` reads it (all its fields), from one
    pass over the log where its reader can (``LogReader.read_many``: ULog), else topic by
    topic.

    Parameters
    ----------
    path : str or path
        The log.
    topics : sequence of str
        Topics of :func:`list_topics` (order kept, each once).
    name : str, optional
        Name for messages (default: the path's name).
    max_values : int
        Most numbers held per topic (:data:`MAX_VALUES`).

    Returns
    -------
    dict of str to LoadedTable
        Each topic's table, equal to ``load_log(path, topic)``'s.

    Raises
    ------
    NoisevarError
        Not a log, unreadable, a topic not in the log (the message lists the topics).
    """
    path = Path(path)
    name = name or path.name
    wanted = list(dict.fromkeys(topics))
    reader = reader_of(path, name)
    if reader.read_many is None or len(wanted) < 2:
        return {t: load_log(path, t, None, name, max_values=max_values) for t in wanted}
    problems: list[str] = []
    out = {}
    try:
        with _quiet(problems):
            got = reader.read_many(path, wanted)
            for topic in wanted:
                info, chunks = got.get(topic, (None, None))
                if info is None or not info.fields or info.count == 0:
                    find_topic(list_topics(path, name), topic, name)  # lists the topics
                    raise NoisevarError(f"no topic {echo(topic)!r} in {echo(name)}")
                out[topic] = _table(reader, name, info, info.fields, chunks, problems, max_values)
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - each library raises its own types on bad logs
        raise _failed(reader, name, exc) from None
    return out


def _table(
    reader: LogReader,
    name: str,
    info: TopicInfo,
    names: Sequence[str],
    chunks: Iterator[Chunk],
    problems: list[str],
    max_values: int,
    extra: Sequence[str] = (),
):
    """One topic's chunks gathered into a :class:`~noisevar.io.table.LoadedTable`; ``extra``:
    fields read only for the variances they declare (not columns of the table)."""
    from noisevar.io.table import LoadedTable, _period_from_time

    said: list[str] = []  # what the reader reports of the file (cut short...)
    with collecting(said):
        t, cols, rows = _gather(chunks, names, max_values)
    if rows == 0:
        raise NoisevarError(f"topic {echo(info.name)!r} of {echo(name)} has no record")
    where = reader.time_note if t is not None else "no time column: samples taken as uniform"
    notes = [f"topic {info.name} ({info.message}), {rows:,} records; {where}", *said]
    if problems:
        notes.append(
            f"the {reader.title} reader reported {len(problems):,} problems (corrupt stretches "
            f"are skipped), the first: {echo(problems[0], 120)}"
        )
    declared = _declared(info, cols)
    for f in extra:
        cols.pop(f, None)
    units = {f: u for f, u in info.units.items() if f in cols}
    side = {f: what for f, what in info.side.items() if f in cols}
    if t is None or "time" in cols:
        return LoadedTable(name, cols, reader.name, None, None, notes, units, declared, side)
    period = _period_from_time(t, notes)
    return LoadedTable(
        name, {"time": t, **cols}, reader.name, "time", period, notes, units, declared, side
    )


def _declared(info: TopicInfo, cols: dict) -> dict[str, float]:
    """Each field's declared variance: the median over the messages of the field holding
    it; ROS's 0 (unknown) and -1 (not given) declare none."""
    out = {}
    for f, source in info.declared.items():
        values = cols.get(source)
        if f not in cols or values is None or not values.size:
            continue
        med = float(np.nanmedian(values))
        if np.isfinite(med) and med > 0:
            out[f] = med
    return out
