"""A headerless table whose rows end in text (a photo log's file names): its first line is a
row, not the header, when it is written as the rows under it are."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

#: digits, masked when two text cells are compared
_DIGITS = re.compile(r"\d")
#: lines under the first compared with it
_ROWS = 5


def _shape(cells: Sequence[str], is_number: Callable[[str], bool]) -> list[str | None]:
    """A row's shape: None for a number, a text cell with its digits masked."""
    return [None if is_number(c) else _DIGITS.sub("0", c.strip()) for c in cells]


def first_line_is_row(lines: Sequence[Sequence[str]], is_number: Callable[[str], bool]) -> bool:
    """Whether the first of ``lines`` (each split into cells) is a data row of a headerless
    table rather than its header.

    Parameters
    ----------
    lines : sequence of sequence of str
        The table's first lines, split into cells.
    is_number : callable
        Whether a cell is a number as the table writes them.

    Returns
    -------
    bool
        True when the first line holds a number and each line under it (up to five) has
        the first's shape: numbers in the same cells, the same text where it has text,
        only digits changed.

    Notes
    -----
    A photo log's lines (a GPS time, east, north, height, three angles, then the photo's
    file name ``..._00805_0.tif``) are not all numbers, so the first was read as the header:
    its numbers named the columns and the first epoch was lost. A header's names differ
    from the text below them in more than their digits (``name`` over ``Alice``).
    """
    if len(lines) < 2:
        return False
    first = _shape(lines[0], is_number)
    if all(s is not None for s in first):
        return False
    return all(_shape(ln, is_number) == first for ln in lines[1 : _ROWS + 1])


#: Share of a headerless table's first-column steps within ``UNIFORM_TOLERANCE`` of their
#: median for the column to be read as times (the rest: gaps, which the times then show).
ON_STEP = 0.9


def _increasing_on_a_step(x: NDArray, tolerance: float) -> bool:
    """Strictly increasing, with :data:`ON_STEP` of its steps on their median step."""
    if x.size < 3 or not np.all(np.isfinite(x)):
        return False
    dt = np.diff(x)
    step = float(np.median(dt))
    on = np.abs(dt - step) <= tolerance * step
    return bool(np.all(dt > 0) and np.mean(on) >= ON_STEP)


def first_column_times(columns: dict[str, NDArray], tolerance: float) -> bool:
    """Whether a headerless table's first column is its times (the x of an x,y file).

    Parameters
    ----------
    columns : dict of str to ndarray
        The table's columns, in file order (``col0``, ``col1``, ...).
    tolerance : float
        Relative spread of a step still on the median step (``UNIFORM_TOLERANCE``).

    Returns
    -------
    bool
        True when there are two columns or more, the first is strictly increasing on a
        near-uniform step (:data:`ON_STEP` of its steps) and no other column is; and the
        first is not a sample counter (whole numbers stepping by 1: read as times, they
        would give the period of 1 a counter gives, and lose it as a channel).

    Notes
    -----
    stingray's ``lc_sample.txt`` (an X-ray light curve, mission time in seconds and the
    count rate, no header) was read with its times as a channel and a period of 1 s
    against its 0.125 s. A ramp signal is not strictly increasing once noise is on it.
    """
    cols = list(columns.values())
    if len(cols) < 2 or not _increasing_on_a_step(cols[0], tolerance):
        return False
    steps = np.diff(cols[0])
    if np.all(steps == 1.0) and np.all(cols[0] == np.round(cols[0])):
        return False  # a counter
    return not any(_increasing_on_a_step(c, tolerance) for c in cols[1:])
