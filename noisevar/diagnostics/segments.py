"""Gaps and non-uniform sampling: where a record splits into uniform segments."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: A step outside ``(1 - GAP_RTOL, 1 + GAP_RTOL)`` times the typical period splits the record.
GAP_RTOL = 0.5
#: Jitter (relative spread of the steps within segments) worth a note.
JITTER_NOTE = 1e-2
#: A uniform segment this long or longer is long enough to estimate on its own.
SEGMENT_USABLE = 64
#: Steps (in periods) from which the record is split, tried in turn when splitting at every
#: irregular step leaves less than half of the samples in usable segments (a logger that
#: drops samples often; fixes logged at irregular times): the shorter steps are bridged,
#: the samples taken in order (the last: no split at all).
BRIDGE_STEPS = (2.5, 4.5, 8.5, 16.5, math.inf)


@dataclass(frozen=True)
class Gap:
    """A place where the record is not uniformly sampled.

    Attributes
    ----------
    index : int
        First sample after the gap (in the samples given).
    before, after : float
        Times of the samples either side (sample numbers when no times were given).
    missing : int
        About how many samples are missing (0 for a short or irregular step).
    kind : str
        ``"gap"`` (samples missing), ``"irregular"`` (a step too short) or ``"nan"``
        (non-finite samples dropped).
    """

    index: int
    before: float
    after: float
    missing: int
    kind: str

    def to_dict(self) -> dict[str, float | int | str]:
        return {
            "index": self.index,
            "before": self.before,
            "after": self.after,
            "missing": self.missing,
            "kind": self.kind,
        }


@dataclass(frozen=True)
class Segmentation:
    """Uniform segments of a record.

    Attributes
    ----------
    segments : tuple of (int, int)
        ``[start, stop)`` sample ranges, each uniformly sampled.
    gaps : tuple of Gap
    period : float or None
        Typical sampling period (None without times).
    jitter : float
        Largest relative deviation of a step from the period within the segments.
    """

    segments: tuple[tuple[int, int], ...]
    gaps: tuple[Gap, ...]
    period: float | None = None
    jitter: float = 0.0


def split_times(t: NDArray) -> Segmentation:
    """Split sample times ``t`` (finite, strictly increasing) into uniform segments.

    Parameters
    ----------
    t : ndarray, shape (n,)

    Returns
    -------
    Segmentation

    Notes
    -----
    A step outside ``1 +- GAP_RTOL`` periods splits the record. When that leaves less
    than half of the samples in segments of :data:`SEGMENT_USABLE` or more (a logger
    that drops every other sample now and then), the record is split only at steps of
    :data:`BRIDGE_STEPS` periods or more, the first that leaves more of it usable (at
    the last, nowhere); the samples between are taken in order as if uniform, which the
    jitter (then 0.5 or more) says.
    """
    n = t.size
    if n < 2:
        return Segmentation(((0, n),), ())
    dt = np.diff(t)
    period = float(np.median(dt))
    ratio = dt / period
    cut = np.flatnonzero(off_period(t))
    share = _usable_share(cut, n)
    for limit in BRIDGE_STEPS:  # too fragmented to estimate: split at longer steps only
        if share >= 0.5:
            break
        wider = np.flatnonzero(ratio >= limit)
        if (more := _usable_share(wider, n)) > share:
            cut, share = wider, more
    gaps = tuple(
        Gap(
            int(i + 1),
            float(t[i]),
            float(t[i + 1]),
            max(int(round(ratio[i])) - 1, 0),
            "gap" if ratio[i] > 1 else "irregular",
        )
        for i in cut
    )
    bounds = [0, *(int(i + 1) for i in cut), n]
    segments = tuple((a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True))
    inside = np.delete(ratio, cut)
    jitter = float(np.max(np.abs(inside - 1.0))) if inside.size else 0.0
    return Segmentation(segments, gaps, period, jitter)


def off_period(t: NDArray) -> NDArray:
    """Which steps of the times ``t`` (finite, increasing, 2 or more) are not the typical
    one: outside ``1 +- GAP_RTOL`` times the median step (where a record is split first)."""
    dt = np.diff(t)
    return np.abs(dt / np.median(dt) - 1.0) >= GAP_RTOL


def _usable_share(cut: NDArray, n: int) -> float:
    """The share of ``n`` samples in segments of :data:`SEGMENT_USABLE` or more, split
    before each sample ``cut + 1``."""
    lengths = np.diff(np.r_[0, cut + 1, n])
    return float(lengths[lengths >= SEGMENT_USABLE].sum() / n)


def split_dropped(dropped: NDArray) -> Segmentation:
    """Segments of the samples left after dropping ``dropped`` (a mask over the original record).

    Parameters
    ----------
    dropped : ndarray of bool, shape (n_original,)

    Returns
    -------
    Segmentation
        Indices refer to the kept samples; each run of dropped ones is a ``"nan"`` gap.
    """
    kept_index = np.cumsum(~dropped) - 1  # index among kept samples of each original one
    starts = np.flatnonzero(dropped & ~np.r_[False, dropped[:-1]])
    stops = np.flatnonzero(dropped & ~np.r_[dropped[1:], False]) + 1
    n_kept = int(np.count_nonzero(~dropped))
    gaps, bounds = [], [0]
    for a, b in zip(starts, stops, strict=True):
        at = int(kept_index[a - 1] + 1) if a > 0 else 0
        if 0 < at < n_kept:
            gaps.append(Gap(at, float(a - 1), float(b), int(b - a), "nan"))
            bounds.append(at)
    bounds.append(n_kept)
    segments = tuple((a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a)
    return Segmentation(segments, tuple(gaps))
