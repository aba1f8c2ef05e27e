"""The plain sentence that says what a record's noise is and which R to use."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from noisevar.diagnostics.assumptions import SHORT_RECORD, unchecked
from noisevar.diagnostics.power_law import WHITE, describe
from noisevar.diagnostics.quantisation import half_a_step
from noisevar.diagnostics.regimes import STILL_RATIO, read_above
from noisevar.diagnostics.tails import light_noise
from noisevar.diagnostics.verdict_parts import (
    BOTH,
    CHANGES,
    GLITCHES_DOMINATE,
    MOSTLY_MOTION,
    OSC_TO_DO,
    OUTLIERS_SOME,
    STILL_WALK,
    WEAK_P,
    colour_in_still,
    departure_cause,
    differenced_verdict,
    found_oscillation,
    glitches_lead,
    glitches_verdict,
    level_changes,
    moved_clause,
    none_quieter,
    not_at_rest,
    oscillation_words,
    rounding_clause,
    still_oscillation,
    to_use_words,
    upper_bound_words,
    walk_verdict,
    weak_colour,
)
from noisevar.format import eng

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics
    from noisevar.diagnostics.whiteness import WhitenessTest

#: R over the core variance above which the outlying samples hold most of R (over half).
OUTLIERS_HOLD = 2.0
#: At most this share of outlying samples is "a few" (a start-up value, a logging error).
OUTLIERS_FEW = 0.01
def _g(x: float) -> str:
    return eng(x)  # the one formatter of shown numbers: pages, CLI and this text agree


def under_half_a_step(diag: NoiseDiagnostics, variance: float) -> bool:
    """On a grid, with an error variance under that of noise of half a step (§E3).

    There, a level that varies along the record follows the signal's offset within a
    step: it is quantisation, not a changing sensor.
    """
    return diag.lsb is not None and variance < half_a_step(diag.lsb)


def make_verdict(
    diag: NoiseDiagnostics,
    variance: float,
    core: float | None = None,
    outliers: float = 0.0,
    still: float | None = None,
    still_gap: str | None = None,
) -> str:
    """One sentence, worst finding first.

    When a few outlying samples hold most of R of a record of one level and the sentence
    would not quote the core variance, the sentence describes the record without them (a
    start-up value held 99.8 % of R, which it called the noise's white part) and says them
    second (:func:`outliers_hold`): their share of R is a point ratio that the record's
    edge moves (PX4 airspeed less 0-4 samples: 99.8, 42, 14, 65, 70 %), its colour is not
    (issue 26).

    Parameters
    ----------
    diag : NoiseDiagnostics
    variance : float
        The estimate's variance (R for a plain Kalman filter).
    core : float, optional
        Variance of the bulk (for a robust filter).
    outliers : float
        Share of samples outside the bulk.
    still : float, optional
        The estimate on the still regimes alone (the same method and residual as
        ``variance``); default the quiet level (``diag.quiet_variance``), or where there
        is none the level profile's, which ``still_gap`` then calls indicative.
    still_gap : str, optional
        Why there is no still R to use
        (:func:`noisevar.estimators.still_set.still_gap`): a quoted still level is then the
        level profile's, and the verdict says it is indicative only.

    Returns
    -------
    str
    """
    holders = outliers_hold(variance, core, outliers, OUTLIERS_SOME, GLITCHES_DOMINATE)
    if unchecked(diag.n, diag):  # R over 10x its core is evidence at any length
        return short_verdict(diag.n, variance, diag) + holders
    if glitches_lead(diag, variance, core, outliers):
        assert core is not None  # glitches_lead said so
        quiet = still if still is not None else diag.quiet_variance
        share, said = still_share(diag), still_said(diag, still_gap)
        level = f"; its quiet stretches ({share:.0%}) give {_g(quiet)}{said}" if quiet else ""
        held = (_share(outliers), _held(1 - core / variance))
        return glitches_verdict(_r(variance), _g(core), held, level)
    said = _sentence(diag, variance, core, outliers, still, still_gap)
    lead = outliers_hold(variance, core, outliers)
    # on one level only: where the level varies, motion is the finding (a cloudy day's
    # transients are its outlying samples, and the core variance is no noise level either);
    # off a grid's half step (there the rounding's flips are the outlying samples)
    rounding = under_half_a_step(diag, variance)
    if still is not None or diag.level_varies:  # named after the finding, when nearly all of R
        return said + ("" if "outlying" in said else holders)
    if rounding or not lead or "core variance" in said:  # some (1-5 %) holding R: said last
        return said if rounding or lead or "core variance" in said else said + holders
    assert core is not None  # outliers_hold said so
    return _sentence(diag, core, core, 0.0, None, still_gap, "the core variance") + lead


def outliers_hold(
    variance: float,
    core: float | None,
    outliers: float,
    few: float = OUTLIERS_FEW,
    hold: float = OUTLIERS_HOLD,
) -> str:
    """The verdict's last clause when a few outlying samples hold most of R ('' when not).

    R counts them as noise (a plain Kalman filter sees them); when they hold over half of
    it, R is mostly those few samples, and the core variance (without them), which the
    verdict's finding is read on, is the R to use when they are not the sensor's noise (a
    start-up value, a logging error), or a robust filter's.
    """
    if core is None or not 0 < outliers <= few or not variance > hold * core:
        return ""
    return (
        f"; {_share(outliers)} of the samples are outlying and hold "
        f"{_share(1 - core / variance)} of {_r(variance)}, which counts them as noise, as a "
        "plain Kalman filter needs: the core variance leaves them out "
        f"({_g(core)}), the R to use if they are not the sensor's noise (a start-up value, a "
        "logging error, spoofed or garbled values), or a robust filter's"
    )


def _sentence(
    diag: NoiseDiagnostics,
    variance: float,
    core: float | None,
    outliers: float,
    still: float | None,
    still_gap: str | None,
    label: str = "R",
) -> str:
    """:func:`make_verdict`'s sentence, worst finding first (its parameters; ``label``
    names ``variance`` in the text)."""
    r = _r(variance, label)
    quiet = still if still is not None else diag.quiet_variance
    if quiet is None:  # none on R's residual: the level profile's, said to be indicative
        quiet = diag.level_profile.quiet_variance
    said = still_said(diag, still_gap)
    not_white = _not_white(diag, r, quiet, variance, still_gap, still is not None)
    if not_white is not None:
        return not_white
    if diag.level_varies and under_half_a_step(diag, variance):
        return (
            f"white noise under half a step on a grid of step {_g(diag.lsb)}: its level "
            "follows the signal's offset within a step, which is quantisation, not a changing "
            f"sensor; {r} includes the rounding error"
        )
    # a still R apart from R (estimators.still_set.has_still_apart): the level varies,
    # though the block medians may not split it into regimes
    if diag.level_varies or still is not None:
        return level_changes(still_share(diag), r, quiet, said, moved_clause(diag))
    if diag.glitches and not diag.tails_beyond_glitches:
        return glitch_verdict(diag, r, core)
    if diag.heavy_tailed and under_half_a_step(diag, variance):
        # held regimes on the grid are one still level (regimes._floor): the rounding's
        # tails, not the sensor's
        return (
            f"white noise under half a step on a grid of step {_g(diag.lsb)}: its tails "
            f"(kurtosis {diag.kurtosis:.1f}) are the rounding error's, which follows the "
            f"signal's offset within a step, not the sensor's; {r} includes the rounding error"
        )
    if diag.heavy_tailed:
        bulk = f"; a robust filter should use the core variance {_g(core)}" if core else ""
        return (
            f"white heavy-tailed noise (kurtosis {diag.kurtosis:.1f}, {_share(outliers)} "
            "outliers): "
            f"{r} includes the tails, as a plain Kalman filter needs{bulk}"
        )
    if diag.lsb is not None and diag.lsb**2 / 12.0 > 0.01 * variance:
        return (
            f"white noise on a grid of step {_g(diag.lsb)}: {r} includes the rounding error "
            f"lsb²/12 = {_g(diag.lsb**2 / 12.0)}, and is a good Kalman R"
        )
    return f"white {_gaussian_or_light(diag)}: {r} is a good Kalman R"


def _gaussian_or_light(diag: NoiseDiagnostics) -> str:
    """ "Gaussian noise", or what the noise is when its tails are measurably lighter (the
    quantum random numbers of benchmarks/real_audit6.py, uniform: "Gaussian" was untrue)."""
    if light_noise(diag.n, diag.kurtosis):
        return (
            f"noise with tails lighter than Gaussian (kurtosis {diag.kurtosis:.1f}; uniform "
            "noise has 1.8)"
        )
    return "Gaussian noise"


def still_share(diag: NoiseDiagnostics) -> float:
    """The share of the record the quoted still level was measured on: the quiet blocks',
    or, with none, the still regimes' a still R was measured on (``diag.quiet.share``)."""
    return diag.quiet.share if diag.quiet is not None else diag.level_profile.quiet_share


def _r(variance: float, label: str = "R") -> str:
    return f"{label} = {_g(variance)} (std {_g(float(np.sqrt(max(variance, 0.0))))})"


def short_verdict(n: int, variance: float, diag: NoiseDiagnostics | None = None) -> str:
    """The verdict of a record too short for some checks (:func:`unchecked`): R is a first
    value, what could not be checked, what the checks made found.

    Notes
    -----
    docs/algorithms.md §E2 (*Short records*). ``diag`` None: no check could be made.
    """
    gaps = unchecked(n, diag)
    todo = ", ".join(gaps[:-1]) + (" or " if len(gaps) > 1 else "") + gaps[-1]
    if diag is None or n < SHORT_RECORD:
        lead, cure = f"only {n} samples", "measure a longer record"
        few = f"samples to check {todo} (every check needs about {SHORT_RECORD})"
    else:  # long, but few residuals clear of level jumps (a staircase of close steps)
        lead = f"{n} samples, but only {diag.whiteness.n} residuals clear of the level jumps"
        few, cure = f"to check {todo}", "record longer stretches between the jumps"
    return (
        f"{lead}: {_r(variance)} is a first value, to be read with its wide interval; too "
        f"few {few}{_weak_findings(diag)}; {cure} before trusting it in a filter"
    )


def _weak_findings(diag: NoiseDiagnostics | None) -> str:
    """What the checks a short record allows found (a clause, or nothing)."""
    if diag is None:
        return ""
    w = diag.whiteness
    if diag.increments.tested and not diag.identifiable:
        return "; its first difference looks white (a random walk): R may be the walk's, not noise"
    if not w.tested:
        return ""
    lags = f"lags 1-{w.acf.size}"
    if not w.white:
        return f"; over {lags} it is not white (lag-1 {w.lag1:+.2f}), so R may be off"
    return f"; over {lags} it looks white (a weak test on so few samples)"


def verdict_of(diag: NoiseDiagnostics | None, n: int, variance: float) -> str:
    """An estimate's verdict: its diagnostics', or, without them, a short record's
    (:func:`short_verdict`: a record too short to diagnose); else empty."""
    if diag is not None:
        return str(diag.verdict)
    return short_verdict(n, variance) if n < SHORT_RECORD else ""


def glitch_verdict(diag: NoiseDiagnostics, r: str, core: float | None) -> str:
    """The verdict of white noise of one level with lone glitches (``diag.glitches``).

    They are noise, so in R (a plain Kalman filter sees them); the core variance leaves
    them out (docs/algorithms.md §E1 *Lone glitches*). One sample is not a level change.
    """
    g = diag.glitches
    it = "it" if len(g) == 1 else "them"
    bulk = f"; without {it} the core variance is {_g(core)}, for a robust filter" if core else ""
    return (
        f"white noise with {glitch_words(diag)}: {r} counts {it} as noise, as a plain "
        f"Kalman filter needs{bulk}"
    )


def glitch_words(diag: NoiseDiagnostics) -> str:
    """ "1 outlying sample, at sample 1500, 80σ" (up to three placed, the largest's size)."""
    g = diag.glitches
    top = max(x.sigmas for x in g)
    size = f"{top:.0f}σ" if top >= 10 else f"{top:.1f}σ"
    if len(g) == 1:
        return f"1 outlying sample, at sample {g[0].index}, {size}"
    at = [str(x.index) for x in g]
    where = (
        f"at samples {', '.join(at[:-1])} and {at[-1]}"
        if len(g) <= 3
        else f"the first at sample {at[0]}"
    )
    return f"{len(g)} outlying samples, {where}, up to {size}"


def _measurably_below(diag: NoiseDiagnostics, variance: float) -> bool:
    """Whether the quiet level is measurably below R (``variance``): its 95 %
    interval's top under R (the quiet level's on R's residual, else the level profile's
    on both grids). A point comparison flipped the verdict's first clause between "no
    stretch measurably quieter" and "mostly motion" when the two were a few % apart and
    two samples were dropped (issue 26)."""
    q = diag.quiet
    if q is not None and q.variance is not None and q.hi is not None:
        return bool(q.hi < variance)
    return bool(diag.level_profile.quiet_bounds[1] < variance)


def _not_white(
    diag: NoiseDiagnostics,
    r: str,
    quiet: float,
    variance: float,
    gap: str | None,
    still_apart: bool = False,
) -> str | None:
    """The verdict of a record whose noise is not a white level (None: it may be one).

    ``gap``: why there is no still R to use (:func:`indicative`), or None; ``still_apart``:
    there is a still R to use apart from R.

    In the order the evidence decides: the rounding (noise under half a grid step: its
    residual follows the signal), no noise to tell apart, no quiet stretch, no stretch
    quieter than R (an indicative level above it; not when R's method read the quiet half
    or more no quieter), mostly motion, differenced data, motion leaking through white
    still stretches, a still R to use (the level changes; its colour said, in the lead too
    where the still stretches are as coloured: :func:`.colour_in_still`), then colour.
    """
    prof = diag.level_profile
    said = still_said(diag, gap)
    rounding = diag.identifiable and not diag.short_correlated and not diag.white
    if rounding and under_half_a_step(diag, variance):
        return _rounding_first(diag, r, quiet, variance, said if still_apart else None)
    if not diag.identifiable:  # a track that stops: its still stretches, the R to use
        stood = None if not still_apart else (still_share(diag), _g(quiet), said)
        return walk_verdict(r, stood, not diag.still_a_walk and not_at_rest(diag) is None)
    # no quiet block, and no still R from the still regimes: no level to quote
    no_quiet = diag.level_varies and not prof.any_quiet and not still_apart
    if no_quiet and not under_half_a_step(diag, variance):  # (that is quantisation)
        return (
            f"{CHANGES}: no stretch of it is quiet, so the sensor noise cannot be measured "
            f"apart from the motion, and {r} over the whole record includes motion or signal "
            "(record the sensor still for a while)"
        )
    if (
        not still_apart
        and diag.level_varies
        and not (read_above(diag.quiet) and not diag.white and prof.quiet_share >= MOSTLY_MOTION)
        and not _measurably_below(diag, variance)
        and not under_half_a_step(diag, variance)
    ):
        return none_quieter(r, quiet, diag)
    # no quiet block (a grid's noise under half a step): no still level to quote
    if diag.level_varies and prof.any_quiet and prof.quiet_share < MOSTLY_MOTION and not diag.white:
        return (
            f"{CHANGES}: mostly motion or signal leaking through; {_measured(diag)} "
            f"in its still stretches ({still_share(diag):.0%} of it) is "
            f"{_g(quiet)} (std {_g(float(np.sqrt(quiet)))}), "
            f"against {_g(variance)} over the whole record{said}{_vibrates(diag)}"
        )
    if diag.short_correlated:
        return differenced_verdict(diag, r)
    if diag.motion_explains_colour:
        return (
            f"{CHANGES}: motion; {r} is an average over "
            f"still and moving stretches; the still stretches ({still_share(diag):.0%}) give "
            f"{_g(quiet)}, and their noise is white: the rest is motion leaking through the "
            f"smoother, not coloured noise{indicative(gap)}"
        )
    below = diag.level_varies and _measurably_below(diag, variance)
    both = still_apart and quiet < variance and colour_in_still(diag)  # both said, one order
    if both or still_apart and (variance > STILL_RATIO * quiet or below):
        # the R to use is the still R, well below R: the level change comes first, then the
        # still stretches' own colour (a coloured verdict would quote R, an average, as its
        # white part); a still R near R leaves the colour the finding (GPS 1PPS: 0.99x) unless
        # the still stretches are as coloured: then both lead, whatever the ratio (issue 26).
        # whether PELT split the record or not (Pololu acc less 3 samples), a still R apart says
        # the level changes; where it did, one measurably below R too (SURFRAD wind; GPS 1PPS)
        lead = BOTH if both else CHANGES  # the colour's clause may come and go, not the lead
        return level_changes(still_share(diag), r, quiet, said, moved_clause(diag), lead)
    if not diag.white:
        return _coloured(diag, r, quiet, still_apart)
    return None


def _measured(diag: NoiseDiagnostics) -> str:
    """What a still level is: the sensor noise, or a level only (its stretches not the
    sensor at rest: a walk, an oscillation, :func:`not_at_rest`)."""
    rest = diag.still_a_walk or still_oscillation(diag) or not_at_rest(diag)
    return "the level measured" if rest else "the sensor noise measured"


def _vibrates(diag: NoiseDiagnostics) -> str:
    """What the whole record's oscillation adds to a sentence on motion ('' when none, or
    when the still stretches' clause named it: :func:`still_oscillation`)."""
    o = found_oscillation(diag.whiteness)
    if o is None or still_oscillation(diag) is not None:
        return ""
    return f"; the whole record carries {oscillation_words(o)}: {OSC_TO_DO}"


def _rounding_first(
    diag: NoiseDiagnostics, r: str, quiet: float, variance: float, said: str | None
) -> str:
    """The verdict of noise under half a grid step that is not one white level.

    The rounding error then follows the signal's offset within a step (docs/algorithms.md
    §E3): a slow signal on a coarse grid gives a residual that is neither white nor of one
    level whatever the sensor does, so the whiteness and level tests read the rounding (the
    systole EDA class of benchmarks/real_audit6.py: "coloured ... model the coloured part").
    ``said``: a still R to use apart from R (its clause), else None.
    """
    stood = (
        f"; its still stretches ({still_share(diag):.0%}) give {_g(quiet)}, the R to use{said}"
        if said is not None
        else ""
    )
    level = " nor of one level" if diag.level_varies else ""
    return (
        f"noise under half a step on a grid of step {_g(diag.lsb)}: the rounding error "
        "follows the signal's offset within a step, so the residual is not white"
        f"{level}, and a colour or a motion cannot be told apart from quantisation; "
        f"{rounding_clause(r, diag.lsb, variance)}{stood}"
    )


def _coloured(diag: NoiseDiagnostics, r: str, quiet: float, still_near: bool) -> str:
    """The verdict of coloured noise; ``still_near``: a still R to use near R (within
    STILL_RATIO), quoted too.

    With no colour named by the power law and a whiteness test failed at a p-value of
    :data:`WEAK_P` or more, the finding is weak (white noise gives such a p-value 1 time
    in ``1/p``, 1 in 20 at most;
    Student-t noise read "coloured: lag-1 autocorrelation -0.00 beyond white noise's"): the
    sentence says so, with the lag that departs most.
    """
    # slopes that read white at every factor name no colour: the farthest lag does
    coloured = any(alpha != WHITE for _, alpha in diag.power_law)
    w, weak = diag.whiteness, weak_colour(diag)
    kind = (
        f"{describe(diag.power_law)} (power-law identification)" if coloured else _farthest_lag(w)
    )
    share = still_share(diag)
    named = found_oscillation(w) is not None
    still = (
        f"; its still stretches ({share:.0%}) give {_g(quiet)}, {to_use_words(diag, named)}"
        if still_near
        else ""
    )
    if (o := found_oscillation(w)) is not None:
        return (
            f"the noise is not white: it carries {oscillation_words(o)}; {r} leaves its line out "
            f"(on one segment; a spread band in part: see the notes): {OSC_TO_DO}{still}"
        )
    if weak:
        return (
            f"the noise may be coloured (a weak finding: whiteness test p = {w.p_value:.2g}, "
            f"as low as white noise gives 1 time in {1 / w.p_value:.0f}): {kind}, or signal "
            f"leaks through the smoother; {r} is its white part, and a good Kalman R if the "
            "noise is white: "
            f"check on a longer record (see the noise model){still}"
        )
    return (
        f"the noise is coloured: {kind}, or signal leaks through the smoother; {r} is "
        "its white part (or a little above): model the coloured part (see the noise "
        f"model), since a white R alone understates what a Kalman filter sees{still}"
    )


def _farthest_lag(w: WhitenessTest) -> str:
    """The lag whose autocorrelation departs most from white noise's, in its band.

    Named by the lag that departs, not lag 1 alone: Student-t noise failed the test at
    p = 0.007 by lags 2-6 and read "lag-1 autocorrelation -0.00 beyond white noise's".
    """
    return _lag_excess(w, _farthest(w))


def _farthest(w: WhitenessTest) -> int:
    """The index of the lag whose autocorrelation departs most from white noise's."""
    return int(np.argmax(np.abs((w.acf - w.expected) / w.band)))


def indicative(gap: str | None) -> str:
    """What a quoted still level says when there is no still R to use ('' when there is).

    ``gap``: :func:`noisevar.estimators.still_set.still_gap`'s message; the level quoted is
    then the level profile's quiet level, on another residual than R.
    """
    if not gap:
        return ""
    reason = gap.removeprefix("regimes='still': ")
    return (
        "; this still level is indicative only (the level profile's, on another residual "
        f"than R): {reason}"
    )


def still_said(diag: NoiseDiagnostics, gap: str | None) -> str:
    """What a quoted still level adds: its colour (:func:`still_colour`), and why it is
    indicative (:func:`indicative`); stretches too short for R's method are too short for
    the whiteness test too, which the gap's reason already says once."""
    untested = gap and diag.still_whiteness is None
    return ("" if untested else still_colour(diag)) + indicative(gap)


def _lag_excess(w: WhitenessTest, k: int) -> str:
    """The residual's lag-``k + 1`` autocorrelation beyond white noise's.

    Notes
    -----
    An excess over white noise's own (-2/3 at lag 1 through the residual filter), so it may
    pass 1: written without "beyond white noise's" it read as an autocorrelation of +1.02
    (the IERS's UT1-UTC, real_audit7).
    """
    return f"lag-{k + 1} autocorrelation {w.acf[k] - w.expected[k]:+.2f} beyond white noise's"


def still_colour(diag: NoiseDiagnostics) -> str:
    """What the still stretches' own whiteness adds to a still level ('' when white).

    Noise that is not white in the still stretches (low-passed by the sensor, or slow
    sway left in them) has no one white level: high-pass estimators of different bandwidth
    disagree on it, so the still level is its white part, not the variance per sample.
    Still stretches too short to test are said to be untested; still stretches that are a
    walk (:attr:`~.results.NoiseDiagnostics.still_a_walk`) to bound the noise only. The
    clause names the lag that departs most (it quoted lag 1's +0.00 where lag 6 failed),
    and says nothing when the whole record, still stretches in, tests white and theirs
    fails only weakly (p of
    :data:`WEAK_P` or more: two tests of white noise give that 1 time in 50 or more; the
    ADS-B altitude of benchmarks/real_audit9.py, p = 0.99 and 0.03).
    """
    w = diag.still_whiteness
    if diag.still_a_walk:
        return STILL_WALK
    if (o := still_oscillation(diag)) is not None:
        return f"; this level is {upper_bound_words(o)}"
    if (rest := not_at_rest(diag)) is not None:  # a smoothed output, a calm stretch
        return rest
    if w is None and diag.level_varies:  # still stretches too short for the test
        q = diag.quiet
        ci = "" if q is None or q.lo is None else f" (95 % {eng(q.lo)} to {eng(q.hi)} on them)"
        return (
            "; the still stretches are too short to test whether their noise is white, so "
            f"this level{ci} is untested: if the sensor low-passes its noise it is only the white "
            "part (record the sensor still for longer)"
        )
    if w is None or w.white or (diag.white and w.p_value >= WEAK_P):
        return ""
    k = _farthest(w)
    named = any(a != WHITE for _, a in diag.power_law) and colour_in_still(diag)  # GPS 1PPS
    law = f"; the whole record: {describe(diag.power_law)}, power-law identification"
    kind = law if named else ""
    return (
        f"; but even there the noise is not white ({_lag_excess(w, k)}: "
        f"{departure_cause(w, k)}), so this is its white part and depends on the bandwidth: "
        f"model the coloured part (see the noise model{kind})"
    )


def _held(x: float) -> str:
    """A share of R near all of it, not rounded up to 100 % ("over 99.9%")."""
    return "over 99.9%" if x > 0.999 else _share(x)


def _share(x: float) -> str:
    """A share as a percentage that does not round a few samples to 0.0%."""
    if x == 0:
        return "no"
    return f"{100 * x:.2g}%" if x < 1e-3 else f"{x:.1%}"
