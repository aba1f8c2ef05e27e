"""The batch table on disk: Parquet or CSV, and the journal that makes a killed batch resumable.

Rows are appended to a journal (``<out>.journal.jsonl``, one JSON row a line, flushed as
each task returns) while the batch runs; at the end the output is written once, atomically
(a temporary file renamed over it), from the rows it had, the journal's and the new ones.
A batch killed at any point leaves the journal; the next run reads it with the output, so
nothing already done is done again.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from noisevar.errors import NoisevarError
from noisevar.estimators.results import row_dtypes
from noisevar.estimators.results import rows_frame as estimate_rows_frame

if TYPE_CHECKING:
    import pandas as pd

#: Output formats by file extension.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}
#: What a batch row is of, before the estimate's columns.
KEY_COLUMNS: tuple[str, ...] = ("file", "channel")
#: How a batch row was made, after the estimate's columns: the time it took, the file's
#: content hash, the error (when there is no estimate), the request it answers and the
#: file's sample rate (Hz, from its time column; empty without one).
RUN_COLUMNS: tuple[str, ...] = ("elapsed_s", "hash", "error", "request", "sample_rate_hz")
#: Columns of tables written before the one row schema, and their names now.
LEGACY_COLUMNS = {"ci95_lo": "ci95_low", "ci95_hi": "ci95_high", "n": "n_total"}


def out_format(out: str | os.PathLike) -> str:
    """``"parquet"`` or ``"csv"`` from the output's extension (anything else is refused)."""
    suffix = Path(out).suffix.lower()
    if suffix not in FORMATS:
        raise NoisevarError(
            f"cannot write {Path(out).name}: give an output ending in .parquet or .csv"
        )
    return FORMATS[suffix]


def journal_path(out: str | os.PathLike) -> Path:
    """The journal beside the output."""
    p = Path(out)
    return p.with_name(p.name + ".journal.jsonl")


def rows_frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    """Batch rows as the batch table: :data:`KEY_COLUMNS`, the estimate's, :data:`RUN_COLUMNS`.

    The estimate's columns are the one row schema
    (:data:`noisevar.estimators.results.ROW_COLUMNS`, ``flag_*`` included).
    """
    return estimate_rows_frame(rows, lead=KEY_COLUMNS, tail=RUN_COLUMNS)


def _renamed(row: dict[str, Any]) -> dict[str, Any]:
    """A row of an older table with today's column names (:data:`LEGACY_COLUMNS`)."""
    return {LEGACY_COLUMNS.get(k, k): v for k, v in row.items()}


def read_table(path: str | os.PathLike | bytes, name: str | None = None) -> pd.DataFrame:
    """A batch table written by :func:`write_table` (Parquet or CSV), from a path or bytes.

    Parameters
    ----------
    path : str, path or bytes
        The file, or its bytes (an upload; then ``name`` gives the format).
    name : str, optional
        File name (default: the path's).

    Raises
    ------
    NoisevarError
        Not a batch table (no ``file`` column), unreadable, or a column of the estimate's
        schema holding a value of the wrong type (text for a number, ...).
    """
    import io

    import pandas as pd

    raw = isinstance(path, bytes | bytearray)
    label = name or ("upload" if raw else Path(path).name)
    source = io.BytesIO(path) if raw else Path(path)
    try:
        if out_format(label) == "parquet":
            frame = pd.read_parquet(source)
        else:
            frame = pd.read_csv(source, dtype={"hash": str, "channel": str, "file": str})
        if "file" not in frame.columns:
            raise NoisevarError(f"{label} is not a batch table (it has no 'file' column)")
        frame = frame.rename(columns=LEGACY_COLUMNS)
        return frame.astype(row_dtypes(frame.columns))  # a cell of the wrong type: refused
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - any reader failure is one clear sentence
        raise NoisevarError(f"cannot read the batch table {label}: {exc}") from None


def read_journal(path: Path) -> list[dict[str, Any]]:
    """Rows of a journal; a last line cut short by a kill is ignored."""
    rows: list[dict[str, Any]] = []
    if not path.is_file():
        return rows
    with path.open(encoding="utf-8") as fh:
        for line in fh:
            try:
                rows.append(_renamed(json.loads(line)))
            except json.JSONDecodeError:
                break
    return rows


def open_journal(path: Path, fresh: bool) -> IO[str]:
    """The journal, opened to append (emptied first when ``fresh``)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return path.open("w" if fresh else "a", encoding="utf-8")


def append_rows(fh: IO[str], rows: list[dict[str, Any]]) -> None:
    """Append rows to the journal and flush them to disk."""
    for r in rows:
        fh.write(json.dumps(r, allow_nan=False) + "\n")
    fh.flush()
    os.fsync(fh.fileno())


def write_table(frame: pd.DataFrame, out: str | os.PathLike) -> None:
    """Write the batch table atomically (a temporary file, then a rename)."""
    p = Path(out)
    fmt = out_format(p)
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.with_name(f".{p.name}.tmp-{os.getpid()}")
    if fmt == "parquet":
        frame.to_parquet(tmp, engine="pyarrow", index=False)
    else:
        frame.to_csv(tmp, index=False)
    os.replace(tmp, p)
