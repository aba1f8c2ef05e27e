"""MATLAB ``.mat`` files (versions 4 to 7.2), through ``scipy.io``; nothing is evaluated.

Each numeric variable is a topic: a vector is one field (its own name); a matrix is samples
by channels, fields ``0``, ``1``, ... (a k x n matrix with k <= 16 < n is n samples of k
channels: MATLAB users store both). The times are a top-level vector named like a time
(``t``, ``time``, ``timestamp``) of the topic's length, in seconds unless its name states a
unit (``time_ns``). Variables are sized from their headers (``whosmat``) before they are
read: more than ``MAX_VALUES`` numbers are refused. A struct or cell is not read (its size
is known only once decompressed, and a compressed file can hold a thousand times its size):
``save(f, '-struct', 's')`` saves a struct's fields as variables. A v7.3 file is HDF5 with
MATLAB's column-major layout: saved again with ``-v7`` it has the same numbers.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs.spec import MAX_FIELDS, MAX_VALUES, Chunk, LogReader, TopicInfo
from noisevar.io.table import is_time_column, time_scale

#: At most this many channels in a matrix read as samples by channels.
MAX_CHANNELS = 16


def _whos(path: Path) -> list[tuple[str, tuple[int, ...], str]]:
    """The variables' names, shapes and classes from their headers; v7.3 refused."""
    import scipy.io as sio

    try:
        found = sio.whosmat(str(path))
    except NotImplementedError:
        raise NoisevarError(
            f"{echo(path.name)} is a MATLAB v7.3 file (HDF5): save it with save(..., '-v7') "
            "or export the variables as CSV"
        ) from None
    total = sum(int(np.prod(s)) for _, s, c in found if c not in ("struct", "cell", "char"))
    if total > MAX_VALUES:
        raise NoisevarError(
            f"{echo(path.name)} holds {total:,} numbers, over the limit of {MAX_VALUES:,}: "
            "save fewer variables"
        )
    return found


def _load(path: Path, names: Sequence[str]) -> dict:
    import scipy.io as sio

    return sio.loadmat(str(path), variable_names=list(names), squeeze_me=True,
                       struct_as_record=False, chars_as_strings=True)  # fmt: skip


def _samples(a: np.ndarray) -> np.ndarray | None:
    """A numeric variable as samples by channels (2-D), or None when it is no signal."""
    a = np.asarray(a)
    if a.dtype.kind not in "biuf" or a.size < 2 or a.ndim > 2:
        return None
    if a.ndim == 1:
        return a[:, None]
    if a.shape[0] <= MAX_CHANNELS < a.shape[1]:
        a = a.T
    return a if a.shape[1] <= MAX_FIELDS else None


def _topics(path: Path) -> dict[str, tuple[dict[str, np.ndarray], np.ndarray | None, str]]:
    """Each topic's fields, its time vector and the time's name."""
    found = _whos(path)
    numeric = [n for n, _, c in found if c not in ("struct", "cell", "char", "object")]
    if not numeric:
        held = ", ".join(f"{echo(n, 40)} ({c})" for n, _, c in found[:10]) or "nothing"
        raise NoisevarError(
            f"{echo(path.name)} has no numeric variable (it holds {held}): save a struct's "
            "fields as variables, save(f, '-struct', 's'), or export them as CSV"
        )
    data = {k: v for k, v in _load(path, numeric).items() if not k.startswith("__")}
    clocks = {k: np.asarray(v, float) for k, v in data.items()
              if is_time_column(k) and np.ndim(v) == 1 and _samples(v) is not None}  # fmt: skip
    out = {}
    for name, value in data.items():
        a = None if name in clocks else _samples(value)
        if a is None:
            continue
        cols = {name: a[:, 0]} if a.shape[1] == 1 else {str(i): a[:, i] for i in range(a.shape[1])}
        clock = next((k for k, c in clocks.items() if c.size == a.shape[0]), None)
        t = clocks[clock] if clock else None
        out[name] = ({f: v.astype(float) for f, v in cols.items()}, t, clock or "")
    return out


def _seconds(t: np.ndarray | None, name: str) -> np.ndarray | None:
    if t is None or not t.size:
        return None
    return (t - t[0]) * time_scale(name, float(t[0]))


def topics(path: Path) -> list[TopicInfo]:
    """Every numeric variable or struct of vectors: its samples, rate and fields."""
    out = []
    for name, (fields, t, clock) in sorted(_topics(path).items()):
        n = next(iter(fields.values())).size if fields else 0
        s = _seconds(t, clock)
        rate = (n - 1) / float(s[-1]) if s is not None and n > 1 and s[-1] > 0 else None
        out.append(TopicInfo(name, "MATLAB variable", n, rate, tuple(fields)))
    return out


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """The variable's fields, in one chunk (a .mat file is read whole)."""
    found = _topics(path)
    if topic not in found:
        raise NoisevarError(f"no variable {echo(topic)!r} with numbers in {echo(path.name)}")
    cols, t, clock = found[topic]
    names = tuple(fields) if fields is not None else tuple(cols)
    bad = [f for f in names if f not in cols]
    if bad:
        raise NoisevarError(
            f"variable {echo(topic)!r} has no field {echo(bad[0])!r}; fields: "
            + ", ".join(echo(f, 40) for f in list(cols)[:40])
        )
    yield Chunk(_seconds(t, clock), {f: cols[f] for f in names})


READER = LogReader(
    name="matlab",
    title="MATLAB file",
    suffixes=(".mat",),
    magic=(b"MATLAB 5.0 MAT-file",),
    topics=topics,
    read=read,
    time_note="times from the file's time vector of the same length, seconds from the first",
    repair="save it again from MATLAB with save(..., '-v7'), or export the variables as CSV",
)
