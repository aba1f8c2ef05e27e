"""HDF5 files (``.h5``, ``.hdf5``), through ``h5py``, read by slices.

Topics are:

- a table (a dataset of a compound type, as PyTables and pandas write): its numeric
  fields; a field named like a time (:data:`~noisevar.io.table.TIME_NAMES`) gives the times;
- a 2-D numeric dataset ``(n, k)``: fields ``col0 .. col{k-1}``; a dataset of more
  dimensions ``(n, a, b, ...)`` (netCDF4 and xarray's, samples first): a field per slice,
  ``col{i}_{j}...``;
- a group holding 1-D numeric datasets of one length: one field per dataset, and the one
  named like a time gives the times. A dataset's ``units`` (or ``unit``) attribute is its
  unit. A dimension scale (a netCDF4 coordinate: ``channel``, ``component``) is a
  coordinate, not a measurement: it gives the times when named like one, never a field.

For safety, external links, virtual datasets and datasets stored in external files are
skipped: an HDF5 file cannot make noisevar read another file.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator, Sequence
from itertools import islice
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.spec import CHUNK, MAX_FIELDS, Chunk, LogReader, TopicInfo, report
from noisevar.io.table import is_time_column, time_scale
from noisevar.io.time_option import how_to_state

#: Most objects of a file looked at (a file of millions of objects is not a sensor log).
MAX_OBJECTS = 100_000


def _safe_datasets(f) -> dict[str, object]:
    """Every local, non-virtual, internally stored dataset of the file, by path."""
    import h5py

    found: dict[str, object] = {}
    seen = 0

    def visit(group, prefix: str) -> None:
        nonlocal seen
        for key in group:
            seen += 1
            if seen > MAX_OBJECTS:
                raise NoisevarError(f"the file holds over {MAX_OBJECTS:,} objects")
            link = group.get(key, getlink=True)
            if not isinstance(link, h5py.HardLink):
                continue  # soft and external links: skipped
            obj = group[key]
            path = f"{prefix}/{key}"
            if isinstance(obj, h5py.Group):
                visit(obj, path)
            elif obj.is_virtual or obj.external:
                continue
            else:
                found[path] = obj

    visit(f, "")
    return found


def _numeric(dtype) -> bool:
    return dtype.kind in "biuf"


def _unit(ds) -> str | None:
    for key in ("units", "unit"):
        value = ds.attrs.get(key)
        if isinstance(value, bytes):
            value = value.decode("utf-8", "replace")
        if isinstance(value, str) and value:
            return echo(value, 40)
    return None


def _is_scale(ds) -> bool:
    """Whether a dataset is a dimension scale (a netCDF4/xarray coordinate).

    Notes
    -----
    pyphysio's ``.ph`` (an xarray netCDF4 file) holds ``channel`` (26), ``component`` (2)
    and ``time`` (8,790) beside a 3-D ``signal``: the channel numbers were read as the
    signal and refused as "a counter or a clock".
    """
    cls = ds.attrs.get("CLASS")
    return (cls.decode("ascii", "replace") if isinstance(cls, bytes) else cls) == "DIMENSION_SCALE"


def _coordinate(path: str, ds) -> bool:
    """A dimension scale not named like a time: a coordinate, never a field."""
    return _is_scale(ds) and not is_time_column(path.rpartition("/")[2])


def _scale_time(ds) -> tuple[str, None] | None:
    """The time source of a dataset of 2 or more dimensions: the dimension scale of its
    first dimension named like a time (netCDF4's ``time`` coordinate), or None."""
    for scale in ds.dims[0].values():
        ok = scale.ndim == 1 and scale.shape[0] == ds.shape[0] and _numeric(scale.dtype)
        if (
            ok
            and not (scale.is_virtual or scale.external)
            and is_time_column(scale.name.rpartition("/")[2])
        ):
            return (scale.name, None)
    return None


def _slices(shape: tuple[int, ...]) -> list[tuple[int, ...]]:
    """The index of each field of a dataset of more than one dimension, samples first."""
    idx = list(islice(np.ndindex(*shape[1:]), MAX_FIELDS))  # never all of a huge shape
    return [i[0] if len(i) == 1 else i for i in idx]


def _topics_of(f) -> dict[str, tuple[str | None, dict[str, tuple], int, dict[str, str]]]:
    """Topic -> (time source, {field: (dataset path, column or field)}, rows, units)."""
    out = {}
    datasets = _safe_datasets(f)
    groups: dict[str, list[tuple[str, object]]] = {}
    for path, ds in datasets.items():
        if ds.dtype.names:
            names = [n for n in ds.dtype.names if _numeric(ds.dtype[n]) and ds.ndim == 1]
            time = next((n for n in names if is_time_column(n)), None)
            fields = {n: (path, n) for n in names if n != time}
            out[path] = ((path, time) if time else None, fields, int(ds.shape[0]), {})
        elif ds.ndim >= 2 and _numeric(ds.dtype):
            fields = {"col" + "_".join(map(str, np.atleast_1d(j))): (path, j)
                      for j in _slices(ds.shape)}  # fmt: skip
            out[path] = (_scale_time(ds), fields, int(ds.shape[0]), {})
        elif ds.ndim == 1 and _numeric(ds.dtype) and not _coordinate(path, ds):
            groups.setdefault(path.rpartition("/")[0] or "/", []).append((path, ds))
    for gpath, members in groups.items():
        length = Counter(int(ds.shape[0]) for _, ds in members).most_common(1)[0][0]
        same = [(p, ds) for p, ds in members if ds.shape[0] == length]
        time = next((p for p, _ in same if is_time_column(p.rpartition("/")[2])), None)
        fields = {p.rpartition("/")[2]: (p, None) for p, _ in same if p != time}
        units = {p.rpartition("/")[2]: u for p, ds in same if p != time and (u := _unit(ds))}
        out[gpath] = ((time, None) if time else None, fields, length, units)
    return {k: v for k, v in out.items() if v[1]}


def _rate(f, time, rows: int) -> float | None:
    if time is None or rows < 2:
        return None
    path, field = time
    ds = f[path]
    first, last = (ds[0][field], ds[-1][field]) if field else (ds[0], ds[-1])
    exact = np.issubdtype(np.asarray(first).dtype, np.integer)  # an epoch in ns: exact
    step = int(last) - int(first) if exact else float(last) - float(first)
    span = step * time_scale(_time_name(time), float(first))
    return (rows - 1) / span if span > 0 else None


def _time_name(time: tuple) -> str:
    """The time source's own name: its field, or its dataset's last path component."""
    path, field = time
    return field if isinstance(field, str) else path.rpartition("/")[2]


def topics(path: Path) -> list[TopicInfo]:
    """Tables, 2-D datasets and groups of 1-D datasets: rows, rate, fields, units."""
    import h5py

    with h5py.File(path, "r") as f:
        return [
            TopicInfo(name, "hdf5 table", rows, _rate(f, time, rows), tuple(fields), units)
            for name, (time, fields, rows, units) in sorted(_topics_of(f).items())
        ]


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The topic's fields, :data:`CHUNK` rows at a time."""
    import h5py

    with h5py.File(path, "r") as f:
        found = _topics_of(f)
        if topic not in found:
            raise NoisevarError(f"no table {echo(topic)!r} in {echo(path.name)}")
        time, have, rows, _ = found[topic]
        names = tuple(fields) if fields is not None else tuple(have)
        bad = [n for n in names if n not in have]
        if bad:
            raise NoisevarError(
                f"table {echo(topic)!r} has no numeric field {echo(bad[0])!r}; fields: "
                + ", ".join(echo(n, 40) for n in list(have)[:40])
            )
        if time is None:
            _step_said(f, [have[n][0] for n in names])
        # its name's unit, or the unit its first value is a Unix time in
        scale = None if time is None else time_scale(_time_name(time), _slice(f, *time, 0, 1)[0])
        for lo in range(0, rows, CHUNK):
            hi = min(lo + CHUNK, rows)
            t = None if time is None else _slice(f, *time, lo, hi) * scale
            yield Chunk(t, {n: _slice(f, *have[n], lo, hi) for n in names})


#: attributes of a dataset that declare its sample step (gwpy's ``dx``) or rate
_STEP_ATTRS = ("dx", "dt", "sample_rate", "sampling_rate")


def _step_said(f, paths: list[str]) -> None:
    """Say (a load note) a step or rate the datasets declare in an attribute when there is
    no time dataset: its unit is not written (gwpy's ``dx`` is in seconds for a time series,
    in Hz for a spectrum), so it is not taken as the period.

    Notes
    -----
    gwpy's HDF5 of LIGO's and Virgo's strain (1 s at 16,384 Hz, ``dx`` = 6.1e-5) was read as
    samples taken as uniform, 1 a second, without a word of its ``dx``.
    """
    said = _declared(f, paths)
    if said is not None:
        key, value = said
        step = key in _STEPS
        what = "time step in seconds" if step else "sample rate in Hz"
        report(f"{STEP_NOTE} {key} = {value:.6g} without a unit, not read as the sample period: "
               f"if it is the {what}, give --rate {1.0 / value if step else value:.6g} where a "
               f"rate counts (allan, imu, fit){_or_state(step)}")  # fmt: skip


#: The attributes that declare a step (the rest: a rate), and how the notes start.
_STEPS, STEP_NOTE = ("dx", "dt"), "its datasets declare"


def _or_state(step: bool) -> str:
    return f", or state its unit: {how_to_state('s')}" if step else ""


def _declared(f, paths: list[str]) -> tuple[str, float] | None:
    """The first of :data:`_STEP_ATTRS` the first dataset declares (a positive number)."""
    attrs = f[paths[0]].attrs if paths else {}
    for key in _STEP_ATTRS:
        value = np.asarray(attrs.get(key, np.nan)).ravel()
        if value.size == 1 and value.dtype.kind in "iuf" and np.isfinite(value[0]) and value[0] > 0:
            return key, float(value[0])
    return None


def declared_step(path: Path, topic: str) -> tuple[str, float] | None:
    """The step (``dx``, ``dt``) the datasets of ``topic`` declare when it has no time
    dataset, else None (a rate attribute is no step)."""
    import h5py

    with h5py.File(path, "r") as f:
        time, have, _, _ = _topics_of(f).get(topic, (None, {}, 0, {}))
        said = None if time is not None else _declared(f, [p for p, _ in have.values()])
    return said if said is not None and said[0] in _STEPS else None


def _slice(f, path: str, part, lo: int, hi: int) -> np.ndarray:
    ds = f[path]
    if part is None:
        return np.asarray(ds[lo:hi], dtype=float)
    if isinstance(part, (int, tuple)):
        return np.asarray(ds[(slice(lo, hi), *np.atleast_1d(part))], dtype=float)
    return np.asarray(ds.fields(part)[lo:hi], dtype=float)


READER = LogReader(
    name="hdf5",
    title="HDF5 file",
    suffixes=(".h5", ".hdf5", ".hdf"),
    magic=(b"\x89HDF\r\n\x1a\n",),
    topics=topics,
    read=read,
    time_note="times from the table's time field",
)
