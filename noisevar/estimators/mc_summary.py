"""A Monte Carlo method's summary row, and when its runs are too few for statistics (issue 28).

Bias, sd and RMSE of the runs that succeeded describe the method only when most runs
succeeded: three survivors of a hundred are the runs where the method happened to work.
Below :data:`MIN_OK_FRACTION` of the runs done (or under two runs), a row carries no
statistics and says ``failed 97/100`` instead; the figure draws no histogram for it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: Statistics are shown only when at least this fraction of the runs done succeeded.
MIN_OK_FRACTION = 0.5
#: The statistics a row carries when enough runs succeeded.
STAT_KEYS = ("bias", "sd", "rmse", "rmse_over_cr", "within_10pct", "max_abs")


def enough_runs(ok: int, done: int) -> bool:
    """Whether ``ok`` successful runs of ``done`` are enough for statistics."""
    return ok >= 2 and ok >= MIN_OK_FRACTION * done


def params_text(params: Mapping[str, Any]) -> str:
    """A method's parameters as ``"gamma_amp=0.05, window=40"`` (empty: its defaults)."""
    return ", ".join(f"{k}={v}" for k, v in params.items() if v is not None)


def summary_row(
    method: str,
    errors: NDArray,
    failures: int,
    done: int,
    cr_floor: float,
    params: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """One method's row: runs, failures, status, parameters and (enough runs) statistics.

    Parameters
    ----------
    method : str
    errors : ndarray
        Relative errors of the runs done (NaN where the method failed).
    failures : int
        Failed runs.
    done : int
        Runs done.
    cr_floor : float
        Cramér-Rao relative sd, ``sqrt(2/n)``.
    params : mapping, optional
        The method's parameters in use (empty: its defaults).

    Returns
    -------
    dict
        ``method, runs, failures, status, params`` and :data:`STAT_KEYS` (NaN when the
        runs are too few; ``status`` then reads ``"failed 97/100: ..."``).
    """
    ok = errors[np.isfinite(errors)]
    row: dict[str, Any] = {"method": method, "runs": int(ok.size), "failures": int(failures)}
    enough = enough_runs(int(ok.size), done)
    if failures and not enough:
        row["status"] = f"failed {failures}/{done}: too few successful runs for statistics"
    elif failures:
        row["status"] = f"failed {failures}/{done} (statistics of the {ok.size} others)"
    else:
        row["status"] = "" if enough else f"{ok.size} run(s): too few for statistics"
    row["params"] = params_text(params or {}) or "defaults"
    if enough:
        rmse = float(np.sqrt(np.mean(ok**2)))
        row.update(
            bias=float(ok.mean()),
            sd=float(ok.std(ddof=1)),
            rmse=rmse,
            rmse_over_cr=rmse / cr_floor,
            within_10pct=float(np.mean(np.abs(ok) <= 0.10)),
            max_abs=float(np.max(np.abs(ok))),
        )
    else:
        row.update(dict.fromkeys(STAT_KEYS, float("nan")))
    return row
