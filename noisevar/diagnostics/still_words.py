"""What a quoted still level is: its colour, and whether its stretches are still at all.

Still stretches whose noise departs from white as the whole record's does, lag by lag,
are the same signal at a lower level (a met mast's calm stretches: no wind is still),
not the sensor at rest: their level is an upper bound on the sensor's noise
(docs/algorithms.md §E2 *Calm is not still*).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy import special

from noisevar._distributions import chi2_sf
from noisevar.diagnostics.verdict_parts import (
    departure_cause,
    still_oscillation,
    upper_bound_words,
)
from noisevar.diagnostics.whiteness import WHITE_ALPHA

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics
    from noisevar.diagnostics.whiteness import WhitenessTest

#: A whiteness test failed at a p-value above this, with no colour named, is a weak finding.
WEAK_P = 0.01
#: The standard normal's two-sided 95 % point: the whiteness tests' bands over it are sds.
_Z95 = float(special.ndtri(0.975))


def farthest(w: WhitenessTest) -> int:
    """The index of the lag whose autocorrelation departs most from white noise's."""
    return int(np.argmax(np.abs((w.acf - w.expected) / w.band)))


def lag_excess(w: WhitenessTest, k: int) -> str:
    """The residual's lag-``k + 1`` autocorrelation beyond white noise's.

    Notes
    -----
    An excess over white noise's own (-2/3 at lag 1 through the residual filter), so it may
    pass 1: written without "beyond white noise's" it read as an autocorrelation of +1.02
    (the IERS's UT1-UTC, real_audit7).
    """
    return f"lag-{k + 1} autocorrelation {w.acf[k] - w.expected[k]:+.2f} beyond white noise's"


def calm_not_still(diag: NoiseDiagnostics) -> bool:
    """Whether the still stretches are calm stretches of the signal, not the sensor at rest.

    Both whiteness tests fail, and the still stretches' departure from white noise is the
    whole record's, lag by lag: a chi-square of the two departures' difference over the
    sum of both tests' variances, widened by Bartlett's factor for correlated residuals,
    at :data:`~noisevar.diagnostics.whiteness.WHITE_ALPHA`.

    Notes
    -----
    A sensor at rest on a moving record departs otherwise (motion's correlation is not a
    low-pass's or a sensor's own); a met mast's calm stretches depart as the record does
    (lag-1 +0.57 against +0.55, 20 lags within the bands: the same wind, quieter). The
    still stretches are part of the record: the variance of the difference is overstated,
    so the test leans to "the same"; it needs their own test to fail first.
    """
    w, a = diag.still_whiteness, diag.whiteness
    if w is None or not w.tested or w.white or a.white:
        return False
    k = min(w.acf.size, a.acf.size)
    ds, da = w.acf[:k] - w.expected[:k], a.acf[:k] - a.expected[:k]
    widen = (1 + 2 * np.sum(a.acf[:k] ** 2)) / (1 + 2 * np.sum(a.expected[:k] ** 2))
    var = (w.band[:k] ** 2 + a.band[:k] ** 2) / _Z95**2 * max(float(widen), 1.0)
    return chi2_sf(float(np.sum((ds - da) ** 2 / var)), float(k)) >= WHITE_ALPHA


def still_named(diag: NoiseDiagnostics) -> str:
    """How a sentence on motion names the still level it quotes: the sensor's noise, or
    the level of the quietest stretches when they are calm, not still."""
    if calm_not_still(diag):
        return "the level of its quietest stretches"
    return "the sensor noise measured in its still stretches"


def calm_words(diag: NoiseDiagnostics) -> str:
    """What a calm (not still) level is (:func:`calm_not_still`)."""
    w, a = diag.still_whiteness, diag.whiteness
    assert w is not None
    return (
        "an upper bound on the sensor's noise, not its level at rest: the quietest "
        f"stretches' noise is correlated as the whole record's (lag-1 {w.lag1:+.2f} against "
        f"{a.lag1:+.2f} beyond white noise's), the same signal at a lower level; a second "
        "sensor beside it (Two sensors) or a record at rest gives the sensor's own noise"
    )


def still_colour(diag: NoiseDiagnostics) -> str:
    """What the still stretches' own whiteness adds to a still level ('' when white).

    Noise that is not white in the still stretches (low-passed by the sensor, or slow
    sway left in them) has no one white level: high-pass estimators of different bandwidth
    disagree on it, so the still level is its white part, not the variance per sample.
    Still stretches too short to test are said to be untested. The clause names the lag
    that departs most (it quoted lag 1's +0.00 where lag 6 failed), and says nothing when
    the whole record, still stretches in, tests white and theirs fails only weakly (p of
    :data:`WEAK_P` or more: two tests of white noise give that 1 time in 50 or more; the
    ADS-B altitude of benchmarks/real_audit9.py, p = 0.99 and 0.03). Stretches that
    oscillate, or are calm rather than still (:func:`calm_not_still`), give an upper bound.
    """
    w = diag.still_whiteness
    if (o := still_oscillation(diag)) is not None:
        return f"; this level is {upper_bound_words(o)}"
    if calm_not_still(diag):
        return f"; this level is {calm_words(diag)}"
    if w is None and diag.level_varies:  # still stretches too short for the test
        return (
            "; the still stretches are too short to test whether their noise is white, so "
            "this level is untested: if the sensor low-passes its noise it is only the white "
            "part (record the sensor still for longer)"
        )
    if w is None or w.white or (diag.white and w.p_value >= WEAK_P):
        return ""
    k = farthest(w)
    return (
        f"; but even there the noise is not white ({lag_excess(w, k)}: "
        f"{departure_cause(w, k)}), so this is its "
        "white part and depends on the bandwidth: model the coloured part (see the noise model)"
    )
