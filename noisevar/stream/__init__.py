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

from noisevar.errors import NoisevarError
from noisevar.estimators import DEFAULT_METHOD, estimate_chunked
from noisevar.estimators.results import VarianceEstimate
from noisevar.stream.sources import FileSource, npy_source, raw_source, spool_csv

__all__ = ["FileSource", "estimate_chunked", "estimate_file", "source_of"]


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
    """
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
