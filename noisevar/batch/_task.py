"""The work of one task: files in, one row per file x channel out (run in any process)."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from typing import Any

from noisevar.batch.channels import channels_and_left_out, skipped_note
from noisevar.errors import NoisevarError


def estimate_row(
    file: str, table: Any, channel: str | None, method: str, params: dict[str, Any]
) -> dict[str, Any]:
    """One row: the estimate of one channel of a loaded table, or its error.

    The estimate's fields are its :meth:`~noisevar.estimators.results.VarianceEstimate.to_row`;
    a row whose estimate failed has ``n_total`` (the samples read) and ``error``. ``unit`` is
    the unit the file declares for the channel (a log's field, a header's ``[unit]``), if any.
    """
    from noisevar.estimators import estimate
    from noisevar.io import channel_record
    from noisevar.units import unit_label

    start = time.perf_counter()
    unit = unit_label(table.units.get(channel)) if channel is not None else None
    row: dict[str, Any] = {"file": file, "channel": channel, "unit": unit, "method": method}
    try:
        # as `noisevar estimate` reads a channel: the table's times (gaps split), one answer
        z, t = channel_record(table, channel, drop_nonfinite=bool(params.get("drop_nonfinite")))
        row["n_total"] = int(z.size)
        est = estimate(z, method=method, t=t, **params)
    except NoisevarError as exc:
        row["error"] = str(exc)
        row["elapsed_s"] = time.perf_counter() - start
        return row
    row.update(est.to_row())
    row["elapsed_s"] = time.perf_counter() - start
    return row


def file_rows(
    path: str,
    columns: str | list[str] | None,
    method: str,
    params: dict[str, Any],
    topic: str | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> list[dict[str, Any]]:
    """Every row of one file: one per channel, or one row with the file's error.

    Parameters
    ----------
    path : str
        The file (CSV/TSV, ``.npy`` or NMEA: whatever :func:`noisevar.io.load_table` reads).
    columns : "all", list of str or None
        The channels (:func:`~noisevar.batch.channels.parse_columns`).
    method : str
        Estimator.
    params : dict
        Its parameters.
    topic : str, optional
        For a log (ROS bag file, ULog, DataFlash, Parquet, HDF5): the topic to read, its
        fields being the channels.
    time_unit : str, optional
        The unit of the time column's values (:func:`noisevar.io.load_table`).
    series : str, optional
        The series read of a file that stacks several (:func:`noisevar.io.load_table`).

    Returns
    -------
    list of dict
        ``file``, ``channel``, the estimate's row
        (:meth:`~noisevar.estimators.results.VarianceEstimate.to_row`) and ``elapsed_s``,
        ``hash``, ``error``; a row's ``hash`` is the file's content hash, so that a
        resumed batch can skip it.
    """
    from noisevar.batch.digest import file_digest
    from noisevar.io import load_table
    from noisevar.io.logs.spec import collecting

    start = time.perf_counter()
    digest = None
    said: list[str] = []  # what a log's reader says of the file (a bag cut short...)
    try:
        # hashed streamed and read by path (a log streamed too): any size, bounded memory
        digest = file_digest(path)
        with collecting(said):
            name = os.path.basename(os.path.normpath(path))
            table = load_table(path, name, topic=topic, time_unit=time_unit, series=series)
        channels, left_out = channels_and_left_out(table, columns)
    except (NoisevarError, OSError) as exc:
        msg = str(exc) if isinstance(exc, NoisevarError) else f"cannot read {path}: {exc}"
        return [
            {
                "file": path,
                "channel": None,
                "method": method,
                "hash": digest,
                "error": msg,
                "elapsed_s": time.perf_counter() - start,
            }
        ]
    rows = [estimate_row(path, table, c, method, params) for c in channels]
    for r, c in zip(rows, channels, strict=True):
        r["hash"] = digest
        r["sample_rate_hz"] = sample_rate(table, c)
        if said:  # the file's own notes first, in the row's one notes field
            r["notes"] = " | ".join([*said, *([r["notes"]] if r.get("notes") else [])])
    # a column "all" left out: a row saying why, as `noisevar estimate --columns all` gives
    rows += [
        {"file": path, "channel": c, "method": method, "hash": digest, "error": skipped_note(why)}
        for c, why in left_out.items()
    ]
    return rows


def sample_rate(table: Any, column: str | None = None) -> float | None:
    """A channel's sample rate in Hz: 1 / its sample period (its run's, in a table of runs:
    ``LoadedTable.period_of``), or its time column's median step.

    None without either (or a time column that does not increase), rounded to 12
    significant digits (a 120 Hz rate is 120, not 120.00000000004799).
    """
    import numpy as np

    period = table.period_of(column)
    if not period:
        t = table.time(column)
        steps = np.diff(np.asarray(t, dtype=float)) if t is not None and len(t) > 1 else None
        period = float(np.median(steps)) if steps is not None else None
    if not period or not np.isfinite(period) or period <= 0:
        return None
    return float(f"{1.0 / period:.12g}")


def run_task(
    paths: Sequence[str],
    columns: str | list[str] | None,
    method: str,
    params: dict[str, Any],
    topic: str | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> list[dict[str, Any]]:
    """The rows of a group of files (the unit of work sent to a process or a Dask worker).

    A file that fails in an unexpected way becomes one error row; the others go on.
    """
    rows: list[dict[str, Any]] = []
    for p in paths:
        try:
            rows.extend(file_rows(p, columns, method, params, topic, time_unit, series))
        except Exception as exc:  # noqa: BLE001 - a bad file is a row, never the end of the batch
            rows.append(
                {
                    "file": p,
                    "channel": None,
                    "method": method,
                    "error": f"unexpected error ({type(exc).__name__}: {exc})",
                }
            )
    return rows
