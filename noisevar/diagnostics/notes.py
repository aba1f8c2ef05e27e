"""Remarks beyond the verdict: interval reliability, quantisation, gaps, jitter."""

from __future__ import annotations

from typing import TYPE_CHECKING

from noisevar.diagnostics.segments import GAP_RTOL, JITTER_NOTE
from noisevar.format import eng

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics


def make_notes(diag: NoiseDiagnostics) -> tuple[str, ...]:
    """Remarks beyond the verdict: interval reliability, quantisation, gaps, jitter."""
    notes = []
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
