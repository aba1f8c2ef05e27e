"""Remarks beyond the verdict: interval reliability, quantisation, gaps, jitter."""

from __future__ import annotations

from typing import TYPE_CHECKING

from noisevar.diagnostics.segments import GAP_RTOL, JITTER_NOTE
from noisevar.diagnostics.verdict_parts import still_oscillation
from noisevar.format import eng

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics


def make_notes(diag: NoiseDiagnostics) -> tuple[str, ...]:
    """Remarks beyond the verdict: interval reliability, quantisation, gaps, jitter, and a
    still level that is an upper bound (its stretches oscillate: docs/algorithms.md §E2
    *Vibration*)."""
    notes = []
    if (bound := upper_bound_note(diag)) is not None:
        notes.append(bound)
    if diag.fourth_moment_unreliable:
        notes.append(
            f"the tails are very heavy (tail index {diag.tail_index:.1f}, below 4: the noise "
            "may have no finite fourth moment): the interval of the variance is unreliable"
        )
    if diag.lsb is not None:
        notes.append(
            f"the samples sit on a grid of step {eng(diag.lsb)}: the error variance is "
            f"σ² + lsb²/12, with lsb²/12 = {eng(diag.lsb**2 / 12.0)}"
        )
    if diag.gaps:
        kinds = {g.kind for g in diag.gaps}
        what = "gaps" if kinds == {"gap"} or kinds == {"nan"} else "gaps or irregular steps"
        what = what if len(diag.gaps) > 1 else what.replace("gaps", "gap").replace("steps", "step")
        notes.append(
            f"{len(diag.gaps)} {what} (first at sample {diag.gaps[0].index}): the record was "
            "estimated per uniform segment and pooled, not spliced"
        )
    if diag.jitter >= GAP_RTOL:
        notes.append(
            f"irregular sampling: steps differ from the period by up to {diag.jitter:.0%} "
            "(samples dropped, or stamped late); too little of the record lies between such "
            "steps to split at each, so the samples are taken in order as if uniform: right "
            "for the noise when the signal changes little from one sample to the next"
        )
    elif diag.jitter > JITTER_NOTE:
        notes.append(f"sampling jitter up to {diag.jitter:.1%} of the period: treated as uniform")
    return tuple(notes)


def upper_bound_note(diag: NoiseDiagnostics) -> str | None:
    """The note of a still level that is an upper bound (None: it is not one).

    Its stretches carry an oscillation (:func:`~.verdict_parts.still_oscillation`): said on
    the estimate and on its still R (``regimes='still'``), which users put in their filter.
    """
    o = still_oscillation(diag)
    if o is None or diag.quiet_variance is None:
        return None
    return (
        f"the still stretches carry an oscillation at {o.frequency:.2f} of the sample rate "
        "(a slower phase of a gait, or a machine running): their level, the R to use of "
        "regimes='still', is an upper bound on the sensor's noise, not its level at rest"
    )


def still_caveat(diag: NoiseDiagnostics, n_used: int | None = None) -> str | None:
    """What the still R itself (``regimes='still'``, ``est.still``) says of its level and
    interval: an upper bound (:func:`upper_bound_note`), a smoothed output's, or untested.

    Notes
    -----
    docs/algorithms.md §E2 *Smoothed outputs*. A smoothed output's still level
    (``NoiseDiagnostics.smoothed``) is neither the sensor's noise nor the output's variance
    per sample: its interval is the residual's sampling error and covers neither. Still
    stretches too short to test (no ``still_whiteness``) leave the still R resting on two
    untested assumptions, white and unsmoothed noise, said with the whole record's lag-1
    reading where that is already smoother than a low-pass leaves noise (RTKLIB's rover2),
    and with the samples it rests on (``n_used``, the still R's; a Permian gamma ray's
    R to use rests on 65 of 12,041, real_audit18).
    """
    if (bound := upper_bound_note(diag)) is not None:
        return bound
    if (w := diag.still_smoothed) is not None:
        return (
            "not an R to use: where the record is still its noise is smoother than a "
            f"sensor's own low-pass leaves it (lag-1 autocorrelation {w.acf[0]:+.2f}, at most "
            f"{w.ar1_limit:+.2f}): this level is not the sensor's noise, and its 95 % interval "
            "(the residual's sampling error) does not cover it; take R from the raw "
            "measurements or the solver's own variance"
        )
    if diag.still_whiteness is not None or not diag.level_varies:
        return None
    whole = diag.whiteness
    said = (
        f"; the whole record's noise is smoother than that (lag-1 {whole.acf[0]:+.2f}, at most "
        f"{whole.ar1_limit:+.2f}): if it is a filter's output this level is not the sensor's"
        if whole.smoother_than_ar1
        else ""
    )
    rests = "" if n_used is None else f" ({n_used} samples, {n_used / diag.n:.2%} of the record)"
    return (
        f"the still stretches{rests} are too short to test their noise: this still R assumes "
        f"it white and no smoother than a sensor's own low-pass leaves it, untested{said}"
    )
