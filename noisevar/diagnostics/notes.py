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
