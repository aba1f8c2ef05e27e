"""The log reader spec: what a reader is (:class:`LogReader`), what it lists
(:class:`TopicInfo`) and what it yields (:class:`Chunk`); shared limits."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path

from numpy.typing import NDArray

from noisevar.io.limits import MAX_BYTES

#: Most numbers one topic may hold in memory (time + fields): the table cap of
#: :data:`~noisevar.io.limits.MAX_BYTES` in float64.
MAX_VALUES = MAX_BYTES // 8
#: Messages per chunk a reader yields.
CHUNK = 1 << 16
#: Most fields a topic may list (the text table's column cap).
MAX_FIELDS = 1000
#: Suffixes other formats read too (NMEA ``.log``): a reader claims them by content only.
SHARED_SUFFIXES = (".log",)


@dataclass(frozen=True)
class TopicInfo:
    """What one topic of a log holds.

    Attributes
    ----------
    name : str
        Topic (ROS), message (ULog, DataFlash; ``name/instance`` when there are several),
        dataset path (HDF5) or ``table`` (Parquet).
    message : str
        Its message type (``sensor_msgs/msg/Imu``), or the format's kind of record.
    count : int
        Records (messages, rows).
    rate : float or None
        Mean rate (Hz) over the topic's span, when the log says it.
    fields : tuple of str
        Numeric fields, by dotted path (``angular_velocity.x``), in the log's order.
    units : mapping of str to str
        Unit of a field, as the format defines it (pint syntax: ``rad/s``, ``m/s**2``);
        fields without a defined unit are absent.
    declared : mapping of str to str
        A field whose message declares its noise variance -> the field holding it (a ROS
        message's covariance element: :mod:`noisevar.io.logs.ros_declared`).
    side : mapping of str to str
        Fields the format's message definitions say are no measured signal (an integration
        interval, a relative timestamp, a bit mask), each with what it is: the loaded
        table's :attr:`~noisevar.io.table.LoadedTable.side_columns`.
    """

    name: str
    message: str
    count: int
    rate: float | None
    fields: tuple[str, ...]
    units: Mapping[str, str] = field(default_factory=dict)
    declared: Mapping[str, str] = field(default_factory=dict)
    side: Mapping[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The topic as plain JSON-ready values."""
        return {
            "topic": self.name,
            "message": self.message,
            "count": self.count,
            "rate_hz": self.rate,
            "fields": list(self.fields),
            "units": dict(self.units),
            "declared_variance_fields": dict(self.declared),
            "side_fields": dict(self.side),
        }


@dataclass(frozen=True)
class Chunk:
    """A piece of one topic: timestamps (seconds; None when the topic has no times) and one
    float array per field."""

    times: NDArray | None
    values: Mapping[str, NDArray]


#: ``read_many(path, topics) -> {topic: (its TopicInfo, its chunks)}`` (:class:`LogReader`).
ManyReader = Callable[[Path, Sequence[str]], Mapping[str, tuple[TopicInfo, Iterator[Chunk]]]]


@dataclass(frozen=True)
class LogReader:
    """One log format.

    Attributes
    ----------
    name : str
        Registry key, also :attr:`LoadedTable.kind` of what it loads.
    title : str
        The format's name in messages.
    suffixes : tuple of str
        File suffixes it reads (lower case, with the dot).
    magic : tuple of bytes
        Prefixes of its files' first bytes.
    topics : callable
        ``topics(path) -> list[TopicInfo]``.
    read : callable
        ``read(path, topic, fields) -> Iterator[Chunk]``; ``fields`` None: the topic's
        fields; times in seconds (the log's clock, see ``time_note``).
    time_note : str
        Where the timestamps come from, for the loaded table's notes.
    repair : str
        What to do with a log the library cannot read.
    read_many : callable or None
        ``read_many(path, topics) -> {topic: (TopicInfo, Iterator[Chunk])}``: several topics
        (all their fields) from one pass over a log its library parses whole (ULog); a topic
        not in the log is left out. None: each topic is read on its own.
    in_folders : bool
        Whether ``noisevar batch`` takes its files when it searches a folder (recordings and
        exports: bags, ULog, DataFlash, workbooks); else only when named or matched by a
        pattern (Parquet and HDF5 tables are often a batch's own output).
    parameters : callable or None
        ``parameters(path) -> {name: value}``: the vehicle's configuration the log carries
        (ULog's initial parameters, DataFlash ``PARM``: :mod:`noisevar.io.logs.params`);
        None: the format carries none.
    """

    name: str
    title: str
    suffixes: tuple[str, ...]
    magic: tuple[bytes, ...]
    topics: Callable[[Path], list[TopicInfo]]
    read: Callable[[Path, str, Sequence[str] | None], Iterator[Chunk]]
    time_note: str
    repair: str = "check that the file is complete and is the format its name says"
    read_many: ManyReader | None = None
    in_folders: bool = False
    parameters: Callable[[Path], dict[str, float]] | None = None

    @property
    def article(self) -> str:
        """``a`` or ``an`` before :attr:`title`."""
        return "an" if self.title[:1] in "AEIOH" else "a"

    def matches(self, name: str, head: bytes) -> bool:
        """Whether this reader claims a file: its first bytes, else its suffix."""
        if any(head.startswith(m) for m in self.magic):
            return True
        lower = name.lower()
        return any(lower.endswith(s) for s in self.suffixes if s not in SHARED_SUFFIXES)


_NOTES: ContextVar[tuple[list[str], ...]] = ContextVar("noisevar_log_notes", default=())


def report(note: str) -> None:
    """Tell the user something about the log being read (a file cut short, say): it joins
    every enclosing :func:`collecting` list (the loaded table's notes, a batch row's), once."""
    for got in _NOTES.get():
        if note not in got:
            got.append(note)


@contextmanager
def collecting(notes: list[str]) -> Iterator[None]:
    """Collect the readers' :func:`report` notes made in this block into ``notes`` (nested
    blocks each get them)."""
    token = _NOTES.set((*_NOTES.get(), notes))
    try:
        yield
    finally:
        _NOTES.reset(token)
