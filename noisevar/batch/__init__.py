"""Batch noise characterisation: many files x many channels, locally or on a Dask cluster.

:func:`batch` estimates every channel of every file and returns (and writes) one row per
file x channel. Files are grouped into tasks; a task runs in this process
(``jobs=1``), in local worker processes (``jobs=N``), or on a ``dask.distributed``
cluster (``client=``). Results stream back as tasks complete and are journalled at
once, so a killed batch resumes where it stopped. :mod:`noisevar.batch.fleet` turns the
table into fleet statistics (which sensors are unusually noisy).
"""

from __future__ import annotations

import contextlib
import glob
import json
import math
import os
import sys
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

from noisevar.batch._lifeline import announce, follow_batch
from noisevar.batch._output import (
    KEY_COLUMNS,
    RUN_COLUMNS,
    append_rows,
    commit,
    journal_groups,
    journal_path,
    open_journal,
    out_format,
    output_lock,
    read_table,
    rows_by_file,
    rows_frame,
)
from noisevar.batch._task import file_rows, run_task
from noisevar.batch.channels import parse_columns
from noisevar.errors import NoisevarError
from noisevar.estimators import DEFAULT_METHOD
from noisevar.io.series_option import checked_series, how_read
from noisevar.io.time_option import TIME_UNIT

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "KEY_COLUMNS",
    "RUN_COLUMNS",
    "batch",
    "check_jobs",
    "expand_paths",
    "machine_jobs",
    "file_rows",
    "read_table",
    "rows_frame",
    "task_size",
]

#: File extensions a directory given to :func:`batch` is searched for.
DATA_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".tab", ".npy", ".nmea", ".nma", ".gps")
#: Files per task at most (a task's results return together), and tasks per worker aimed at.
MAX_TASK_FILES = 64
TASKS_PER_WORKER = 8

Progress = bool | Callable[[int, int], None]


def _data_suffixes() -> tuple[str, ...]:
    from noisevar.io.logs import readers
    from noisevar.io.logs.spec import SHARED_SUFFIXES

    logs = (s for r in readers() if r.in_folders for s in r.suffixes)  # (LogReader.in_folders)
    # ".log" is any program's text log too: taken when named, not in a folder's search
    return tuple(dict.fromkeys(s for s in (*DATA_EXTENSIONS, *logs) if s not in SHARED_SUFFIXES))


def _in_folder(folder: Path, suffixes: tuple[str, ...]) -> list[str]:
    """The data files and ROS 2 bag directories under ``folder``; a bag's own files are
    its directory's (one log, possibly split over several files)."""
    from noisevar.io.logs import is_ros2_dir

    if is_ros2_dir(folder):
        return [str(folder)]
    found = []
    for p in sorted(folder.iterdir()):
        if p.is_dir() and not p.is_symlink():  # a linked folder could loop
            found.extend(_in_folder(p, suffixes))
        elif p.is_file() and p.suffix.lower() in suffixes:
            found.append(str(p))
    return found


def expand_paths(paths: str | os.PathLike | Iterable[str | os.PathLike]) -> list[str]:
    """The files named by paths, directories (searched recursively) and glob patterns.

    Parameters
    ----------
    paths : str, path or iterable of them
        ``'logs/**/*.csv'`` (``**`` spans folders), a file, or a folder (its data files and
        the logs whose reader says ``in_folders``: recordings and workbooks). A ROS 2 bag
        directory (``metadata.yaml`` inside), named or met in a folder, is one log.

    Returns
    -------
    list of str
        Sorted, without duplicates.
    """
    from noisevar.io.logs import is_ros2_dir

    items = [paths] if isinstance(paths, str | os.PathLike) else list(paths)
    suffixes = _data_suffixes()
    found: list[str] = []
    for item in items:
        s = os.fspath(item)
        if glob.has_magic(s):
            hits = glob.glob(s, recursive=True)
            if not hits:
                raise NoisevarError(f"no file matches {s!r}: check the pattern (quote it)")
            found.extend(h for h in hits if os.path.isfile(h) or is_ros2_dir(Path(h)))
        elif os.path.isdir(s):
            found.extend(_in_folder(Path(s), suffixes))
        elif os.path.isfile(s):
            found.append(s)
        else:
            raise NoisevarError(f"no such file or folder: {s}")
    return sorted(set(found))


def task_size(n_files: int, workers: int) -> int:
    """Files per task: about :data:`TASKS_PER_WORKER` tasks per worker, 1 to 64 files each."""
    per = math.ceil(n_files / max(1, workers * TASKS_PER_WORKER))
    return max(1, min(MAX_TASK_FILES, per))


def _previous(out: Path | None, resume: bool, files: list[str]) -> dict[str, list[dict[str, Any]]]:
    """Rows already done, keyed by file (:func:`~noisevar.batch._output.rows_by_file`):
    the output's and its journal's, for the files given (none when not resuming)."""
    if out is None or not resume:
        return {}
    rows = read_table(out).to_dict("records") if out.is_file() else []
    return rows_by_file(rows, journal_groups(journal_path(out)), files)


def request_key(columns: Any, method: str, params: dict[str, Any], topic: str | None = None) -> str:
    """What was asked (channels, method, parameters, a log's topic) as JSON: a row is reused
    only for the same. Without a topic the key is what it was before topics existed."""
    asked = {"columns": columns, "method": method, "params": params}
    if topic is not None:
        asked["topic"] = topic
    return json.dumps(asked, sort_keys=True, default=str)


def _plan(
    files: list[str], old: dict[str, list[dict[str, Any]]], request: str
) -> tuple[list[str], list[dict[str, Any]]]:
    """Files still to do, and the old rows kept.

    A file is skipped when its old rows were made for the same request and hold its
    current content hash; a changed file or a new request redoes it.
    """
    from noisevar.batch.digest import file_digest

    todo, kept = [], []
    for f in files:
        rows = old.get(f, [])
        hashes = {r.get("hash") for r in rows}
        h = hashes.pop() if len(hashes) == 1 else None
        if rows and isinstance(h, str) and h and all(r.get("request") == request for r in rows):
            try:
                if file_digest(f) == h:
                    kept.extend(rows)
                    continue
            except OSError:
                pass
        todo.append(f)
    return todo, kept


def _failed(group: Sequence[str], method: str, exc: BaseException) -> list[dict[str, Any]]:
    msg = f"task failed ({type(exc).__name__}: {exc})"
    return [{"file": p, "channel": None, "method": method, "error": msg} for p in group]


def _stream(
    groups: list[list[str]], args: tuple, jobs: int, client: Any
) -> Iterator[list[dict[str, Any]]]:
    """Each task's rows as it completes: in this process, in local processes, or on Dask."""
    if client is not None:
        from distributed import as_completed

        futures = {client.submit(run_task, g, *args, pure=False): g for g in groups}
        for fut in as_completed(futures):
            try:
                yield fut.result()
            except Exception as exc:  # noqa: BLE001 - a lost task is rows with its error
                yield _failed(futures[fut], args[1], exc)
        return
    if jobs <= 1:
        for g in groups:
            yield run_task(g, *args)
        return
    import multiprocessing
    from concurrent.futures import as_completed

    # a fork server that imported noisevar (and the caller's script) once, its compiled
    # code loaded: workers forked from it start in a fraction of a second
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(["__main__", "noisevar.batch._warm"])
    me = announce()  # the fork server and the workers die with this process (_lifeline)
    with ProcessPoolExecutor(
        max_workers=jobs, mp_context=ctx, initializer=follow_batch, initargs=(me,)
    ) as pool:
        futs = {pool.submit(run_task, g, *args): g for g in groups}
        try:
            for fut in as_completed(futs):
                try:
                    yield fut.result()
                except Exception as exc:  # noqa: BLE001 - a lost task is rows with its error
                    yield _failed(futs[fut], args[1], exc)
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


def _workers(jobs: int, client: Any) -> int:
    if client is None:
        return jobs
    return max(1, sum(client.nthreads().values()))


def _progress(progress: Progress, total: int) -> tuple[Callable[[int], None], Callable[[], None]]:
    """An ``advance(files)`` and a ``close()`` for a tqdm bar, a callback, or nothing."""
    if callable(progress):
        done = [0]

        def advance(k: int) -> None:
            done[0] += k
            progress(done[0], total)

        progress(0, total)
        return advance, lambda: None
    from tqdm.auto import tqdm

    bar = tqdm(total=total, unit="file", disable=not progress, file=sys.stderr)
    return bar.update, bar.close


def machine_jobs() -> int:
    """Worker processes this machine runs at once: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - no affinity (macOS, Windows)
        return max(1, os.cpu_count() or 1)


def check_jobs(jobs: int | None) -> tuple[int, str | None]:
    """``jobs`` bounded by the machine (:func:`machine_jobs`), and a sentence when it was cut.

    Parameters
    ----------
    jobs : int or None
        Worker processes asked for (None: 1).

    Returns
    -------
    int, str or None
        The processes to start, and why fewer than asked (None when as asked).

    Raises
    ------
    NoisevarError
        Not a whole number >= 1.
    """
    if jobs is None:
        return 1, None
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise NoisevarError(f"jobs must be a whole number >= 1, got {jobs!r}")
    bound = machine_jobs()
    if jobs <= bound:
        return jobs, None
    return bound, f"jobs {jobs} is more than the {bound} CPUs this machine gives it: using {bound}"


def batch(
    paths: str | os.PathLike | Iterable[str | os.PathLike],
    columns: str | Sequence[str] | None = "all",
    method: str = DEFAULT_METHOD,
    out: str | os.PathLike | None = None,
    jobs: int | None = None,
    client: Any = None,
    resume: bool = True,
    progress: Progress = True,
    topic: str | None = None,
    time_unit: str | None = None,
    series: str | None = None,
    **params: Any,
) -> pd.DataFrame:
    """Estimate the noise of every channel of every file: one row per file x channel.

    Parameters
    ----------
    paths : str, path or iterable
        Files, folders or glob patterns (:func:`expand_paths`).
    columns : "all", "a,b,c", list of str or None
        Channels of each file (None: the first data column).
    method : str
        Estimator (:func:`noisevar.methods`).
    out : str or path, optional
        ``.parquet`` or ``.csv`` output, written atomically at the end; rows are
        journalled beside it as they arrive.
    jobs : int, optional
        Local worker processes (default 1: this process); at most the machine's CPUs
        (:func:`check_jobs`: more is cut to that, with a warning).
    client : distributed.Client, optional
        Run the tasks on this Dask cluster instead (``jobs`` is then ignored).
    resume : bool
        Skip files already in ``out`` (or its journal) with the same content hash and the
        same request (channels, method, parameters).
    progress : bool or callable
        A tqdm bar on stderr, or ``progress(done, total)`` called as files complete.
    topic : str, optional
        For logs (ROS bag files, ULog, DataFlash, Parquet, HDF5): the topic read from each,
        its fields being the channels; part of the resume key.
    time_unit : str, optional
        The unit of each file's time column (:func:`noisevar.io.load_table`); part of the
        resume key when given.
    series : str, optional
        The series read of each file that stacks several (:func:`noisevar.io.load_table`):
        a file without that label, or that holds one series, is a row with its reason;
        part of the resume key when given.
    **params
        The method's parameters (as for :func:`noisevar.estimate`).

    Returns
    -------
    pandas.DataFrame
        Every row of the output: :data:`KEY_COLUMNS`, the estimate's row (the one
        schema, :data:`noisevar.estimators.results.ROW_COLUMNS` with ``flag_*``
        columns) and :data:`RUN_COLUMNS`. A file that cannot be read is one row whose
        ``error`` says why.

    Notes
    -----
    Rows equal single-file estimates exactly: each channel is estimated on its own,
    with the same loader as ``noisevar estimate``. With ``jobs > 1`` a script must call
    ``batch`` under ``if __name__ == "__main__":`` (worker processes import it).
    """
    from noisevar.estimators import method_spec

    spec = method_spec(method)
    if spec.needs_reference:
        raise NoisevarError(
            f"{method} needs a second sensor of the same quantity; a batch estimates each "
            "channel on its own: choose another method"
        )
    spec.validate(params)  # a bad parameter stops the batch before it starts
    cols = parse_columns(columns)
    n_jobs, cut = check_jobs(jobs)
    if cut and client is None:
        warnings.warn(cut, stacklevel=2)
    target = Path(out) if out is not None else None
    if target is not None:
        out_format(target)
    skip = {str(target), str(journal_path(target))} if target is not None else set()
    files = [f for f in expand_paths(paths) if f not in skip]
    if not files:
        raise NoisevarError("no data file found in the given paths")
    time_unit, series = TIME_UNIT.validate(time_unit), checked_series(series)
    asked = {**params, **how_read(time_unit, series)}  # a row is reused for the same reading
    request = request_key(cols, method, asked, topic)
    with output_lock(target) if target is not None else contextlib.nullcontext():
        todo, kept = _plan(files, _previous(target, resume, files), request)
        task = (cols, method, dict(params), topic, time_unit, series)  # run_task's, after files
        return _run(todo, kept, task, request, target, n_jobs, client, resume, progress)


def _run(  # noqa: PLR0913 - the batch's arguments, once checked
    todo: list[str],
    kept: list[dict[str, Any]],
    args: tuple,
    request: str,
    target: Path | None,
    n_jobs: int,
    client: Any,
    resume: bool,
    progress: Progress,
) -> pd.DataFrame:
    """Run the tasks of ``todo``, journalling their rows; the table of kept and new rows."""
    k = task_size(len(todo), _workers(n_jobs, client))
    groups = [todo[i : i + k] for i in range(0, len(todo), k)]
    journal = open_journal(journal_path(target), fresh=not resume) if target else None
    new: list[dict[str, Any]] = []
    advance, close = _progress(progress, len(todo))
    try:
        for rows in _stream(groups, args, n_jobs, client):
            for r in rows:
                r["request"] = request
            new.extend(rows)
            if journal is not None:
                append_rows(journal, rows)
            advance(len({r["file"] for r in rows}))
    finally:
        close()
        frame = _finish(target, journal, kept, new)
    return frame


def _finish(target: Path | None, journal: Any, kept: list[dict], new: list[dict]) -> pd.DataFrame:
    """The output table: kept and new rows sorted by file; written, and the journal removed."""
    rows = [*kept, *new]
    frame = rows_frame(rows) if rows else rows_frame([{"file": None}]).iloc[0:0]
    if not frame.empty:
        order = {f: i for i, f in enumerate(sorted({str(x) for x in frame["file"]}))}
        frame = frame.iloc[
            sorted(range(len(frame)), key=lambda i: order[str(frame["file"].iat[i])])
        ].reset_index(drop=True)
    if target is not None:
        commit(frame, target, journal)
    return frame
