"""The work of one task: files in, one row per file x channel out (run in any process)."""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from noisevar.errors import NoisevarError

#: Columns of every batch row, in output order; ``flag_<name>`` columns follow ``outlier_fraction``
#: when the estimates carry diagnostics.
ROW_COLUMNS: tuple[str, ...] = (
    "file",
    "channel",
    "n",
    "n_used",
    "variance",
    "std",
    "ci95_lo",
    "ci95_hi",
    "dof",
    "core_variance",
    "outlier_fraction",
    "verdict",
    "method",
    "params",
    "notes",
    "elapsed_s",
    "hash",
    "error",
    "request",
)


def _finite(value: Any) -> float | None:
    """A float, or None for a missing or non-finite value (rows are JSON-safe)."""
    if value is None:
        return None
    v = float(value)
    return v if math.isfinite(v) else None


def _json_value(obj: Any) -> Any:
    if hasattr(obj, "item"):
        return obj.item()
    if hasattr(obj, "tolist"):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def parse_columns(columns: str | Sequence[str] | None) -> str | list[str] | None:
    """``"all"``, ``None`` (the first data column) or a list of column names.

    Parameters
    ----------
    columns : str, sequence of str or None
        ``"all"``, a comma-separated list ``"a,b,c"``, a list of names, or None.

    Returns
    -------
    "all", list of str or None
    """
    if columns is None:
        return None
    if isinstance(columns, str):
        if columns.strip().lower() == "all":
            return "all"
        names = [c.strip() for c in columns.split(",") if c.strip()]
    else:
        names = [str(c) for c in columns]
    if not names:
        raise NoisevarError("no column given: name the columns (a,b,c) or say 'all'")
    return names


def table_channels(table: Any, columns: str | list[str] | None) -> list[str]:
    """The channel names of ``table`` selected by :func:`parse_columns`'s result."""
    if columns == "all":
        names = list(table.data_columns)
        if not names:
            raise NoisevarError(f"{table.name} has no data column (only a time column)")
        return names
    if columns is None:
        return [table.data_columns[0]] if table.data_columns else [None]
    return list(columns)


def estimate_row(
    file: str, table: Any, channel: str | None, method: str, params: dict[str, Any]
) -> dict[str, Any]:
    """One row: the estimate of one channel of a loaded table, or its error."""
    import noisevar
    from noisevar.io import pick_column

    start = time.perf_counter()
    row: dict[str, Any] = {"file": file, "channel": channel, "method": method}
    try:
        z = pick_column(table, channel, drop_nonfinite=bool(params.get("drop_nonfinite")))
        row["n"] = int(z.size)
        est = noisevar.estimate(z, method=method, **params)
    except NoisevarError as exc:
        row["error"] = str(exc)
        row["elapsed_s"] = time.perf_counter() - start
        return row
    row.update(estimate_fields(est))
    row["elapsed_s"] = time.perf_counter() - start
    return row


def estimate_fields(est: Any) -> dict[str, Any]:
    """The row fields of one :class:`~noisevar.estimators.results.VarianceEstimate`."""
    out: dict[str, Any] = {
        "n_used": int(est.n_used),
        "variance": _finite(est.variance),
        "std": _finite(est.std),
        "ci95_lo": _finite(est.ci95[0]),
        "ci95_hi": _finite(est.ci95[1]),
        "dof": _finite(est.dof),
        "core_variance": _finite(getattr(est, "core_variance", None)),
        "outlier_fraction": _finite(getattr(est, "outlier_fraction", None)),
        "params": json.dumps(est.params, sort_keys=True, default=_json_value),
        "notes": " | ".join(est.notes) if est.notes else None,
    }
    diag = getattr(est, "diagnostics", None)
    if diag is not None:
        out["verdict"] = str(getattr(diag, "verdict", "")) or None
        for key, flag in dict(getattr(diag, "flags", {}) or {}).items():
            out[f"flag_{key}"] = bool(flag)
    return out


def file_rows(
    path: str, columns: str | list[str] | None, method: str, params: dict[str, Any]
) -> list[dict[str, Any]]:
    """Every row of one file: one per channel, or one row with the file's error.

    Parameters
    ----------
    path : str
        The file (CSV/TSV, ``.npy`` or NMEA: whatever :func:`noisevar.io.load_table` reads).
    columns : "all", list of str or None
        The channels (:func:`parse_columns`).
    method : str
        Estimator.
    params : dict
        Its parameters.

    Returns
    -------
    list of dict
        Rows keyed by :data:`ROW_COLUMNS` (and ``flag_*``); a row's ``hash`` is the
        file's content hash, so that a resumed batch can skip it.
    """
    from noisevar.io import content_digest, load_table

    start = time.perf_counter()
    digest = None
    try:
        raw = Path(path).read_bytes()
        digest = content_digest(raw)
        table = load_table(raw, os.path.basename(path))
        channels = table_channels(table, columns)
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
    for r in rows:
        r["hash"] = digest
    return rows


def run_task(
    paths: Sequence[str], columns: str | list[str] | None, method: str, params: dict[str, Any]
) -> list[dict[str, Any]]:
    """The rows of a group of files (the unit of work sent to a process or a Dask worker).

    A file that fails in an unexpected way becomes one error row; the others go on.
    """
    rows: list[dict[str, Any]] = []
    for p in paths:
        try:
            rows.extend(file_rows(p, columns, method, params))
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
