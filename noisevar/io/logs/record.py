"""Several topics of one log as one record of columns, each on its own time base.

PX4 logs the gyroscope and the accelerometer in separate topics (``sensor_gyro_fifo``
and ``sensor_accel_fifo``, both with fields ``x y z``), and ROS bags often do too; an
IMU model needs both. :func:`load_topics` reads each topic as
:func:`~noisevar.io.logs.load_log` does (one :class:`~noisevar.io.table.LoadedTable` per
topic, with the log's timestamps), from one pass over the log where its reader can
(:func:`~noisevar.io.logs.load_logs`: a ULog is parsed once for all its topics), and
:func:`combine_topics` names their columns: a field keeps its name when one topic has it,
else it is ``topic/field`` (``sensor_gyro_fifo/x``). A column's samples, times and rate
stay its topic's: nothing is resampled or interpolated (an Allan or GMWM fit is per
column, at its own rate).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.table import LoadedTable

#: Between a topic and its field in a column's full name (``sensor_gyro_fifo/x``).
SEPARATOR = "/"


@dataclass(frozen=True)
class LogColumn:
    """One column of a :class:`TopicsRecord`: its topic's samples, times and unit.

    Attributes
    ----------
    name : str
        The column's name in the record (the field, or ``topic/field`` on a clash).
    topic, field : str
        Where it comes from.
    values : ndarray
        Its samples.
    times : ndarray or None
        Its topic's timestamps (seconds).
    sample_period : float or None
        Its topic's median time step (seconds; None: not uniform enough to say).
    unit : str or None
        Its unit as the log defines it.
    """

    name: str
    topic: str
    field: str
    values: NDArray
    times: NDArray | None
    sample_period: float | None
    unit: str | None

    @property
    def rate(self) -> float | None:
        """Samples per second of its topic (None without a sample period)."""
        return 1.0 / self.sample_period if self.sample_period else None


@dataclass(frozen=True)
class TopicsRecord:
    """Several topics of one log: each topic's table, its columns named across topics.

    Attributes
    ----------
    name : str
        The log's name (for messages).
    tables : mapping of str to LoadedTable
        Each topic's table, in the order asked.
    """

    name: str
    tables: Mapping[str, LoadedTable]

    @property
    def sources(self) -> dict[str, tuple[str, str]]:
        """Each column's name and its ``(topic, field)``: the field alone when one topic
        has it, else ``topic/field``."""
        owners: dict[str, list[str]] = {}
        for topic, table in self.tables.items():
            for f in table.data_columns:
                owners.setdefault(f, []).append(topic)
        return {
            (f if len(owners[f]) == 1 else f"{topic}{SEPARATOR}{f}"): (topic, f)
            for topic, table in self.tables.items()
            for f in table.data_columns
        }

    @property
    def columns(self) -> list[str]:
        """Every column's name, topic by topic."""
        return list(self.sources)

    @property
    def rates(self) -> dict[str, float | None]:
        """Each topic's samples per second (None: not uniform enough to say)."""
        return {
            t: 1.0 / tab.sample_period if tab.sample_period else None
            for t, tab in self.tables.items()
        }

    def resolve(self, name: str) -> tuple[str, str]:
        """The ``(topic, field)`` of a column named by field or by ``topic/field``.

        Raises
        ------
        NoisevarError
            A field several topics have, named without its topic; a name no topic has.
        """
        sources = self.sources
        if name in sources:
            return sources[name]
        for topic, table in self.tables.items():
            head = f"{topic}{SEPARATOR}"
            if name.startswith(head) and name[len(head) :] in table.data_columns:
                return topic, name[len(head) :]
        having = [t for t, table in self.tables.items() if name in table.data_columns]
        if having:
            full = " or ".join(f"{echo(t, 60)}{SEPARATOR}{echo(name, 60)}" for t in having)
            raise NoisevarError(
                f"column {echo(name, 60)!r} is in topics {', '.join(map(echo, having))}: "
                f"name it {full}"
            )
        shown = ", ".join(echo(c, 60) for c in list(sources)[:30])
        raise NoisevarError(
            f"no column {echo(name, 60)!r} in topics "
            f"{', '.join(echo(t, 60) for t in self.tables)} of {echo(self.name)}; "
            f"columns: {shown}"
        )

    def column(self, name: str) -> LogColumn:
        """One column by field or ``topic/field``, with its topic's times and rate."""
        from noisevar.io.load import pick_column

        topic, field = self.resolve(name)
        table = self.tables[topic]
        full = next(c for c, src in self.sources.items() if src == (topic, field))
        times = table.time()
        return LogColumn(
            full,
            topic,
            field,
            np.asarray(pick_column(table, field), dtype=float),
            None if times is None else np.asarray(times, dtype=float),
            table.sample_period,
            table.units.get(field),
        )


def combine_topics(name: str, tables: Mapping[str, LoadedTable]) -> TopicsRecord:
    """Topics of one log, each already read (:func:`load_topics`; the dashboard's cached
    uploads), as one record.

    Raises
    ------
    NoisevarError
        No topic given.
    """
    if not tables:
        raise NoisevarError(f"no topic of {echo(name)} chosen: give one or more (--topic T)")
    return TopicsRecord(name, dict(tables))


def load_topics(
    source: str | Path | bytes, topics: Sequence[str], name: str | None = None
) -> TopicsRecord:
    """Several topics of one log as one record (each column on its topic's time base).

    Parameters
    ----------
    source : str, path or bytes
        The log, or its bytes (an upload).
    topics : sequence of str
        Topics of :func:`~noisevar.io.logs.list_topics` (each once; order kept).
    name : str, optional
        The log's name (default: the path's name).

    Returns
    -------
    TopicsRecord

    Raises
    ------
    NoisevarError
        Not a log, unreadable, a topic not in the log (the message lists the topics).

    Examples
    --------
    >>> rec = load_topics("flight.ulg", ["sensor_gyro_fifo", "sensor_accel_fifo"])  # doctest: +SKIP
    >>> rec.columns  # doctest: +SKIP
    ['sensor_gyro_fifo/x', 'sensor_gyro_fifo/y', ..., 'sensor_accel_fifo/z']
    """
    from noisevar.io.load import load_log_tables

    if name is None:
        name = "upload" if isinstance(source, bytes | bytearray) else Path(source).name
    if not topics:
        return combine_topics(name, {})
    return combine_topics(name, load_log_tables(source, topics, name))
