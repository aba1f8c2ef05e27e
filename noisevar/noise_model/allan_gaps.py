"""The Allan deviation of rate data that dropped samples (docs/algorithms.md §E4, gaps).

A logger that drops samples leaves stamps at whole multiples of the sensor's period.
The samples are placed on that base grid, the missing ones left empty, and the
overlapping Allan variance is taken from means of the samples each window holds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

#: A step of the stamps is a whole number k of base periods when it is within
#: ``STEP_TOL`` base periods of k (PX4's ``vehicle_angular_velocity``: 2 % jitter), and
#: every stamp lies within ``STAMP_TOL`` base periods of its grid slot (no drift, each
#: sample's slot unambiguous).
STEP_TOL = 0.25
STAMP_TOL = 0.5
#: A grid is given up (the samples taken as uniform) when it would hold more than this
#: many slots per sample present: a record that is mostly one long pause.
MAX_SLOTS_PER_SAMPLE = 8
#: A window's mean counts when it holds at least this share of its samples: the excess
#: white variance of its mean, ``sigma^2 (1/c - 1/m)``, is then at most ``sigma^2 / m``
#: (the term's own white part), and its samples' centroid within ``m/4`` of its centre.
WINDOW_SHARE = 0.5


@dataclass(frozen=True)
class StampGrid:
    """Stamps placed on a base period.

    Attributes
    ----------
    period : float
        The base period (s): the stamps' span over the base steps it holds.
    slot : ndarray of int
        Each sample's slot on the grid (0 for the first).
    """

    period: float
    slot: NDArray

    @property
    def size(self) -> int:
        """Slots of the grid, empty ones included."""
        return int(self.slot[-1]) + 1

    @property
    def dropped(self) -> int:
        """Empty slots (samples the logger dropped)."""
        return self.size - int(self.slot.size)


def stamp_grid(t: ArrayLike) -> StampGrid | None:
    """The base grid of stamps ``t`` when each step is a whole number of one period.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times (s), increasing.

    Returns
    -------
    StampGrid or None
        None when the steps are not whole multiples of one period (within
        :data:`STEP_TOL`), a stamp strays more than :data:`STAMP_TOL` periods from its
        slot, or the grid would be mostly empty (:data:`MAX_SLOTS_PER_SAMPLE`).

    Notes
    -----
    The base is the median of the steps below 1.5 times the shortest, refined to the
    stamps' span over the whole steps it holds.
    """
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 3 or not np.all(np.isfinite(t)):
        return None
    s = np.diff(t)
    if not np.all(s > 0):
        return None
    base = float(np.median(s[s < 1.5 * s.min()]))
    k = np.rint(s / base)
    if np.any(k < 1) or np.max(np.abs(s / base - k)) > STEP_TOL:
        return None
    slot = np.concatenate([[0], np.cumsum(k.astype(np.int64))])
    if slot[-1] + 1 > MAX_SLOTS_PER_SAMPLE * t.size:
        return None
    period = float((t[-1] - t[0]) / slot[-1])
    if np.max(np.abs(t - t[0] - slot * period)) > STAMP_TOL * period:
        return None
    return StampGrid(period, slot)


def gap_grid(t: ArrayLike | None, data: str, kind: str, regimes: str = "all") -> StampGrid | None:
    """The grid :func:`noisevar.allan` places the samples on: that of rate data's
    overlapping Allan deviation over the whole record, when :func:`stamp_grid` finds one
    with samples dropped; None otherwise (the samples are taken as uniform)."""
    if t is None or data != "rate" or kind != "oadev" or regimes == "still":
        return None
    grid = stamp_grid(t)
    return grid if grid is not None and grid.dropped else None


@dataclass(frozen=True)
class GappedDeviation:
    """Overlapping Allan deviation of rate data on a grid with empty slots.

    Attributes
    ----------
    m : ndarray of int
        Averaging factors (tau = m period).
    deviation : ndarray
        The deviation per factor.
    n : ndarray of int
        Terms (pairs of adjacent windows, both holding enough samples) per factor.
    full : ndarray of int
        Terms the grid would give with no slot empty.
    raw : ndarray
        The Allan variance before the excess is removed: the estimate's spread is that
        of ``raw`` (its relative spread times ``raw / deviation^2``).
    white : float
        The sample-to-sample variance removed as the windows' excess (see Notes).
    """

    m: NDArray
    deviation: NDArray
    n: NDArray
    full: NDArray
    raw: NDArray
    white: float


def gapped_adev(y: ArrayLike, grid: StampGrid, m: ArrayLike) -> GappedDeviation:
    """Overlapping Allan deviation of rate samples ``y`` on ``grid``, per factor ``m``.

    Parameters
    ----------
    y : array_like, shape (n,)
        Rate samples, one per stamp.
    grid : StampGrid
        Their slots (:func:`stamp_grid`).
    m : array_like of int
        Averaging factors in base periods.

    Returns
    -------
    GappedDeviation

    Notes
    -----
    Term ``j`` at factor ``m``: ``d = Y2 - Y1``, the means of the samples present in
    slots ``[j, j+m)`` and ``[j+m, j+2m)`` (each window with at least
    :data:`WINDOW_SHARE` of its samples); ``avar = mean(d^2) / 2``. A mean of ``c`` of
    ``m`` samples carries ``sigma^2 (1/c - 1/m)`` more sample-to-sample noise than the
    full mean; that excess, with ``sigma^2`` the Allan variance of adjacent samples both
    present, is subtracted from each term. Noise correlated over many samples (bias
    instability, random walks) is seen nearly alike by a full and a partial mean.
    """
    y = np.asarray(y, dtype=float)
    full_y = np.zeros(grid.size)
    have = np.zeros(grid.size)
    full_y[grid.slot] = y - y.mean()
    have[grid.slot] = 1.0
    sy = np.concatenate([[0.0], np.cumsum(full_y)])
    sc = np.concatenate([[0.0], np.cumsum(have)])
    pair = have[1:] * have[:-1]
    if not np.any(pair):
        raise NoisevarError("No two adjacent samples are present: no Allan deviation.")
    d1 = np.diff(full_y)[pair > 0]
    white = float(np.mean(d1**2) / 2)
    ms = np.asarray(m, dtype=np.int64)
    dev, raw = np.full(ms.size, np.nan), np.full(ms.size, np.nan)
    n = np.zeros(ms.size, dtype=np.int64)
    full = np.maximum(grid.size - 2 * ms + 1, 0)
    for i, k in enumerate(int(v) for v in ms):
        c = sc[k:] - sc[:-k]  # samples in window [j, j+k)
        s = sy[k:] - sy[:-k]
        ok = c >= WINDOW_SHARE * k
        c1, c2, s1, s2, ok1, ok2 = c[:-k], c[k:], s[:-k], s[k:], ok[:-k], ok[k:]
        use = ok1 & ok2
        n[i] = int(np.count_nonzero(use))
        if not n[i]:
            continue
        c1, c2 = c1[use], c2[use]
        d = s2[use] / c2 - s1[use] / c1
        excess = white * (1.0 / c1 + 1.0 / c2 - 2.0 / k)
        raw[i] = float(np.mean(d**2) / 2)
        avar = raw[i] - float(np.mean(excess) / 2)
        if avar > 0:
            dev[i] = np.sqrt(avar)
    return GappedDeviation(ms, dev, n, full, raw, white)
