"""A sample period from a time column's stamps: the digits they support, and the period of a
uniform clock whose stamps were rounded (a 64 Hz logger's stamps written to the
millisecond step by 15 and 16 ms)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def timestamp_resolution(t: NDArray) -> float:
    """The finest step the timestamps can tell apart (seconds).

    The decimal step they are written in (``1e-6`` for six decimals), or the float
    spacing at the largest timestamp when they carry every digit.
    """
    floor = 4.0 * float(np.spacing(float(np.max(np.abs(t)))))
    head = t[:1000]
    for k in range(13):
        step = 10.0**-k
        if step <= floor:
            break
        off = np.abs(head / step - np.round(head / step)) * step
        if np.all(off <= max(floor, 1e-6 * step)):
            return step
    return floor


def _shortest(x: float, rel: float) -> tuple[int, float]:
    """The fewest significant digits that keep ``x`` within ``rel`` of itself."""
    for d in range(1, 16):
        r = float(f"{x:.{d}g}")
        if abs(r - x) <= rel * abs(x):
            return d, r
    return 16, x


def rounded_period(t: NDArray, step: float) -> float:
    """A sample period cut to the digits the timestamps support.

    Parameters
    ----------
    t : ndarray
        The time column (seconds, increasing).
    step : float
        Its median step.

    Returns
    -------
    float
        The step, or ``1 / rate``, whichever of period and rate needs fewer
        significant digits to stay within the timestamps' precision: timestamps
        at 1/120 s give exactly ``1 / 120`` (120 Hz, not 120.00000000004799), a
        step of 3600 s stays 3600 s.

    Notes
    -----
    One step is known to about half the timestamps' resolution (relative
    precision ``resolution / (2 step)``, at least 1e-12); period and rate share it.
    """
    return _cut(step, max(0.5 * timestamp_resolution(t) / step, 1e-12))


def _cut(step: float, rel: float) -> float:
    """``step`` or ``1 / rate``, whichever needs fewer digits to stay within ``rel``."""
    d_period, period = _shortest(step, rel)
    d_rate, rate = _shortest(1.0 / step, rel)
    return 1.0 / rate if d_rate < d_period else period


def clock_period(t: NDArray, dt: NDArray) -> tuple[float, str] | None:
    """The period of a uniform clock whose stamps ``t`` were rounded to their resolution, and
    the note that says so; None when ``t`` is not such a clock.

    Parameters
    ----------
    t : ndarray
        The time column (seconds, increasing).
    dt : ndarray
        Its steps.

    Returns
    -------
    tuple of (float, str) or None
        The clock's step (the stamps' least-squares slope), cut to the digits the
        whole span supports (as :func:`rounded_period`), and a note; None unless the
        steps take two values one resolution apart, the smaller at least two
        resolutions, and every stamp lies within one resolution of the straight line
        from the first to the last.

    Notes
    -----
    The Daphnet set's 64 Hz accelerometers (aeon's ``S06R02E0.csv``) have stamps written
    to the millisecond: steps of 15 and 16 ms, read as a period of 16 ms (62.5 Hz) and as
    non-uniform sampling. Missed samples (a 1 s logger's 2 s steps) are not taken for
    rounding: their smaller step is one resolution, and their stamps leave the line.
    """
    res = timestamp_resolution(t)
    lo, hi = float(dt.min()), float(dt.max())
    if t.size < 3 or abs(hi - lo - res) > 1e-6 * res or lo < 2.0 * res:
        return None
    span = float(t[-1] - t[0])
    line = t[0] + span * np.arange(t.size) / (t.size - 1)
    if np.max(np.abs(t - line)) > res * (1 + 1e-6):
        return None
    slope = float(np.polyfit(np.arange(t.size), t, 1)[0])  # the clock's step, least squares
    period = _cut(slope, max(res / span, 1e-12))
    return period, (
        f"the time stamps are written to {res:g} s, so a uniform clock's steps read "
        f"{lo:.4g} or {hi:.4g} s: taken as uniform, its period the clock's step, {period:.6g} s "
        f"({1.0 / period:.6g} Hz)"
    )
