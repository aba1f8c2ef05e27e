"""Series labelled by numbers (a turbine, vehicle or station number) in a file that stacks
several, and a picked series' own clock (docs/algorithms.md, "One series by its label").

A numeric column names the series when its values are whole numbers, few
(:func:`few_values`), and its series share one clock or follow one another
(:func:`on_one_clock`); :func:`noisevar.io.stacked.stacks` then decides, as for a text label.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar._arrays import EXACT_INT
from noisevar.io.headerless import ON_STEP

if TYPE_CHECKING:
    import pandas as pd

#: Rows each value of a label column holds on average, at least (fewer: a measured quantity).
LABEL_ROWS = 20


def few_values(cells: pd.Series) -> bool:
    """Whether ``cells`` hold few values: 2 or one per :data:`LABEL_ROWS` rows, at most."""
    return int(cells.nunique()) <= max(2, cells.size // LABEL_ROWS)


def on_one_clock(key: NDArray, t: NDArray) -> bool:
    """Whether the whole numbers ``key`` label series that follow one another (each value
    one contiguous block) or share one clock: in each run of rows whose time ``t`` does not
    rise, each value at most once in :data:`~noisevar.io.headerless.ON_STEP` of the runs,
    and two values or more, half of them or more, on average.

    Notes
    -----
    OpenOA's La Haute Borne SCADA file writes each time stamp once per turbine. A status
    flag, a quantised sensor (an ADC count) or a fix quality repeats its value within a
    time stamp written coarser than the rows (10 rows a second, the time in seconds); a
    sample counter (0-255 over and over) holds 10 of its 256 values in each. A digital
    line whose clock is reset once (two sessions) holds one value in each run of one row.
    """
    n_values = np.unique(key).size
    if np.count_nonzero(key[1:] != key[:-1]) == n_values - 1:
        return True
    with np.errstate(invalid="ignore"):
        run = np.concatenate([[0], np.cumsum(np.diff(t) > 0)])
    order = np.lexsort((key, run))
    twice = (run[order][1:] == run[order][:-1]) & (key[order][1:] == key[order][:-1])
    n_runs = int(run[-1]) + 1
    clean = 1.0 - np.unique(run[order][1:][twice]).size / n_runs
    held = (key.size - np.count_nonzero(twice)) / n_runs
    return clean >= ON_STEP and held >= max(2.0, n_values / 2)


def number_keys(columns: dict[str, NDArray], t: NDArray) -> dict[str, pd.Series]:
    """The numeric columns (other than the clock ``t``) that may label series: whole
    numbers in every row (within 2**53), of :func:`few_values`, :func:`on_one_clock`; none
    when ``t`` rises at every step (a file whose time never falls back is one series)."""
    import pandas as pd

    with np.errstate(invalid="ignore"):
        if t.size < 3 or bool(np.all(np.diff(t) > 0)):
            return {}
    keys = {}
    for c, v in columns.items():
        whole = np.all(np.isfinite(v)) and np.all(v == np.round(v))
        if v is t or not whole or np.abs(v).max() > EXACT_INT:
            continue
        key = pd.Series(v.astype(np.int64))
        if key.nunique() >= 2 and few_values(key) and on_one_clock(key.to_numpy(), t):
            keys[c] = key
    return keys


def number_label(label: str) -> str:
    """A label given for a column of whole numbers as that column's values read: ``"02"``
    and ``"2.0"`` as ``"2"``; any other text as given (refused as no row's)."""
    try:
        x = float(label)
    except ValueError:
        return label
    return str(int(x)) if np.isfinite(x) and x == round(x) else label


def own_clock(
    columns: dict[str, NDArray], time_col: str | None, relative: bool, first: float | None
) -> float | None:
    """A picked series' times (``time_col``; None: none, or no series picked) from its own
    first row, as the file of its rows alone reads them: the time column rebased (in place)
    when it was read relative to the file's first row (``relative``: date-times, clock
    times; ``first``: integers beyond 2**53, taken relative to that first value, which is
    returned moved to the series' first row).

    Notes
    -----
    iglu's Subject 2 started at -8.8e6 s, the file's first patient's first reading.
    """
    if time_col is None or not (relative or first is not None):
        return first
    t = columns[time_col]
    finite = t[np.isfinite(t)]
    origin = float(finite[0]) if finite.size else 0.0
    columns[time_col] = t - origin
    return None if first is None else first + origin
