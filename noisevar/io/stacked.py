"""Files that stack or interleave several series (the long format), refused in one line."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

if TYPE_CHECKING:
    import pandas as pd


def refuse_stacked(key: pd.Series, t: NDArray, cname: str, name: str) -> None:
    """Refuse a file that stacks or interleaves several series (the long format: a text
    column ``key`` naming each row's series, the time column ``t`` falling back or repeating
    where ``key`` changes), in one line that says to give one series.

    Notes
    -----
    Read as one record, the series were spliced: vega_datasets' ``stocks.csv`` (five stocks'
    prices one after the other, R over their joins), traffic's ten aircraft at Zurich (in
    blocks, each on its own day) and OpenOA's La Haute Borne SCADA file (four turbines' rows
    interleaved, each time stamp four times: R 163 on the blade pitch against 11 on one
    turbine's). A time stamp that repeats inside one series, away from a change of the
    label (a status column), is no stacking.
    """
    k = key.to_numpy()
    labels = list(dict.fromkeys(key.tolist()))
    back = np.flatnonzero(~(np.diff(t) > 0))  # falls back or repeats (NaN: not a rise)
    if len(labels) < 2 or not back.size:
        return
    at = np.intersect1d(back, np.flatnonzero(k[1:] != k[:-1])).size
    if at < max(1.0, (len(labels) - 1) / 2) or at < back.size / 2:
        return
    shown = ", ".join(repr(echo(str(v), 20)) for v in labels[:3])
    raise NoisevarError(
        f"{echo(name)} stacks {len(labels)} series, one per value of column {echo(cname)!r} "
        f"({shown}{', ...' if len(labels) > 3 else ''}), its time falling back or repeating "
        f"where the value changes: give one series, e.g. the rows of one {echo(cname)!r} "
        "saved as their own file"
    )
