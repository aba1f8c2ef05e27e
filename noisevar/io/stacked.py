"""Files that stack or interleave several series (the long format): refused in one line, or
one series read by its label (:data:`noisevar.io.series_option.SERIES`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import StackedSeries
from noisevar.io.headerless import ON_STEP
from noisevar.io.limits import echo
from noisevar.io.number_labels import number_keys, number_label
from noisevar.io.series_option import kept_labels, not_stacked, series_rows, stacked_message

if TYPE_CHECKING:
    import pandas as pd


def stacks(key: pd.Series, t: NDArray) -> bool:
    """Whether the text column ``key`` names the series a file stacks or interleaves: the
    time ``t`` falls back or repeats mostly where ``key`` changes, at half its changes of
    series or more, or at some when each value of ``key`` is one contiguous block (series
    one after the other, some starting later than the one before ends).

    Notes
    -----
    A time stamp that repeats inside one series, away from a change of the label (a status
    column), is no stacking. iglu's CGM file of 19 patients (in blocks, recorded over
    three years) falls back at 8 of its 18 joins only: the others start later.
    """
    k = key.to_numpy()
    n_labels = len(dict.fromkeys(key.tolist()))
    back = np.flatnonzero(~(np.diff(t) > 0))  # falls back or repeats (NaN: not a rise)
    if n_labels < 2 or not back.size:
        return False
    changes = np.flatnonzero(k[1:] != k[:-1])
    at = np.intersect1d(back, changes).size
    blocks = changes.size == n_labels - 1
    return at >= max(1.0, back.size / 2) and (blocks or at >= (n_labels - 1) / 2)


#: Share of a column's steps that rise for it to stand for the time of a table without a
#: time column (:func:`stack_clock`): the headerless-times rule's
#: (:data:`noisevar.io.headerless.ON_STEP`)
RISING = ON_STEP


def stack_clock(columns: dict[str, NDArray], names: list[str], time_idx: int | None
                ) -> NDArray | None:  # fmt: skip
    """The column whose falls back :func:`refuse_stacked` checks: the time column, or with
    none, the first column when :data:`RISING` of its steps rise and some fall back (a
    headerless file's times, unevenly spaced); None otherwise.

    Parameters
    ----------
    columns : dict of str to ndarray
        The numeric columns read so far.
    names : list of str
        The table's column names, in file order.
    time_idx : int or None
        The time column's index.

    Returns
    -------
    ndarray or None

    Notes
    -----
    radvel's ``rvs_toi141.dat`` (no header: a Julian date, a radial velocity, its error and
    the spectrograph, FEROS, CORALIE and HARPS one after the other) was read as one
    record with its dates as the signal (R = 20,366 d², the dates falling back at each
    spectrograph), where a header's ``time`` column was refused as stacked on ``tel``.
    """
    if time_idx is not None:
        return columns[names[time_idx]]
    first = columns.get(names[0]) if names else None
    if first is None or first.size < 3:
        return None
    with np.errstate(over="ignore", invalid="ignore"):  # ±1e308 cells: inf steps
        rises = np.diff(first) > 0
    return first if float(np.mean(rises)) >= RISING and not rises.all() else None


def refuse_stacked(keys: dict[str, pd.Series], t: NDArray | None, name: str) -> None:
    """Refuse a file that stacks or interleaves several series (the long format: a text
    column naming each row's series, the time column ``t`` (:func:`stack_clock`; None:
    none) falling back or repeating where it changes, :func:`stacks`), in one line that
    says to give one series; of the text columns ``keys`` that stack, the one of most
    values is named (its rows are one series).

    Notes
    -----
    Read as one record, the series were spliced: vega_datasets' ``stocks.csv`` (five stocks'
    prices one after the other, R over their joins), traffic's ten aircraft at Zurich (in
    blocks, each on its own day) and OpenOA's La Haute Borne SCADA file (four turbines' rows
    interleaved, each time stamp four times: R 163 on the blade pitch against 11 on one
    turbine's). iglu's 19 patients were told to keep the rows of one ``diagnosis`` (still
    13 patients spliced), not of one ``id``.
    """
    if t is None:
        return
    found = [(len(dict.fromkeys(c.tolist())), n) for n, c in keys.items() if stacks(c, t)]
    if not found:
        return
    n_labels, cname = max(found, key=lambda f: f[0])
    labels = list(dict.fromkeys(keys[cname].tolist()))
    raise StackedSeries(stacked_message(name, cname, labels), *kept_labels(cname, labels))


def one_series(
    keys: dict[str, pd.Series],
    columns: dict[str, NDArray],
    t: NDArray | None,
    name: str,
    series: str | None,
    notes: list[str],
) -> dict[str, NDArray]:
    """The columns of a text table, or with ``series`` given, the rows of that series only.

    Parameters
    ----------
    keys : dict of str to pandas.Series
        The text columns left out.
    columns : dict of str to ndarray
        The numeric columns, each of the file's rows.
    t : ndarray or None
        The time column (None: none).
    name : str
        The file's name (for messages).
    series : str or None
        The label of the series to read (:data:`noisevar.io.series_option.SERIES`).
    notes : list of str
        The loader's notes (which rows were read is added).

    Returns
    -------
    dict of str to ndarray

    Notes
    -----
    A file that stacks series without ``series`` is refused (:func:`refuse_stacked`), on a
    text column or on a numeric one that labels series by number
    (:func:`noisevar.io.number_labels.number_keys`); of one that does not, ``series`` is
    refused. The rows of the series are kept in file
    order: the stacking column is the finest label :func:`refuse_stacked` names.
    """
    numbers = number_keys(columns, t) if t is not None else {}
    try:
        if t is not None:
            refuse_stacked({**keys, **numbers}, t, name)
    except StackedSeries as stacked:
        if series is None:
            raise
        return _picked(keys, numbers, columns, stacked.column, series, name, notes)
    not_stacked(name, series)
    return columns


def _picked(
    keys: dict[str, pd.Series],
    numbers: dict[str, pd.Series],
    columns: dict[str, NDArray],
    column: str,
    series: str,
    name: str,
    notes: list[str],
) -> dict[str, NDArray]:
    """The rows of ``series`` on the stacking ``column``: a text column's, or a numeric
    one's (``numbers``: the label matched as a number, the column left out, constant)."""
    if column not in numbers:
        rows = series_rows(keys[column], series, column, name, notes)
        return {c: v[rows] for c, v in columns.items()}
    rows = series_rows(numbers[column], number_label(series), column, name, notes)
    notes.append(f"column {echo(column)!r} (the series' number) left out")
    return {c: v[rows] for c, v in columns.items() if c != column}
