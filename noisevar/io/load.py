"""One entry point for files: :func:`load_table`, then :func:`pick_column`."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.nmea import _looks_like_nmea, _read_nmea
from noisevar.io.npy import _read_npy
from noisevar.io.table import _NPY_MAGIC, NMEA_EXTENSIONS, LoadedTable
from noisevar.io.text import _read_text_table


def _check_binary(raw: bytes, name: str) -> str:
    head = raw[:65536]
    if b"\x00" in head:
        raise NoisevarError(
            f"{name} looks like a binary file (it contains NUL bytes): give a CSV/TSV text "
            "table, an NMEA 0183 log, or a .npy array"
        )
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
        ctrl = sum(1 for ch in text[:65536] if ord(ch) < 32 and ch not in "\r\n\t")
        if ctrl > 0.01 * min(len(text), 65536):
            raise NoisevarError(
                f"{name} looks like a binary file (not UTF-8 text): give a CSV/TSV text table, "
                "an NMEA 0183 log, or a .npy array"
            ) from None
    return text


def _read_source(source: str | os.PathLike | bytes, name: str | None) -> tuple[bytes, str]:
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source), name or "upload"
    path = Path(source)
    if not path.is_file():
        raise NoisevarError(f"no such file: {path}")
    try:
        return path.read_bytes(), name or path.name
    except OSError as exc:
        raise NoisevarError(f"cannot read {path}: {exc.strerror or exc}") from None


def load_table(
    source: str | os.PathLike | bytes,
    name: str | None = None,
    *,
    max_bytes: int | None = None,
) -> LoadedTable:
    """Read a CSV/TSV text table, a ``.npy`` array or an NMEA 0183 log.

    Parameters
    ----------
    source : str, path or bytes
        A file path, or the file's bytes (an upload).
    name : str, optional
        File name; its extension picks the format (``.npy``; ``.nmea`` and
        friends; anything else is sniffed: ``.npy`` magic bytes, NMEA
        sentences, else a text table). Default: the path's name.
    max_bytes : int, optional
        Refuse larger files with a clear message.

    Returns
    -------
    LoadedTable

    Raises
    ------
    NoisevarError
        Missing, empty, binary or malformed files (with the line and column),
        NMEA checksum errors, pickled ``.npy`` arrays, files over ``max_bytes``.

    Examples
    --------
    >>> tab = load_table(b"t,x\\n0,1.0\\n0.5,1.2\\n1.0,0.9\\n", "demo.csv")
    >>> tab.data_columns, tab.sample_period
    (['x'], 0.5)
    """
    raw, name = _read_source(source, name)
    if max_bytes is not None and len(raw) > max_bytes:
        raise NoisevarError(
            f"{name} is {len(raw) / 1e6:.1f} MB, over the {max_bytes / 1e6:.0f} MB limit: "
            "give a shorter record or raise the limit"
        )
    if len(raw) == 0 or not raw.strip():
        raise NoisevarError(f"{name} is empty")
    lower = name.lower()
    if raw.startswith(_NPY_MAGIC) or lower.endswith(".npy"):
        if not raw.startswith(_NPY_MAGIC):
            raise NoisevarError(f"{name} is not a valid .npy file (no NumPy header)")
        return _read_npy(raw, name)
    if lower.endswith(".npz"):
        raise NoisevarError(f"{name}: .npz archives are not supported; save one array as .npy")
    text = _check_binary(raw, name)
    if lower.endswith(NMEA_EXTENSIONS) or _looks_like_nmea(text):
        return _read_nmea(text, name)
    return _read_text_table(text, name)


def pick_column(
    table: LoadedTable, column: str | int | None = None, *, drop_nonfinite: bool = False
) -> NDArray:
    """One column of a table as a signal for :func:`noisevar.estimate`.

    Parameters
    ----------
    table : LoadedTable
        A loaded file.
    column : str or int, optional
        Column name, or index among :attr:`LoadedTable.data_columns`
        (default: the first data column).
    drop_nonfinite : bool
        Drop empty/NaN cells instead of refusing them.

    Returns
    -------
    ndarray of float, shape (n,)

    Raises
    ------
    NoisevarError
        Unknown column, or a column with empty/NaN cells (unless dropped).
    """
    data_cols = table.data_columns
    if not data_cols:
        raise NoisevarError(f"{table.name} has no data column (only a time column)")
    if column is None:
        cname = data_cols[0]
    elif isinstance(column, (int, np.integer)) and not isinstance(column, bool):
        if not 0 <= int(column) < len(data_cols):
            raise NoisevarError(
                f"column index {column} is out of range: {table.name} has {len(data_cols)} "
                f"data columns ({', '.join(data_cols)})"
            )
        cname = data_cols[int(column)]
    else:
        cname = str(column)
        if cname not in table.columns:
            if cname.isdigit() and int(cname) < len(data_cols):
                cname = data_cols[int(cname)]
            else:
                raise NoisevarError(
                    f"no column {column!r} in {table.name}; columns: {', '.join(table.columns)}"
                )
    z = np.asarray(table.columns[cname], dtype=float)
    bad = ~np.isfinite(z)
    if bad.any():
        if not drop_nonfinite:
            first = int(np.argmax(bad))
            raise NoisevarError(
                f"column {cname!r} of {table.name} has {int(bad.sum())} empty or NaN values "
                f"(the first at data row {first + 1}): clean the file, or drop them "
                "(CLI: --drop-nonfinite)"
            )
        z = z[~bad]
    return z
