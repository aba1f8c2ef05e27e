"""The batch table on disk: Parquet or CSV, its journal, and the lock that makes it exactly-once.

Rows are journalled (``<out>.journal.jsonl``) as each task returns: one line per file, all
of that file's rows (a line cut short by a kill is ignored, so a file is journalled whole or
not at all). At the end the output is written once, atomically (a temporary file renamed
over it), and the journal is removed. The commit sequence is :data:`COMMIT_STEPS`.

The journal is keyed: a rerun reads the output and the journal into one table keyed by
file, a file's journalled rows replacing the output's (:func:`rows_by_file`). Whatever step
a batch was killed at, no row is lost or doubled: before the rename the output lacks the
journal's files, after it the output holds the same rows as the journal. One batch at a
time writes an output (:func:`output_lock`).
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from noisevar.errors import NoisevarError
from noisevar.estimators.results import row_dtypes
from noisevar.estimators.results import rows_frame as estimate_rows_frame

if TYPE_CHECKING:
    import pandas as pd

#: Output formats by file extension.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}
#: What a batch row is of, before the estimate's columns: the file, the channel and the
#: unit the file declares for it (empty when it declares none).
KEY_COLUMNS: tuple[str, ...] = ("file", "channel", "unit")
#: How a batch row was made, after the estimate's columns: the time it took, the file's
#: content hash, the error (when there is no estimate), the request it answers and the
#: file's sample rate (Hz, from its time column; empty without one).
RUN_COLUMNS: tuple[str, ...] = ("elapsed_s", "hash", "error", "request", "sample_rate_hz")
#: Columns of tables written before the one row schema, and their names now.
LEGACY_COLUMNS = {"ci95_lo": "ci95_low", "ci95_hi": "ci95_high", "n": "n_total"}
#: The commit sequence, each step named as :func:`commit_point` is told of it: a file's rows
#: journalled (once per file), the temporary table written, renamed over the output, the
#: journal removed.
COMMIT_STEPS: tuple[str, ...] = ("journalled", "written", "renamed", "unjournalled")


def commit_point(step: str) -> None:
    """Called after each step of :data:`COMMIT_STEPS`: nothing (where tests inject a kill)."""


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


def journal_groups(path: Path) -> list[list[dict[str, Any]]]:
    """Each line of a journal: one file's rows, in order; a line cut short by a kill is skipped.

    A line is ``{"file": ..., "rows": [...]}``; a journal written before it was keyed by
    file holds one row a line, grouped here by consecutive file.
    """
    groups: list[list[dict[str, Any]]] = []
    if not path.is_file():
        return groups
    last = None
    with path.open(encoding="utf-8", errors="replace") as fh:
        for line in fh:
            try:
                item = json.loads(line)
            except json.JSONDecodeError:
                continue  # cut short by a kill; a later run's lines follow it
            if not isinstance(item, dict):
                continue
            if isinstance(item.get("rows"), list):
                rows = [_renamed(r) for r in item["rows"] if isinstance(r, dict) and "file" in r]
                groups.append(rows)
                last = None
            elif "file" in item:  # a legacy row
                if last == item["file"] and groups:
                    groups[-1].append(_renamed(item))
                else:
                    groups.append([_renamed(item)])
                last = item["file"]
    return [g for g in groups if g]


def read_journal(path: Path) -> list[dict[str, Any]]:
    """Rows of a journal, in order (:func:`journal_groups`, flattened)."""
    return [r for g in journal_groups(path) for r in g]


def _channel_key(channel: Any) -> Any:
    """A row's channel as a key (a missing channel, NaN in a table read back, is None)."""
    return None if channel is None or channel != channel else str(channel)


def rows_by_file(
    table: list[dict[str, Any]], journal: list[list[dict[str, Any]]], files: list[str]
) -> dict[str, list[dict[str, Any]]]:
    """The rows done, keyed by file: the output's, each file's journalled rows replacing them.

    Parameters
    ----------
    table : list of dict
        Rows of the output (each file's rows together).
    journal : list of list of dict
        :func:`journal_groups`: one file's rows each, in the order journalled.
    files : list of str
        The files of this run: rows of other files are dropped.

    Returns
    -------
    dict
        File -> its rows (one per channel, or one error row), for the files given only.
    """
    given = set(files)
    by_channel: dict[str, dict[Any, dict[str, Any]]] = {}
    for r in table:  # a table doubled by an older version: each (file, channel) once
        if str(r["file"]) in given:
            by_channel.setdefault(str(r["file"]), {})[_channel_key(r.get("channel"))] = r
    keyed = {f: list(rows.values()) for f, rows in by_channel.items()}
    for group in journal:  # a later line of a file replaces what came before it
        f = str(group[0]["file"])
        if f in given:
            keyed[f] = group
    return keyed


def open_journal(path: Path, fresh: bool) -> IO[str]:
    """The journal, opened to append (emptied first when ``fresh``).

    A last line cut short by a kill is ended first, so that the lines appended after it
    stay whole.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    if not fresh and path.is_file() and path.stat().st_size:
        with path.open("rb") as fh:
            fh.seek(-1, os.SEEK_END)
            cut = fh.read(1) != b"\n"
        if cut:
            with path.open("a", encoding="utf-8") as fh:
                fh.write("\n")
    return path.open("w" if fresh else "a", encoding="utf-8")


def append_rows(fh: IO[str], rows: list[dict[str, Any]]) -> None:
    """Journal rows, one line per file (all its rows), and flush them to disk.

    Each line is handed to the system as it is written (a killed process loses none of
    them); the disk is synced once per call (a task's files), not once per file.
    """
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(str(r["file"]), []).append(r)
    for f, group in groups.items():
        fh.write(json.dumps({"file": f, "rows": group}, allow_nan=False) + "\n")
        fh.flush()
        commit_point("journalled")
    os.fsync(fh.fileno())


@contextlib.contextmanager
def output_lock(out: Path) -> Iterator[None]:
    """Hold ``<out>.lock`` while a batch writes ``out``; a second batch is refused at once.

    The lock is an advisory ``flock`` (released by the system when its process dies, even
    by SIGKILL); where ``fcntl`` does not exist (Windows) no lock is taken.

    Raises
    ------
    NoisevarError
        Another batch is writing ``out``.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    lock = out.with_name(out.name + ".lock")
    lock.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise NoisevarError(
                f"another batch is writing {out.name} (its lock {lock.name} is held): wait for "
                "it to finish, or give another --out"
            ) from None
        _remove_stale_temporaries(out)
        yield
    finally:
        os.close(fd)  # releases the lock; the lock file stays (removing it would race)


def _remove_stale_temporaries(out: Path) -> None:
    """Temporary tables of killed batches (the lock is held: none is being written)."""
    for tmp in out.parent.glob(f".{out.name}.tmp-*"):
        with contextlib.suppress(OSError):
            tmp.unlink()


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
    with open(tmp, "rb+") as fh:  # on disk before the rename makes it the output
        os.fsync(fh.fileno())
    commit_point("written")
    os.replace(tmp, p)
    commit_point("renamed")


def commit(frame: pd.DataFrame, out: Path, journal: IO[str]) -> None:
    """The end of a batch: the table written over ``out``, then the journal removed."""
    journal.close()
    write_table(frame, out)
    journal_path(out).unlink(missing_ok=True)
    commit_point("unjournalled")
