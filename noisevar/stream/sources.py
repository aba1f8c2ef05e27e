"""Records read in pieces from disk: ``.npy`` and raw binary by offset, CSV spooled to binary.

Nothing is memory-mapped (a mapping would keep every page it touched in the process's
resident memory): each read copies the samples asked for, so that memory stays bounded
whatever the file's size.
"""

from __future__ import annotations

import os
import stat
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from noisevar._arrays import EXACT_INT
from noisevar.errors import NoisevarError
from noisevar.io.table import echo


def regular_file(path: str | os.PathLike) -> Path:
    """``path`` if it is a regular file (a FIFO or a device would be read forever), else
    a :class:`NoisevarError`."""
    p = Path(path)
    try:
        mode = os.stat(p).st_mode
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(str(path))}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(mode):
        raise NoisevarError(
            f"{echo(str(path))} is not a regular file (a pipe, a device or a folder): "
            "save the record to a file first"
        )
    return p


@dataclass(frozen=True)
class FileSource:
    """One column of a binary file: ``n`` samples of ``dtype``, ``stride`` bytes apart.

    Attributes
    ----------
    path : Path
    offset : int
        Byte offset of the column's first sample.
    n : int
        Samples.
    dtype : numpy.dtype
    stride : int
        Bytes from one sample to the next (the row size for a column of a C-order table).
    name : str
        For messages.
    """

    path: Path
    offset: int
    n: int
    dtype: np.dtype
    stride: int
    name: str

    def read(self, a: int, b: int) -> NDArray:
        """Samples ``a .. b`` as float64 (a copy), checked finite."""
        a, b = max(0, a), min(self.n, b)
        item = self.dtype.itemsize
        width = self.stride // item if self.stride % item == 0 else 0
        with open(self.path, "rb") as f:
            f.seek(self.offset + a * self.stride)
            if self.stride == item:
                raw = np.fromfile(f, dtype=self.dtype, count=b - a)
            elif width:
                rows = np.fromfile(f, dtype=self.dtype, count=(b - a - 1) * width + 1)
                raw = rows[::width]
            else:  # pragma: no cover - rows of mixed fields are read by np.dtype strides
                raise NoisevarError(f"{echo(self.name)}: unsupported row layout")
        if raw.size != b - a:
            raise NoisevarError(f"{echo(self.name)} is shorter than its header says: re-save it")
        _exact(raw, self.name, a)
        out = raw.astype(float, copy=False)
        if out.size and not (np.isfinite(out.min()) and np.isfinite(out.max())):  # NaN, Inf
            bad = ~np.isfinite(out)
            raise NoisevarError(
                f"{echo(self.name)} has a non-finite value (NaN or Inf) at sample "
                f"{a + int(np.argmax(bad))}: the streamed path needs finite samples; clean them, "
                "or load a smaller file in memory with --drop-nonfinite"
            )
        return out

    def __getitem__(self, s: slice) -> NDArray:
        """A strided slice (the quantisation probe), read sample by sample."""
        out = []
        with open(self.path, "rb") as f:
            for i in range(*s.indices(self.n)):
                f.seek(self.offset + i * self.stride)
                out.append(np.fromfile(f, dtype=self.dtype, count=1))
        raw = np.concatenate(out) if out else np.zeros(0)
        _exact(raw, self.name, 0)
        return raw.astype(float)


def _exact(raw: NDArray, name: str, start: int) -> None:
    """Refuse integers that float64 cannot hold exactly (beyond 2**53), as in memory."""
    if raw.dtype.kind not in "iu" or raw.dtype.itemsize < 8 or not raw.size:
        return
    big = (raw > EXACT_INT) | (raw < -EXACT_INT) if raw.dtype.kind == "i" else raw > EXACT_INT
    if big.any():
        k = int(np.argmax(big))
        raise NoisevarError(
            f"{echo(name)} holds integers beyond 2**53 (sample {start + k}: {int(raw[k])}): "
            "float64 cannot hold them exactly; subtract an offset or rescale them first"
        )


def _numeric(dtype: np.dtype, name: str) -> np.dtype:
    if dtype.kind not in "iuf" or dtype.hasobject:
        raise NoisevarError(
            f"{echo(name)} holds {dtype} values: the streamed path reads integers or floats"
        )
    return dtype


def npy_source(path: str | os.PathLike, column: int | None = None) -> FileSource:
    """A ``.npy`` file's samples (1-D, or one column of a 2-D array), header read without pickle."""
    p = Path(path)
    name = str(path)
    try:
        with open(p, "rb") as f:
            version = np.lib.format.read_magic(f)
            header = {(1, 0): np.lib.format.read_array_header_1_0}.get(
                version, np.lib.format.read_array_header_2_0
            )
            shape, fortran, dtype = header(f)
            offset = f.tell()
    except (OSError, ValueError) as exc:
        raise NoisevarError(
            f"{echo(name)} is not a readable .npy file ({echo(exc, 200)})"
        ) from None
    dtype = _numeric(np.dtype(dtype), name)
    if dtype.names:
        raise NoisevarError(f"{echo(name)}: a structured array cannot be streamed: save columns")
    if len(shape) == 1:
        return FileSource(p, offset, int(shape[0]), dtype, dtype.itemsize, name)
    if len(shape) != 2:
        raise NoisevarError(f"{echo(name)} has shape {shape}: stream a 1-D or 2-D array")
    n, cols = int(shape[0]), int(shape[1])
    col = 0 if column is None and cols == 1 else column
    if col is None or not 0 <= col < cols:
        raise NoisevarError(
            f"{echo(name)} has {cols} columns: pick one with --column 0..{cols - 1}"
        )
    if fortran:
        return FileSource(p, offset + col * n * dtype.itemsize, n, dtype, dtype.itemsize, name)
    return FileSource(p, offset + col * dtype.itemsize, n, dtype, cols * dtype.itemsize, name)


def raw_source(
    path: str | os.PathLike, dtype: str, columns: int = 1, column: int = 0
) -> FileSource:
    """A headerless binary file of ``dtype`` samples, ``columns`` per row (C order)."""
    p = Path(path)
    try:
        dt = _numeric(np.dtype(dtype), str(path))
    except TypeError:
        raise NoisevarError(
            f"unknown dtype {echo(dtype)!r}: give e.g. float64, <f4, int16"
        ) from None
    row = dt.itemsize * columns
    size = p.stat().st_size
    if size % row:
        raise NoisevarError(
            f"{echo(str(path))} is {size} bytes, not a whole number of {columns}-column rows "
            f"of {dt}: check --dtype"
        )
    if not 0 <= column < columns:
        raise NoisevarError(f"column {column} is not one of the file's {columns} columns")
    return FileSource(p, column * dt.itemsize, size // row, dt, row, str(path))


def spool_csv(
    path: str | os.PathLike, column: str | int | None, directory: str | None = None
) -> tuple[FileSource, str]:
    """One column of a text table copied in chunks to a float64 file; the source and its name.

    The table is read as :func:`noisevar.io.load_table` reads it (delimiter, decimal mark,
    header); the caller removes the spool file (``source.path``) when done.
    """
    from noisevar.io.load import read_text_chunks  # here: it brings pandas

    name = str(path)
    names, frames = read_text_chunks(path, name)
    picked = _pick(names, column, name)
    fd, spool = tempfile.mkstemp(suffix=".f64", dir=directory)
    try:
        with os.fdopen(fd, "wb") as out:
            row = 0
            for frame in frames:
                col = frame.iloc[:, names.index(picked)].to_numpy()
                _exact(col, name, row)  # an integer column beyond 2**53: refused, as in memory
                col.astype(float).tofile(out)
                row += col.size
    except BaseException:
        os.unlink(spool)
        raise
    n = os.path.getsize(spool) // 8
    return FileSource(Path(spool), 0, n, np.dtype(float), 8, name), picked


def _pick(names: list[str], column: str | int | None, name: str) -> str:
    if column is None:
        if len(names) != 1:
            raise NoisevarError(f"{echo(name)} has {len(names)} columns: pick one with --column")
        return names[0]
    if str(column) in names:
        return str(column)
    if str(column).isdigit() and int(column) < len(names):
        return names[int(column)]
    raise NoisevarError(f"{echo(name)} has no column {echo(str(column))!r}")
