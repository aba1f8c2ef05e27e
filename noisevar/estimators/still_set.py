"""Whether a record has a still R to use: the one rule for ``regimes="still"`` (issue 26).

Apart from :mod:`noisevar.estimators.regimes` (which runs :func:`noisevar.estimate`) so that
the pipeline, which writes the verdict, can follow the same rule.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from noisevar.diagnostics.regimes import ABOVE, HELD, SAME, STILL_RATIO, QuietLevel
from noisevar.diagnostics.verdict import under_half_a_step

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics
    from noisevar.estimators.results import VarianceEstimate

#: Fewest samples a piece of still stretch needs, still on both block grids and with the
#: samples around jumps cut out, to be estimated again by R's method (its spans need room;
#: shorter pieces say little). Fewer in every piece: the record has no still R to use.
STILL_MIN = 64

#: What a still fit that cannot be made asks for instead, on every surface.
USE_ALL = "use regimes='all' (CLI --regimes all; dashboard: untick the still regimes only)"


def still_gap(
    diag: NoiseDiagnostics | None, variance: float, still: VarianceEstimate | None
) -> str | None:
    """Why a record has no still R to use: the one rule for ``regimes="still"``.

    Parameters
    ----------
    diag : NoiseDiagnostics or None
        The record's diagnostics.
    variance : float
        The record's R (a level that varies under half a grid step is quantisation).
    still : VarianceEstimate or None
        R's method on the still stretches (the estimate's ``.still``).

    Returns
    -------
    str or None
        None when there is an R to use: ``still``, or the whole record when it is one
        still regime (its level does not vary, or varies only within a grid step). Else
        the message that ``regimes.variance_for`` raises, the CLI prints and the verdict
        quotes: no regimes found, no quiet stretch, still stretches too short for R's
        method (fewer than :data:`STILL_MIN` samples in every piece), or held values (the
        quiet level's source :data:`HELD`: under the stored digits, or on a grid far more
        often than noise of their level holds one, ``still_quiet.held_on_grid``).

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). The verdict, ``.still``,
    ``regimes.variance_for`` and ``regimes.longest_still_stretch`` all follow it, so a
    record never gets a still level on one page and the whole record's R as "the R to
    use" on another.
    """
    kind, total, share = _gap(diag, variance, still)
    if kind in ("have", "one", SAME):
        return None
    if kind == "unknown":
        return f"regimes='still': the record's regimes could not be found; {USE_ALL}"
    if kind in (HELD, ABOVE) and diag is not None and diag.quiet is not None:
        return f"regimes='still': {diag.quiet.reason}, so there is no still R to use; {USE_ALL}"
    if kind == "none":
        return (
            "regimes='still': the record has no still stretch (its level varies throughout "
            f"and no stretch of it is quiet); record the sensor still for a while, or {USE_ALL}"
        )
    return (
        f"regimes='still': the still stretches total {total} samples ({share:.0%} "
        f"of the record), in pieces shorter than the {STILL_MIN} samples R's method needs "
        "(still on both block grids, away from jumps), so there is no still R to use; "
        f"record the sensor still for longer, or {USE_ALL}"
    )


def smoothed_gap(diag: NoiseDiagnostics | None) -> str | None:
    """Why the still R is no R to use although it is measured: the noise where the record is
    still is smoother than a sensor's own low-pass leaves it (None: it is not).

    Returns
    -------
    str or None
        The message :func:`still_refusal` gives, on every surface that hands out a still R.

    Notes
    -----
    docs/algorithms.md §E2 *Smoothed outputs*: ``NoiseDiagnostics.still_smoothed``. The
    level is neither the sensor's noise (not in the record) nor the output's variance per
    sample, so its interval, the residual's sampling error, covers neither.
    """
    w = None if diag is None else diag.still_smoothed
    if w is None:
        return None
    return (
        "regimes='still': where the record is still its noise is smoother than a sensor's own "
        f"low-pass leaves it (lag-1 autocorrelation {w.acf[0]:+.2f}, at most {w.ar1_limit:+.2f} "
        "through a first-order low-pass): a filter's smoothed output, or slow motion; its "
        "still level is not the sensor's noise and its interval does not cover it, so there "
        "is no still R to use; take R from the raw measurements or the solver's own variance"
    )


def still_refusal(
    diag: NoiseDiagnostics | None, variance: float, still: VarianceEstimate | None
) -> str | None:
    """Why ``regimes="still"`` gives no R: :func:`still_gap`, else, for a still R measured
    apart (``still``), :func:`smoothed_gap`. Where R is the still R (one still regime, the
    still stretches at R's level, a level within a grid step) R is quoted with its own
    assumption ``unsmoothed``, as the verdict does.

    Notes
    -----
    The rule every surface that hands out a still R follows (``regimes.why_no_still``,
    the row's still cells); the verdict reads :func:`still_gap` alone and says a smoothed
    level in its own words (``verdict_parts.not_at_rest``).
    """
    return still_gap(diag, variance, still) or (None if still is None else smoothed_gap(diag))


def still_note(
    diag: NoiseDiagnostics | None, variance: float, still: VarianceEstimate | None
) -> str | None:
    """Why a result row's still-R cells are empty, in a few words (None when they are not).

    Parameters
    ----------
    diag, variance, still
        As :func:`still_gap`.

    Returns
    -------
    str or None
        The row's ``still_note``: no diagnostics, one still regime (the record's R is its
        still R), no still stretch, still stretches too short, or a smoothed output's
        (:func:`smoothed_gap`: the still R measured, not one to use); None when ``still``
        is given and is one to use.

    Notes
    -----
    The same cases as :func:`still_gap` (one rule), phrased for a table cell.
    """
    kind, total, share = _gap(diag, variance, still)
    w = None if diag is None else diag.still_smoothed
    if kind == "have" and w is not None:
        level = f" (measured {still.variance:.3g}, not the sensor's)" if still else ""
        return (
            f"no still R to use{level}: smoothed output (still lag-1 {w.acf[0]:+.2f} over "
            f"{w.ar1_limit:+.2f}); take R from the raw measurements or the solver's variance"
        )
    return {
        "have": None,
        "unknown": "no still R: the record's regimes could not be found",
        "one": "no separate still R: the record is one still regime (its R is the still R)",
        "same": "no separate still R: the still stretches read the whole record's level "
        "(its R is the still R)",
        "none": "no still stretch: the level varies throughout",
        "held": "no still R: the still stretches hold values under the stored digits"
        if diag is None or diag.lsb is None
        else "no still R: the still stretches are held values on the grid (padding, a stale "
        "sensor), not noise",
        "above": "no still R: the still stretches read above the whole record",
        "short": f"no still R: still stretches too short ({total} samples, {share:.0%} of "
        f"the record, each piece under {STILL_MIN})",
    }[kind]


def _gap(
    diag: NoiseDiagnostics | None, variance: float, still: VarianceEstimate | None
) -> tuple[str, int, float]:
    """The case of :func:`still_gap`: ``"have"`` (a still R), ``"unknown"`` (no
    diagnostics), ``"one"`` (one still regime), ``"same"`` (still stretches at R's level:
    :func:`same_level`), ``"held"``, ``"above"``, ``"none"`` (no quiet stretch) or
    ``"short"``; with the quiet samples and their share of the record."""
    if still is not None:
        return "have", 0, 0.0
    if diag is None:
        return "unknown", 0, 0.0
    if diag.quiet is not None and diag.quiet.source in (HELD, ABOVE, SAME):
        return diag.quiet.source, 0, 0.0
    if not has_still_apart(diag, variance) or under_half_a_step(diag, variance):
        return "one", 0, 0.0
    prof = diag.level_profile
    if not prof.any_quiet:
        return "none", 0, 0.0
    return "short", round(prof.quiet_share * diag.n), prof.quiet_share


def has_still_apart(diag: NoiseDiagnostics, variance: float) -> bool:
    """Whether the record's still stretches are apart from the rest: R's method runs on them.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics.
    variance : float
        The record's R.

    Returns
    -------
    bool
        False when R is under half a grid step's error variance (``under_half_a_step``
        on ``diag.lsb``, the grid a trend moves and keeps: the levels follow the signal's
        offset within a step, §E3). Else True when the
        level varies (a regime that is not still; not when no block is quiet on the
        record's grid and the reversed grid finds one quiet level), or when the record is
        one regime of robust level but its R is more than
        :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times the quiet level
        (``quiet_variance``) and the still stretches leave part of the record out (motion the
        block medians hardly see: heavy-tailed, or cut out around level jumps); or when
        the profile has still stretches beside stretches too fast to measure, R above the
        quiet level's interval and no lone glitch outside them (:func:`_unmeasured_apart`),
        whatever R's ratio.

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). Whether the regimes split on the block
    medians can hang on one marginal change point that dropping two samples flips (a
    Pololu accelerometer: PELT's gain 54-60 over the block phases against a penalty of
    55). The second test keeps the R to use from jumping between the still stretches'
    R and a whole-record R many times larger: the whole record's R is the R to use only
    when it is within about ``STILL_RATIO`` of the quiet level, so wherever either test
    flips the R to use moves by at most about that factor.
    """
    if under_half_a_step(diag, variance):  # a level within a grid step is quantisation
        return False
    if diag.level_varies:
        return not one_level_reversed(diag, variance)
    prof = diag.level_profile
    if _unmeasured_apart(diag, variance):
        return True
    return _run_apart(prof.left_out_ratio(), variance, prof.quiet_variance)


def _unmeasured_apart(diag: NoiseDiagnostics, variance: float) -> bool:
    """Stretches too fast to measure (``LevelProfile.unmeasured``) beside still stretches,
    R measurably above the quiet level, and no lone glitch to hold the excess: R's
    residuals hold motion no block reads, whatever R's ratio (docs/algorithms.md §E1).
    Glitches inside the unmeasured stretches are part of that motion.

    Where lone glitches hold R (UCR InternalBleeding16: R 7.5x its core, two outlying
    samples of a labelled anomaly, beside runs of level jumps), they, not the unmeasured
    stretches, are R's excess, said as outlying samples.
    """
    prof = diag.level_profile
    moving = prof.unmeasured
    held = any(not any(a <= g.index < b for a, b in moving) for g in diag.glitches)
    return bool(moving and prof.still_stretches and not held and variance > prof.quiet_bounds[1])


def _run_apart(left_out_ratio: float, variance: float, quiet_variance: float) -> bool:
    """A run of left-out blocks over :data:`STILL_RATIO` times the quiet level, and R over
    that many times it: motion apart from a record of one regime."""
    return bool(left_out_ratio > STILL_RATIO and variance > STILL_RATIO * quiet_variance)


def one_level_reversed(diag: NoiseDiagnostics, variance: float) -> bool:
    """The record's own grid finds no quiet block and the reversed record's grid finds it
    one level with nothing apart (every regime still, and no run of left-out blocks
    apart as :func:`has_still_apart` asks of a record of one level).

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). PELT's split can hang on the grid's phase:
    KITTI's GPS east velocity is one still level on both grids, and with 2 samples
    dropped two regimes on the record's grid, neither with a quiet block, while the
    reversed grid still finds one quiet level. Nothing is quiet apart from the rest on
    either grid, so the record's R is the R to use, as with no sample dropped.
    """
    back = diag.level_profile.back_grid
    if back is None or back.profile is None or diag.level_profile.quiet.any():
        return False
    if not all(r.still for r in back.profile.regimes):
        return False
    return not _run_apart(back.left_out_ratio, variance, back.quiet_variance)


def kept_still(
    diag: NoiseDiagnostics, variance: float, still: VarianceEstimate | None
) -> tuple[VarianceEstimate | None, NoiseDiagnostics]:
    """``still`` and ``diag``, or no still R when the record's R leaves none apart.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics (its ``other_still`` levels over ``still``).
    variance : float
        The record's R as quoted (the coloured-noise one when it replaced the first).
    still : VarianceEstimate or None
        R's method on the still stretches, decided on the first R.

    Returns
    -------
    (VarianceEstimate or None, NoiseDiagnostics)
        ``(None, diag without other still levels)`` when :func:`has_still_apart` is False
        for ``variance`` (R under half a grid step: the still stretches are no level of
        their own), its quiet level absent (:data:`ABOVE`) when ``still`` is no quieter
        than it (:func:`not_quieter`); else both as given.

    Notes
    -----
    The still R is measured beside the coloured-noise pass, on the first R; whether it
    is apart is decided again on the R the record quotes, so that the one rule
    (:func:`still_gap`) reads one R (docs/algorithms.md §E1 *The still set*).
    """
    if still is None:
        return still, diag
    if not has_still_apart(diag, variance):
        return None, replace(diag, other_still=())
    level = no_quieter_level(diag, still, variance)
    if level is None:
        return still, diag
    return None, replace(diag, quiet=level, other_still=())


def no_quieter_level(
    diag: NoiseDiagnostics, still: VarianceEstimate, variance: float
) -> QuietLevel | None:
    """The quiet level when the still R is no quieter than R (:func:`not_quieter`), else None.

    Absent, source :data:`SAME` when the still stretches read R's level
    (:func:`same_level`: R, the R to use, is the quiet level), else :data:`ABOVE` (no
    still R to use); with :func:`not_quieter`'s reason.
    """
    reason = not_quieter(still, variance)
    if reason is None:
        return None
    source = SAME if same_level(still, variance) else ABOVE
    return QuietLevel(None, None, None, diag.level_profile.quiet_share, source, reason)


def same_level(still: VarianceEstimate, variance: float) -> bool:
    """Whether the still stretches read R's level: the still R at or above R (at most
    :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times it) with R inside its 95 %
    interval.

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). A still R just under R is the R to use, and
    one just over it with R inside its interval is no quieter level: which side it falls
    on hangs on the block grid's phase where the still stretches are most of the record
    (gtsam's legged robot gyr_x: 0.95x R, then 1.02x with 2 samples dropped; KITTI's GPS
    east velocity: one regime, then two, reading 1.13x R). Were the R to use then none,
    it would come and go with the phase; it is R itself, inside the still R's interval
    on both sides of the edge.
    """
    return (
        still.variance >= variance
        and still.variance <= STILL_RATIO * variance
        and (still.ci95[0] <= variance)
    )


def not_quieter(still: VarianceEstimate, variance: float) -> str | None:
    """Why the still R is no quieter level than R (``variance``), or None when it may be.

    Not below R, and either told apart over
    :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times it (its 95 % interval's low
    end there: the value alone crossed it as the block grid's phase moved the stretches,
    UT1-UTC's still R 1.9x R, ci95 1.1-3.8x, then 2.8x with 2 samples dropped) or with R
    inside its 95 % interval: the still regimes are the record's quietest on the
    diagnostics' residual, and R's own method reads them no quieter (a ship's temperature
    in 1-degree steps with spikes: 107 against R 42; sktime's solar generation, 38 % night
    zeros: 1.77e-4 against R 7.33e-5, its interval 0.68x-77x R, on one block grid's phase
    only). A still R above R and told apart from it, by at most twice, may be: a dropout
    or held stretch pulls R down (heartpy's PPG, 840 samples of 0: still R 1.05x R, the
    noise's own).
    """
    if still.variance < variance:
        return None
    over = still.ci95[0] >= STILL_RATIO * variance  # told apart over twice R
    if not (over or still.ci95[0] <= variance):
        return None
    how = (
        f"over {STILL_RATIO:g} times"
        if over
        else f"above, with it inside their 95 % interval ({still.ci95[0]:.3g} to "
        f"{still.ci95[1]:.3g}),"
    )
    return (
        f"the still stretches read {still.variance:.3g} on R's residual, {how} the whole "
        f"record's R {variance:.3g}, so they are no quieter level than R"
    )
