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

from noisevar.batch._task import ROW_COLUMNS
from noisevar.errors import NoisevarError

if TYPE_CHECKING:
    import pandas as pd

#: Output formats by file extension.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}


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
    """Rows as a DataFrame with the batch columns in their order (``flag_*`` after the rest)."""
    import pandas as pd

    frame = pd.DataFrame(rows)
    flags = sorted(c for c in frame.columns if c.startswith("flag_"))
    extra = [c for c in frame.columns if c not in ROW_COLUMNS and c not in flags]
    order = [*ROW_COLUMNS[:11], *flags, *ROW_COLUMNS[11:], *extra]
    frame = frame.reindex(columns=order)
    # nullable dtypes: an error row has no count or flag, and reads back the same from Parquet
    return frame.astype({"n": "Int64", "n_used": "Int64", **dict.fromkeys(flags, "boolean")})


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
        Not a batch table (no ``file`` column) or unreadable.
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
    except NoisevarError:
        raise
    except Exception as exc:  # noqa: BLE001 - any reader failure is one clear sentence
        raise NoisevarError(f"cannot read the batch table {label}: {exc}") from None
    if "file" not in frame.columns:
        raise NoisevarError(f"{label} is not a batch table (it has no 'file' column)")
    return frame.astype({c: "Int64" for c in ("n", "n_used") if c in frame.columns})


def read_journal(path: Path) -> list[dict[str, Any]]:
    """Rows of a journal; a last line cut short by a kill is ignored."""
    rows: list[dict[str, Any]] = []
    if not path.is_file():
        return rows
    with path.open(encoding="utf-8") as fh:
        for line in fh:
            try:
                rows.append(json.loads(line))
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
