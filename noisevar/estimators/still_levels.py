"""Other still levels: near-still regimes, each measured on the R to use's own residual.

A record can rest at more than one level: a lower-back IMU sitting and standing, a board
set down upside down (docs/algorithms.md §E1 Regimes, *Several still levels*). The floor's
test leaves such a regime out of the still set (the R to use is the lowest level, the
sensor's own noise); this module measures each one with the same method, for the verdict
to say so (``NoiseDiagnostics.other_still``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from noisevar.diagnostics import NoiseDiagnostics
from noisevar.diagnostics.regimes import STILL_RATIO, StillLevel
from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate


def own_tails(diag: NoiseDiagnostics, est: VarianceEstimate) -> NoiseDiagnostics:
    """``diag`` with the kurtosis of ``est``'s own residual (the method's reading on a
    stretch), for its interval: the record's, read through its motion, is not the
    stretch's.

    Notes
    -----
    docs/algorithms.md §E1 *Several still levels*: GENEActiv z's 378-sample still stretch
    (128 residuals, kurtosis 38) was widened by the record's kurtosis, 1033, to 0.25
    degrees of freedom: "13.69x (ci95 1.50-25035646563412.54x)".
    """
    return diag if est.kurtosis is None else replace(diag, kurtosis=est.kurtosis)


#: At most this many near-still regimes are measured (the longest first), so at most
#: this many more passes of the method over at most the record's samples.
MOST_LEVELS = 3


def other_still_levels(
    diag: NoiseDiagnostics,
    still: VarianceEstimate,
    measure: Callable[[list[tuple[int, int]]], VarianceEstimate],
) -> tuple[StillLevel, ...]:
    """The near-still regimes' levels over the R to use, those above it.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics (its regimes).
    still : VarianceEstimate
        The R to use: the method on the still regimes.
    measure : callable
        ``measure(ranges)``: the same method and parameters on those sample ranges, its
        interval widened as the R to use's is.

    Returns
    -------
    tuple of StillLevel
        In order of length, longest first.

    Notes
    -----
    Each regime loses one profile block at either end (its edge blocks can hold some
    of the motion beside it). A level is kept when its interval lies above the R to use
    (a level of its own, not the floor read through another residual) and it is at most
    :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times the R to use's upper bound
    (taps or handling inside the stretch, which the diagnostics' robust levels do not
    see, make it motion). Levels are ratios to the R to use, so they hold in any units.
    """
    prof = diag.level_profile
    edge = int(prof.stop[0] - prof.start[0]) if prof.start.size else 0
    spans = [(r.start + edge, r.stop - edge) for r in prof.regimes if r.near_still]
    spans = sorted((s for s in spans if s[1] > s[0]), key=lambda s: s[0] - s[1])
    out = []
    for a, b in spans[:MOST_LEVELS]:
        try:
            est = measure([(a, b)])
        except NoisevarError:
            continue
        # a level of its own (its interval above the R to use), and not motion: at most
        # STILL_RATIO times the R to use's upper bound, as a still regime is on its floor's
        if not still.variance < est.ci95[0] or est.variance > STILL_RATIO * still.ci95[1]:
            continue
        lo, hi = (c / still.variance for c in est.ci95)
        out.append(StillLevel(a, b, est.variance / still.variance, lo, hi))
    return tuple(out)
