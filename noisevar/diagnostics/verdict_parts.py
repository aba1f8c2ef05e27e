"""Parts of the verdict that stand alone: the other still levels' clause and fields, and
the sentence on differenced data (:mod:`noisevar.diagnostics.verdict` joins them)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from noisevar.diagnostics.regimes import StillLevel
    from noisevar.diagnostics.results import NoiseDiagnostics


def still_level_fields(level: StillLevel, n: int) -> dict[str, str]:
    """A near-still regime's stretch, share, level and interval, as every page says them.

    Parameters
    ----------
    level : StillLevel
        One of ``NoiseDiagnostics.other_still``.
    n : int
        Samples in the record.

    Returns
    -------
    dict
        ``stretch`` ("samples 300-5400"), ``share`` of the record ("76%"), ``level`` and
        its ``ci95`` as multiples of the R to use ("2.20x", "1.95-2.48x").
    """
    return {
        "stretch": f"samples {level.start}-{level.stop}",
        "share": f"{(level.stop - level.start) / max(n, 1):.0%}",
        "level": f"{level.ratio:.2f}x",
        "ci95": f"{level.lo:.2f}-{level.hi:.2f}x",
    }


def other_still_clause(diag: NoiseDiagnostics) -> str:
    """What the other still levels add to the verdict ('' when there is none).

    Each near-still regime whose level, measured as the R to use is, lies above it
    (docs/algorithms.md §E1 *Several still levels*): the R to use stays the floor.
    """
    if not diag.other_still:
        return ""
    said = "; ".join(
        f"{f['stretch']} ({f['share']} of the record) at {f['level']} (ci95 {f['ci95']})"
        for f in (still_level_fields(x, diag.n) for x in diag.other_still)
    )
    return (
        f". Other still stretches rest at a higher level on the same residual: {said}: "
        "another posture, or slow sway; the still level above is the floor, the sensor's "
        "own noise, and a filter that runs through those stretches without modelling that "
        "motion needs their level"
    )


def differenced_verdict(corr: NDArray, r: str) -> str:
    """The verdict on differenced data: MA(1) (a difference) or MA(q) (a derivative filter)."""
    if corr.size == 1:
        return (
            "the data look differenced (a frequency from phase, a velocity from positions): "
            f"the noise's lag-1 correlation is {corr[0]:+.2f}, as the difference of white "
            f"noise gives (-0.5); {r} is the variance per sample, but successive errors are "
            "correlated: filter the undifferenced quantity (its R is about half this) or "
            "model MA(1) measurement noise"
        )
    lag = int(np.argmin(corr)) + 1
    return (
        "the data look differenced (a velocity from positions by a central difference or a "
        f"derivative filter): the noise's correlation at lag {lag} is {corr[lag - 1]:+.2f} "
        f"(np.gradient's central difference gives -0.5 at lag 2); {r} is the variance per "
        "sample, but errors up to "
        f"{corr.size} samples apart are correlated: filter the undifferenced quantity or "
        f"model MA({corr.size}) measurement noise"
    )
