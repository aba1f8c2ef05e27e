"""Records larger than memory: files read in chunks, estimated by a method's chunked engine.

:func:`estimate_file` streams a ``.npy`` file, a raw binary file (``dtype=``) or a CSV
column (spooled to a binary file first, through :mod:`noisevar.io`'s readers) through
:func:`~noisevar.estimators.estimate_chunked`, which gives the numbers of the one-pass
estimate with memory bounded whatever the record's length (docs/algorithms.md §F5.7).
This package holds the file sources only; the engine is the method's (``spec.chunked``).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from noisevar.errors import NoisevarError
from noisevar.estimators import DEFAULT_METHOD, estimate_chunked
from noisevar.estimators.results import VarianceEstimate
from noisevar.stream.sources import FileSource, npy_source, raw_source, regular_file, spool_csv

if TYPE_CHECKING:
    from noisevar.io.table import LoadedTable

__all__ = [
    "STREAM_BYTES",
    "FileSource",
    "estimate_chunked",
    "estimate_file",
    "same_column",
    "source_of",
    "streamed_column",
]

#: Files larger than this (bytes) are streamed by ``noisevar estimate`` without a flag,
#: when :func:`same_column` says the streamed path reads what the in-memory path reads
#: (and the method has a chunked path): memory stays bounded, the numbers are the same.
STREAM_BYTES = 32 << 20
#: Bytes of a file read to tell its columns (and whether it has a time column).
_HEAD_BYTES = 1 << 16


def source_of(
    path: str | os.PathLike, column: str | int | None = None, dtype: str | None = None
) -> FileSource:
    """The samples of ``path`` as a :class:`FileSource` (``.npy``, or raw with ``dtype``)."""
    if dtype is not None:
        return raw_source(path, dtype, 1, 0) if column is None else _raw_column(path, dtype, column)
    if str(path).lower().endswith(".npy"):
        return npy_source(path, None if column is None else int(column))
    raise NoisevarError(
        f"cannot stream {Path(path).name!r}: give a .npy file, a raw binary file with a dtype, "
        "or a CSV file"
    )


def same_column(path: str | os.PathLike, column: str | int | None) -> tuple[bool, str | int | None]:
    """The ``column`` of :func:`estimate_file` that streams what the in-memory loader picks.

    Parameters
    ----------
    path : path-like
        A ``.npy`` or text (CSV/TSV) file.
    column : str, int or None
        The column as the in-memory path takes it.

    Returns
    -------
    bool, str or int or None
        Whether the file streams the same samples (False for a text table with a time
        column: the in-memory path splits its record at gaps; for a structured or non-numeric
        ``.npy`` array; for other formats), and the column to give :func:`estimate_file`.

    Raises
    ------
    NoisevarError
        No such column (the in-memory path's message).
    """
    low = str(path).lower()
    if not low.endswith((".npy", ".csv", ".tsv", ".txt")):
        return False, None
    table = _head_table(path)
    if table is None or (not low.endswith(".npy") and table.time() is not None):
        return False, None
    return True, streamed_column(path, column)[0]


def streamed_column(
    path: str | os.PathLike, column: str | int | None, dtype: str | None = None
) -> tuple[str | int | None, str | int | None, str | None]:
    """The column the streamed reader takes for what the in-memory loader picks.

    Parameters
    ----------
    path : path-like
        The file :func:`estimate_file` reads.
    column : str, int or None
        The column as the in-memory path takes it (:func:`noisevar.io.pick_column`): a
        name, an index among the *data* columns (a time column is not counted), or None
        for the first signal. A raw binary file (``dtype``) takes ``'K/COLUMNS'``.
    dtype : str, optional
        The raw file's sample type.

    Returns
    -------
    tuple
        The column to give the file's streamed reader (a name for text, an index for
        ``.npy``, as given for raw files), its name to show, and the unit the file declares
        for it (None if none).

    Raises
    ------
    NoisevarError
        No such column (the in-memory path's message).

    Notes
    -----
    The file's head is read as a table (:data:`_HEAD_BYTES`), so ``--column 1`` names the
    same channel, with the same unit, streamed or not.
    """
    from noisevar.io.load import column_name

    table = None if dtype is not None else _head_table(path)
    if table is None:
        return column, column, None
    name = column_name(table, column)
    index = table.data_columns.index(name)
    reader = (index if _npy_columns(path) else None) if str(path).lower().endswith(".npy") else name
    return reader, name, table.units.get(name)


def _head_table(path: str | os.PathLike) -> LoadedTable | None:
    """The file's head as the in-memory loader reads it (a ``.npy``: a two-row array of
    its shape, so the same column names); None for a file that does not stream so."""
    import io

    import numpy as np

    from noisevar.io import load_table

    name = Path(path).name
    low = name.lower()
    if low.endswith(".npy"):
        try:
            npy_source(path, 0)
            cols = _npy_columns(path)
        except NoisevarError:
            return None  # structured, non-numeric, 3-D...: read in memory
        head = io.BytesIO()
        np.save(head, np.zeros((2, cols) if cols else 2))
        return load_table(head.getvalue(), name)
    if not low.endswith((".csv", ".tsv", ".txt")):
        return None
    with open(path, "rb") as fh:
        raw = fh.read(_HEAD_BYTES)
    raw = raw[: raw.rfind(b"\n") + 1] or raw
    return load_table(raw, name)


def _npy_columns(path: str | os.PathLike) -> int:
    """Columns of a 2-D ``.npy`` array (0 for 1-D), from its header (read by ``npy_source``)."""
    import numpy as np

    with open(path, "rb") as f:
        version = np.lib.format.read_magic(f)
        read = {(1, 0): np.lib.format.read_array_header_1_0}.get(
            version, np.lib.format.read_array_header_2_0
        )
        shape = read(f)[0]
    return int(shape[1]) if len(shape) == 2 else 0


def _raw_column(path: str | os.PathLike, dtype: str, column: str | int) -> FileSource:
    cols, _, col = str(column).partition("/")
    if not (cols.isdigit() and col.isdigit()):
        raise NoisevarError("for raw binary give column as 'K/COLUMNS', e.g. '2/6'")
    return raw_source(path, dtype, int(col), int(cols))


def estimate_file(
    path: str | os.PathLike,
    *,
    column: str | int | None = None,
    dtype: str | None = None,
    method: str = DEFAULT_METHOD,
    chunk: int | None = None,
    workers: int = 2,
    **params: object,
) -> VarianceEstimate:
    """The estimate of one column of a file, read in chunks.

    Parameters
    ----------
    path : path-like
        ``.npy`` (1-D, or 2-D with ``column``), a headerless binary file of ``dtype``
        samples (``column='K/COLUMNS'`` for interleaved channels), or a CSV file.
    column : str or int, optional
        As the in-memory loader takes it (:func:`streamed_column`): a name, an index among
        the data columns, or None for the first signal; ``'K/COLUMNS'`` for a raw file.
    dtype : str, optional
        The raw file's sample type (``"float64"``, ``"<f4"``, ``"int16"``, ...).
    method : str
        A method with a chunked engine (default: the default method).
    chunk, workers : see :func:`~noisevar.estimators.estimate_chunked`.
    **params
        The method's parameters.

    Returns
    -------
    VarianceEstimate

    Raises
    ------
    NoisevarError
        Not a regular file (a FIFO, a device, a folder), an unreadable or malformed file,
        non-finite samples, integers beyond 2**53, or a method without a chunked path.
    """
    regular_file(path)
    column = streamed_column(path, column, dtype)[0]  # as the in-memory path counts them
    spool = None
    if dtype is None and str(path).lower().endswith((".csv", ".txt", ".tsv")):
        src, _ = spool_csv(path, column)
        spool = src.path
    else:
        src = source_of(path, column, dtype)
    try:
        return estimate_chunked(
            src.read, src.n, method=method, probe=src.__getitem__, chunk=chunk,
            workers=workers, **params,
        )  # fmt: skip
    finally:
        if spool is not None:
            os.unlink(spool)
