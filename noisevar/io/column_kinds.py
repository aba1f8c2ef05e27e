"""Columns of a table that are bookkeeping, not a signal: counters, a date's parts, axes
(:attr:`noisevar.io.LoadedTable.first_signal` and ``.signals`` pass them over; each can
still be named). A logger's missing-value code read as a number is
:mod:`noisevar.io.quirks`'.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def bookkeeping(z: NDArray) -> bool:
    """Whether the finite values ``z`` of a column are bookkeeping, not a measured signal.

    A frame counter with drops, a sequence counter that wraps, a date's part (a year, a
    month, a day) or an axis the rows are written along (a depth, an age); a clock that
    steps evenly is :func:`noisevar._arrays.steps_evenly`'s.

    Parameters
    ----------
    z : ndarray
        The column's finite values, in order.

    Returns
    -------
    bool
    """
    return (
        _frame_counter(z)
        or _wrapping_counter(z)
        or _calendar_part(z)
        or _axis(z)
        or not_measured(z) is not None
    )


#: Distinct whole values a flag or a code holds at most (Météo-France's quality codes: 0, 1
#: and 9): noise under one step toggles between neighbours instead.
CODE_VALUES = 3
#: Distinct values a column of clock times written HHMM must hold: a measured whole
#: number from 0 to 2359 keeps its last two digits under 60 with probability (60/100)^n,
#: under 1e-3 from 14 values on.
HHMM_VALUES = 14


def not_measured(z: NDArray) -> str | None:
    """Why the finite values ``z`` of a column are no measured signal, in a few words, or
    None: a flag or a code (up to :data:`CODE_VALUES` whole values, not all neighbours, or
    0 and 1: a digital line), or clock times written HHMM.

    Parameters
    ----------
    z : ndarray
        The column's finite values.

    Returns
    -------
    str or None

    Notes
    -----
    Météo-France's daily files (benchmarks/real_audit15.py) hold a quality code beside
    each field (``QRR``: 0, 1 and 9) and the time of day of each extreme as HHMM (``HTN``:
    2250 for 22:50); ``--columns all`` estimated both as signals. A sensor's noise under one
    step toggles between neighbouring values, so two neighbours (512, 513) stay a signal;
    whole numbers within one hundred (515-545) stay one too: times span two hours or more,
    which a signal crosses through 60-99.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        if z.size < 2 or not np.all(z == np.round(z)):
            return None
        values = np.unique(z)
        apart = bool(np.any(np.diff(values) > 1))  # ±1e308: inf apart, no warning
    # a digital line is 0 and 1; 0, 1, 2 are neighbours, a count's noise at rest (rain tips)
    if values.size <= CODE_VALUES and (apart or (values.size == 2 and values[0] == 0)):
        return f"a flag or a code ({values.size} values), not a measured signal"
    hours = np.unique(values // 100).size  # a signal across an hour passes 60-99 too
    hhmm = values[0] >= 0 and values[-1] < 2400 and bool(np.all(values % 100 < 60))
    if hhmm and hours > 1 and values.size >= HHMM_VALUES:
        return "clock times written HHMM (minutes never past 59), not a measured signal"
    return None


def _wrapping_counter(z: NDArray) -> bool:
    """Whether ``z`` is a sequence counter that wraps (BITalino's 4-bit ``nSeq``: 0..15, 0,
    1, ...): whole numbers that rise by 1 each step except where they fall back to their
    least value."""
    with np.errstate(over="ignore", invalid="ignore"):
        if z.size < 3 or not np.all(z == np.round(z)):
            return False
        steps = np.diff(z)
        lo, hi = float(z.min()), float(z.max())
        wrap = steps == lo - hi
        return bool(hi > lo and wrap.any() and np.all((steps == 1) | wrap))


def _calendar_part(z: NDArray) -> bool:
    """Whether ``z`` is a part of a date: whole numbers that hold or rise by 1 and fall back
    only to their least value (a year, a month or a day column of daily rows: the IERS's
    ``YR MM DD``, NOAA's ``YEAR``), which the counters' rules do not catch (they hold)."""
    with np.errstate(over="ignore", invalid="ignore"):
        if z.size < 8 or not np.all(z == np.round(z)):
            return False
        steps = np.diff(z)
        wrap = (steps < 0) & (z[1:] == z.min())
        return bool(np.all((steps == 0) | (steps == 1) | wrap))


def _axis(z: NDArray) -> bool:
    """Whether ``z`` is an axis the rows are written along: strictly monotone (an ice core's
    depth or age, a decimal year rounded to 6 digits), which no signal with noise is over
    a record (:func:`~noisevar._arrays.steps_evenly` catches the even ones only)."""
    with np.errstate(over="ignore", invalid="ignore"):
        steps = np.diff(z)
        return bool(z.size >= 8 and (np.all(steps > 0) or np.all(steps < 0)))


def _frame_counter(z: NDArray) -> bool:
    """Whether ``z`` counts frames with some dropped: whole numbers rising by 1 at most steps
    and never falling or holding (a camera's ``frame_number``, a message's ``seq`` with
    drops), which :func:`~noisevar._arrays.steps_evenly` does not catch."""
    with np.errstate(over="ignore", invalid="ignore"):  # 1e308 cells: inf steps, no counter
        steps = np.diff(z)
        whole = bool(np.all(z == np.round(z)))
        return bool(steps.size > 1 and np.all(steps >= 1) and whole and np.median(steps) == 1)


#: A column whose values after the first are the clock's steps times one of these (seconds
#: to ns .. s) is the clock's steps
_STEP_SCALES = (1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9)


def time_steps(z: NDArray, t: NDArray) -> bool:
    """Whether the column ``z`` holds the steps of the clock ``t`` (a ``dt`` column), in
    any of :data:`_STEP_SCALES`: from its second row on, each value is the time since the
    row before (the first has no step and holds anything: KITTI's holds its own time).

    Notes
    -----
    gtsam's KITTI IMU file starts ``Time dt accelX ...``: with no column named, ``dt`` was
    read as the signal, and its first row (46,534 s) as a glitch.
    """
    if z.shape != t.shape or z.size < 8:
        return False
    steps, vals = np.diff(t), z[1:]
    ok = np.isfinite(steps) & np.isfinite(vals)
    if ok.sum() < 7 or not np.any(steps[ok] > 0):
        return False
    steps, vals = steps[ok], vals[ok]
    tol = 1e-9 * float(np.abs(steps).max())
    with np.errstate(over="ignore", invalid="ignore"):
        return any(bool(np.allclose(vals, k * steps, rtol=1e-6, atol=k * tol))
                   for k in _STEP_SCALES)  # fmt: skip
