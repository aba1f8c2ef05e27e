"""What loggers write into a table that is not data: a header in numbers, a missing-value code,
one series written several values a line.

Both are read as numbers by a table reader, and both would be in R: the loader says so
(docs/algorithms.md, *Reading logs*).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.io.limits import echo

if TYPE_CHECKING:
    import pandas as pd

#: A headerless table's first row is a header of numbers when it lies further than this many
#: mean steps of the rest outside their range in every column but one, and in at least
#: this many columns
HEADER_FAR = 10.0
HEADER_MIN_COLUMNS = 3
NUMBERS_HEADER = (
    "the first row lies far outside the rest in {far} of {of} columns (a header of numbers, "
    "as UO SRML's files begin: a station, a year, element codes; or a logger's start-up "
    "row): left out of the data"
)


def header_of_numbers(columns: dict[str, NDArray]) -> str | None:
    """The note when a headerless table's first row is a header written in numbers, else None.

    A header when, of columns of 20 values or more (all of the table's), the first value
    lies outside the others' range by more than :data:`HEADER_FAR` times their mean step
    (any amount where the others are one value) in all but one, and in at least
    :data:`HEADER_MIN_COLUMNS`. A clock's first value is one step before the rest, and a
    signal's within a few steps of its next: data rows are not that far in nearly every
    column at once. UO SRML's day files begin ``94255 2018 1000 0 2010 0 ...`` (station,
    year, element codes and flags; the year falls inside the HHMM clock's range), which a
    user's CLI read as a glitch holding R = 3,519 of a pyranometer's 0.04.
    """
    cols = [v for v in columns.values() if v.size >= 20]
    if len(cols) < len(columns):
        return None
    far = sum(_far_first(v) for v in cols)
    if far < max(HEADER_MIN_COLUMNS, len(cols) - 1):
        return None
    return NUMBERS_HEADER.format(far=far, of=len(cols))


#: The lines a one-column file may start with before a count of the values below them
COUNT_LINES = 3
#: A count header counts at least this many values
COUNT_MIN = 8


def count_header(columns: dict[str, NDArray]) -> tuple[int, str] | None:
    """How many leading values of a headerless one-column file are its header, and the note:
    a whole number among the first :data:`COUNT_LINES` that counts the values below it (and
    the values above it), else None.

    Notes
    -----
    vallenae's ``signal.txt`` starts ``100.000000`` (its period), ``1024`` (its samples'
    count), then the 1,024 samples: read as samples, the two lines held R = 947 of the
    samples' 0.33 ("heavy-tailed"). A signal's value equal to the count of the values
    after it is a coincidence no record repeats on its first lines.
    """
    if len(columns) != 1:
        return None
    z = next(iter(columns.values()))
    for i, v in enumerate(z[:COUNT_LINES]):
        below = z.size - i - 1
        if below >= COUNT_MIN and v == below:
            head = ", ".join(f"{x:g}" for x in z[: i + 1])
            lines = "line" if i == 0 else f"{i + 1} lines"
            return i + 1, (
                f"the first {lines} ({echo(head)}) are a header, not samples ({below:g} counts "
                "the values below): left out of the data"
            )
    return None


def leading_header(columns: dict[str, NDArray]) -> tuple[int, str] | None:
    """A headerless table's leading rows that are a header, and the note: a first row of
    numbers far outside the rest (:func:`header_of_numbers`) or a one-column file's count
    of its values (:func:`count_header`), else None."""
    if (head := header_of_numbers(columns)) is not None:
        return 1, head
    return count_header(columns)


#: A headerless table of at least this many columns whose values, read row after row, step
#: (mean square) under ``ROWS_CONTINUE`` times down a column, also from one line's last value
#: to the next line's first, is one series written several values a line
ROWS_MIN_COLUMNS = 4
ROWS_CONTINUE = 0.5


def rows_continue(columns: dict[str, NDArray]) -> str | None:
    """The note when a headerless table is one series written k values a line, else None.

    Notes
    -----
    R prints a monthly series 12 values a line (pmdarima's ``sunspots.txt``): each column
    is then one calendar month of every year, and the first column's R is a yearly series'.
    Channels side by side step further across a line than down it, and several sensors of
    one quantity step from a line's last value to the next line's first as down a column.
    """
    cols = list(columns.values())
    if len(cols) < ROWS_MIN_COLUMNS or cols[0].size < 20:
        return None
    a = np.column_stack(cols)
    a = a[np.all(np.isfinite(a), axis=1)]  # (a last line cut short)
    down = float(np.mean(np.diff(a, axis=0) ** 2)) if a.shape[0] > 1 else 0.0
    along = float(np.mean(np.diff(a.ravel()) ** 2)) if a.size > 1 else 0.0
    wrap = float(np.mean((a[1:, 0] - a[:-1, -1]) ** 2)) if a.shape[0] > 1 else 0.0
    if not down > 0:
        return None
    if max(along, wrap) >= ROWS_CONTINUE * down:
        return _series_a_line(a, down)
    k = len(cols)
    return (
        f"the {k} columns continue each other along each line (read line after line the "
        f"values step {np.sqrt(down / along):.2g}x less than down a column): one series "
        f"written {k} values a line, as R prints a monthly series? Each column is then every "
        f"{k}th value: give the values one a line"
    )


def _series_a_line(a: NDArray, down: float) -> str | None:
    """The note when a headerless table about as wide as long (``a``: its complete lines)
    holds one series a line, else None: along each line its values step under
    ``ROWS_CONTINUE`` times down a column (mean square, ``down``), and from a line's end
    to the next line's start they jump (else :func:`rows_continue`'s one series).

    Notes
    -----
    The UCR archive's text files (tslearn's copies: Lightning2, 61 lines of a class and 637
    values) were read down a column, one instant of every case, with no word of it. Sensors
    side by side also step little along a line, but a record has far more lines than them.
    """
    lines, width = a.shape
    along = float(np.mean(np.diff(a, axis=1) ** 2))
    if width < lines / 2 or along >= ROWS_CONTINUE * down:
        return None
    return (
        f"the values step {np.sqrt(down / along):.2g}x less along each line than down a "
        f"column, and the table is about as wide as long ({width} columns, {lines} lines): "
        "one series a line, as the UCR archive writes its cases (a class, then the values)? "
        "Each column is then one instant of every series: give one line's values as a column"
    )


def _far_first(v: NDArray) -> bool:
    """The first value lies far outside the rest (:func:`header_of_numbers`)."""
    rest = v[1:][np.isfinite(v[1:])]
    if not np.isfinite(v[0]) or rest.size < 2:
        return False
    lo, hi = float(rest.min()), float(rest.max())
    gap = max(lo - float(v[0]), float(v[0]) - hi)
    step = float(np.mean(np.abs(np.diff(rest))))
    return gap > HEADER_FAR * step and gap > 0.0


#: share of a column's values at one extreme from which that value may be a missing-value code
CODE_SHARE = 0.05
#: ... when it lies further from every other value than this many times their range
CODE_GAP = 2.0


def code_note(cname: str, z: NDArray) -> str | None:
    """A note when many of a column's values are one extreme value far outside the others
    (NREL MIDC writes -7999, SURFRAD -9999.9, BSRN -999 for a missing value), else None.

    Such a value is read as a number, so it is in R: the note says how to leave it out.
    """
    z = z[np.isfinite(z)]
    if z.size < 20:
        return None
    for v in (float(z.min()), float(z.max())):
        same = z == v
        k = int(same.sum())
        if k < max(10, CODE_SHARE * z.size) or k == z.size:
            continue
        rest = z[~same]
        lo, hi = float(rest.min()), float(rest.max())  # Python floats: inf, not a warning
        span, gap = hi - lo, min(abs(lo - v), abs(hi - v))
        # (a signal of a few levels, a switch or a counter, is not a code and its values)
        if gap > CODE_GAP * span > 0 and np.unique(rest).size >= 10:
            return (
                f"column {echo(cname)!r}: {k:,} of {z.size:,} values ({k / z.size:.0%}) are "
                f"{v:g}, far outside the others: a logger's missing-value code? In R as they "
                "are; write those cells empty and drop them (CLI: --drop-nonfinite)"
            )
    return None


#: An angle's turn: degrees, radians
TURNS = (360.0, 2.0 * np.pi)
#: ... a column wraps when at least this many steps exceed half a turn and unwrapping them
#: cuts the steps' mean square by this factor
WRAP_MIN = 3
WRAP_CUT = 4.0
#: ... and its values spread over at least this share of the turn
WRAP_SPREAD = 0.9


def wrap_note(cname: str, z: NDArray) -> str | None:
    """A note when a column is an angle that wraps (a wind vane, a heading read from 0 to
    360 degrees), else None.

    Each wrap is a step of nearly a turn, so R counts it as a jump or an outlier: the note
    says to unwrap the column first.

    Notes
    -----
    brightwind's met mast and floating lidar write their wind directions from 0 to 360: R
    read as written was 7.8x (the mast's vane, 801 wraps) and 33x (the lidar's, 13 wraps)
    its R unwrapped, and no verdict said why.
    """
    z = z[np.isfinite(z)]
    if z.size < 20:
        return None
    lo, hi = float(z.min()), float(z.max())
    for turn in TURNS:
        within = max(abs(lo), abs(hi)) <= turn * (1 + 1e-9)  # first: no overflow at 1e308
        # spread over most of the turn (a 0/5 V logic channel is no angle in radians)
        if not (within and WRAP_SPREAD * turn < hi - lo <= turn * (1 + 1e-9)):
            continue
        steps = np.diff(z)
        wraps = int(np.count_nonzero(np.abs(steps) > turn / 2))
        unwrapped = np.diff(np.unwrap(z, period=turn))
        if wraps >= WRAP_MIN and WRAP_CUT * np.mean(unwrapped**2) < np.mean(steps**2):
            return (
                f"column {echo(cname)!r} wraps like an angle read from one turn ({wraps:,} "
                f"steps of over half of {turn:.4g}: a wind vane, a heading): R counts each wrap "
                f"as a jump; unwrap it first (numpy.unwrap(z, period={turn:.4g}))"
            )
    return None


def repeated_rows(
    columns: dict[str, NDArray], time_col: str | None, notes: list[str]
) -> dict[str, NDArray]:
    """``columns`` without the rows that repeat the row before in every column, time
    included and given (a logger's duplicated record), with a note; as they are without a
    time column or a time in the row (a held value is data there).

    Notes
    -----
    Garmin Connect's TCX export repeats a track point at a pause or a lap (sweat's smart
    recording: 4 of 100 rows): the time column was not increasing, so its times and its
    32 s pause were not used.
    """
    if time_col is None or columns[time_col].size < 2:
        return columns
    table = np.column_stack(list(columns.values()))
    same = np.all((table[1:] == table[:-1]) | (np.isnan(table[1:]) & np.isnan(table[:-1])), axis=1)
    # a row with no time is no duplicated record: a fix held while still, untimed (a GPX
    # track whose first fixes have no time)
    same &= np.isfinite(np.asarray(columns[time_col], dtype=float)[1:])
    k = int(np.count_nonzero(same))
    if k == 0:
        return columns
    keep = np.r_[True, ~same]
    notes.append(
        f"{k} rows repeat the row before in every column, time included (a duplicated "
        f"record, the first at data row {int(np.argmax(same)) + 2}): left out"
    )
    return {c: v[keep] for c, v in columns.items()}


#: Cells a missing-value mark must fill at least to be read as one (a single bad cell is a
#: typo or a garbled line, refused where it is)
MARK_CELLS = 2
_DIGIT = re.compile(r"\d")


def missing_mark(col: pd.Series, cname: str, notes: list[str]) -> NDArray | None:
    """A column of numbers whose other cells all hold one word with no digit (a writer's
    mark for no value: ``\\nodata``, ``OVER``, ``---``), read with those cells missing (a
    note appended to ``notes`` says so); None otherwise.

    Parameters
    ----------
    col : pandas.Series
        The column as pandas parsed it (text where a cell is not a number).
    cname : str
        The column's name, for the note.
    notes : list of str
        The loader's notes.

    Returns
    -------
    ndarray or None
        The column as floats, NaN at the marks.

    Notes
    -----
    radvel's ``164922_fixed.txt`` (a star's radial velocities, two spectrographs) writes
    ``\\nodata`` in its ``svalue`` column until the second spectrograph's rows: the whole
    file was refused, even with ``--column mnvel`` ("'\\nodata' is not a number"). The
    mark must fill :data:`MARK_CELLS` cells or more and hold no digit (a date, a clock
    time or a garbled number does), so one bad cell is still refused where it is.
    """
    import pandas as pd

    coerced = pd.to_numeric(col, errors="coerce")
    bad = coerced.isna() & col.notna()
    marks = set(col[bad].astype(str).str.strip())
    if len(marks) != 1 or int(bad.sum()) < MARK_CELLS or not coerced.notna().any():
        return None
    (mark,) = marks
    if _DIGIT.search(mark):
        return None
    notes.append(f"column {echo(cname)!r}: {echo(mark, 20)!r} in {int(bad.sum())} cells read "
                 "as missing (a mark for no value)")  # fmt: skip
    return np.array(coerced.to_numpy(dtype=float, na_value=np.nan), dtype=float)
