"""The abscissa of a record's figures: seconds or sample index, and back.

A record is drawn against time when its sample period (or its own time stamps) is
known, else against the sample index. :func:`x_axis` maps sample indices to that
abscissa and :func:`range_to_slice` maps a range of it (a box selection on a figure)
back to the samples it covers.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Seconds per sample (float), the samples' own times (array, seconds) or None (sample index).
Timing = float | NDArray | None


def x_axis(idx: ArrayLike, sample_period: Timing = None, t0: float = 0.0) -> NDArray:
    """Abscissa of sample indices: seconds when a sample period is known, else the index.

    ``sample_period`` may also be the record's own time stamps (an array of
    seconds, one per sample): records with gaps are then drawn against real time.

    Parameters
    ----------
    idx : array_like of int
        Sample indices.
    sample_period : float, optional
        Seconds per sample.
    t0 : float
        Time of sample 0.

    Returns
    -------
    ndarray of float
    """
    idx = np.asarray(idx, dtype=float)
    if isinstance(sample_period, np.ndarray):  # the samples' own times: gaps stay gaps
        return np.interp(idx, np.arange(sample_period.size), sample_period)
    return t0 + idx * sample_period if sample_period else idx


def range_to_slice(
    x0: float, x1: float, n: int, sample_period: Timing = None, t0: float = 0.0
) -> slice:
    """Sample slice covered by an abscissa range (a box selection on a figure).

    Parameters
    ----------
    x0, x1 : float
        Range on the abscissa of :func:`x_axis` (either order).
    n : int
        Samples in the record.
    sample_period : float, optional
        Seconds per sample, as used for the figure.
    t0 : float
        Time of sample 0.

    Returns
    -------
    slice
        ``slice(start, stop)`` clipped to ``[0, n]``.
    """
    lo, hi = sorted((float(x0), float(x1)))
    if isinstance(sample_period, np.ndarray):  # the samples' own times
        start = int(np.searchsorted(sample_period, lo, side="left"))
        stop = int(np.searchsorted(sample_period, hi, side="right"))
        return slice(min(start, n), max(min(start, n), min(stop, n)))
    if sample_period:
        lo, hi = (lo - t0) / sample_period, (hi - t0) / sample_period
    start = int(np.clip(np.ceil(lo), 0, n))
    stop = int(np.clip(np.floor(hi) + 1, 0, n))
    return slice(start, max(start, stop))


def unit_name(units: str | None, name: str) -> str:
    """An axis or legend title with its units: ``"signal (m)"``, or ``name`` without units.

    Parameters
    ----------
    units : str or None
        Units of the quantity (empty for none).
    name : str
        The quantity.

    Returns
    -------
    str
    """
    return f"{name} ({units})" if units else name


def has_time(sample_period: Timing) -> bool:
    """Whether ``sample_period`` (a period or the samples' times) gives seconds."""
    return isinstance(sample_period, np.ndarray) or bool(sample_period)


def x_title(sample_period: Timing) -> str:
    """Axis title matching :func:`x_axis`.

    Parameters
    ----------
    sample_period : float or None
        Seconds per sample; ``None`` or 0 for a sample-index axis.

    Returns
    -------
    str
        ``"time (s)"`` or ``"sample"``.
    """
    return "time (s)" if has_time(sample_period) else "sample"
