"""Parquet tables (``.parquet``), through ``pyarrow``, streamed by record batches.

A Parquet file is one topic, ``table``. Its numeric columns are the fields; a column
named like a time (:data:`~noisevar.io.table.TIME_NAMES`) or of a timestamp type gives
the times (a timestamp, or integers beyond 2**53, in seconds from the first row). A
field's unit is its column metadata ``unit`` (or ``units``) when the writer set one.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo
from noisevar.io.table import is_time_column, time_scale

TOPIC = "table"


def _layout(schema) -> tuple[str | None, tuple[str, ...], dict[str, str]]:
    """The time column, the numeric fields and their units of an Arrow schema."""
    import pyarrow as pa

    time, fields, units = None, [], {}
    for col in schema:
        t = col.type
        if pa.types.is_timestamp(t) or (
            (pa.types.is_integer(t) or pa.types.is_floating(t)) and is_time_column(col.name)
        ):
            time = time or col.name
            continue
        if pa.types.is_integer(t) or pa.types.is_floating(t) or pa.types.is_boolean(t):
            fields.append(col.name)
            meta = col.metadata or {}
            unit = meta.get(b"unit") or meta.get(b"units")
            if unit:
                units[col.name] = echo(unit.decode("utf-8", "replace"), 40)
    return time, tuple(fields[:MAX_FIELDS]), units


def topics(path: Path) -> list[TopicInfo]:
    """The one topic ``table``: its rows, mean rate (with a time column), fields and units."""
    import pyarrow.parquet as pq

    pf = pq.ParquetFile(path)
    time, fields, units = _layout(pf.schema_arrow)
    n = pf.metadata.num_rows
    rate = None
    if time is not None and n > 1:
        groups = range(pf.metadata.num_row_groups)
        stats = [pf.metadata.row_group(i).column(_index(pf, time)).statistics for i in groups]
        if all(s is not None and s.has_min_max for s in stats):
            lo, hi = min(s.min for s in stats), max(s.max for s in stats)
            if isinstance(hi, int) and isinstance(lo, int):  # exact: an epoch in ns
                span = (hi - lo) * time_scale(time, lo)
            else:
                span = (_seconds(hi) - _seconds(lo)) * (
                    1.0 if hasattr(hi, "timestamp") else time_scale(time, _seconds(lo))
                )
            rate = (n - 1) / span if span > 0 else None
    return [TopicInfo(TOPIC, "parquet table", int(n), rate, fields, units)]


def _index(pf, name: str) -> int:
    return pf.schema_arrow.get_field_index(name)


def _seconds(value) -> float:
    """A time statistic in seconds (a datetime, or a number taken as seconds)."""
    if hasattr(value, "timestamp"):
        return float(value.timestamp())
    return float(value)


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The table's fields, one record batch at a time; times as the time column says."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    if topic != TOPIC:
        raise NoisevarError(f"a Parquet file has one topic, {TOPIC!r}; not {echo(topic)!r}")
    pf = pq.ParquetFile(path)
    time, have, _ = _layout(pf.schema_arrow)
    names = tuple(fields) if fields is not None else have
    bad = [f for f in names if f not in have]
    if bad:
        raise NoisevarError(
            f"{echo(path.name)} has no numeric column {echo(bad[0])!r}; columns: "
            + ", ".join(echo(f, 40) for f in have[:40])
        )
    origin, scale = None, None
    cols = [*names, time] if time else list(names)
    is_ts = time is not None and pa.types.is_timestamp(pf.schema_arrow.field(time).type)
    for batch in pf.iter_batches(batch_size=CHUNK, columns=cols):
        t = None
        if time is not None:
            arr = batch.column(time)
            if is_ts:
                arr = arr.cast(pa.timestamp("ns")).cast(pa.int64())
            raw = arr.to_numpy(zero_copy_only=False)
            if scale is None and raw.size:  # its name's unit, or its first value's epoch unit
                scale = 1e-9 if is_ts else time_scale(time, float(raw[0]))
            if is_ts or (raw.dtype.kind in "iu" and (origin is not None or _big(raw))):
                origin = int(raw[0]) if origin is None else origin
                t = (raw - origin) * scale
            else:  # a number column: in seconds, or in the unit its name states (time_ns)
                t = raw.astype(float) * (scale or 1.0)
        values = {f: _floats(batch.column(f)) for f in names}
        yield Chunk(t, values)


def _big(raw: np.ndarray) -> bool:
    return raw.size > 0 and float(np.abs(raw).max()) > 2**53


def _floats(arr) -> np.ndarray:
    """An Arrow column as float64, nulls as NaN."""
    import pyarrow as pa

    return arr.cast(pa.float64()).to_numpy(zero_copy_only=False)


READER = LogReader(
    name="parquet",
    title="Parquet table",
    suffixes=(".parquet", ".pq"),
    magic=(b"PAR1",),
    topics=topics,
    read=read,
    time_note="times from the table's time column",
)
