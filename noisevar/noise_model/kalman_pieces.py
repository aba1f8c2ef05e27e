"""The Kalman fit between the level jumps the record's R leaves out (docs/algorithms.md §E6
*Between the jumps*).

:func:`noisevar.estimate` leaves the samples around a persistent level jump (or a far-off
glitch it cannot tell from a one-sample step) out of R: they are signal, not noise. A
Gaussian likelihood over the whole record takes them in full: one 300-sigma glitch moves the
fitted ``r`` several times over. :func:`fit_kalman` fits the same samples R measures: the
pieces between those jumps, each from its own diffuse start, their likelihoods summed (the
jump is a gap in the record, as a filter restarted after it would see).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.estimators.results import VarianceEstimate
from noisevar.noise_model._steady import FilterPass, filter_pass
from noisevar.numeric.blocks import runs_of


@dataclass(frozen=True)
class Pieces:
    """A record as the fit sees it: the spans ``[start, stop)`` its likelihood sums over."""

    n: int
    spans: tuple[tuple[int, int], ...]
    note: str = ""

    def take(self, z: NDArray) -> tuple[NDArray, ...]:
        """Each span of ``z``, centred on its first sample (numerics; the fit is shift-free)."""
        return tuple(z[a:b] - z[a] for a, b in self.spans)

    @property
    def size(self) -> int:
        """Samples the fit uses."""
        return sum(b - a for a, b in self.spans)

    @property
    def left_out(self) -> int:
        """Samples of the record the fit leaves out."""
        return self.n - self.size


def whole(n: int) -> Pieces:
    """The whole record of ``n`` samples as one span."""
    return Pieces(n, ((0, n),))


def between_jumps(n: int, est: VarianceEstimate | str, need: int) -> Pieces:
    """The spans between the samples the record's R leaves out around level jumps.

    Parameters
    ----------
    n : int
        Samples in the record.
    est : VarianceEstimate or str
        The record's answer (method auto); a string (no answer) gives the whole record.
    need : int
        Fewest samples a span must have to enter the fit (the model's minimum).

    Returns
    -------
    Pieces
        The whole record when R leaves nothing out, or when no span between the jumps has
        ``need`` samples (said in its note); else the spans of at least ``need`` samples.
    """
    jumps = getattr(est, "jumps", None)
    if jumps is None or jumps.size != n or not jumps.any():
        return whole(n)
    runs = [r for r in runs_of(~np.asarray(jumps, bool)) if r[1] - r[0] >= need]
    left = int(np.count_nonzero(jumps))
    if not runs:
        return Pieces(
            n,
            ((0, n),),
            f"the fit takes the whole record: between the level jumps R leaves out ({left} "
            f"samples) no piece has the {need} samples the model needs",
        )
    used = sum(b - a for a, b in runs)
    return Pieces(
        n,
        tuple(runs),
        f"fitted between the level jumps R leaves out, as R is: {n - used} samples left out "
        f"({left} around the jumps, {n - used - left} in pieces under {need} samples), "
        f"{len(runs)} piece(s), each from its own diffuse start",
    )


def pieces_pass(
    pieces: tuple[NDArray, ...], F: NDArray, h: NDArray, Q: NDArray, r: float, states: bool
) -> FilterPass:
    """:func:`~noisevar.noise_model._steady.filter_pass` on each piece, the passes joined
    (innovations, their variances and estimates in order; ``start`` the first piece's)."""
    fps = [filter_pass(p, F, h, Q, r, states=states) for p in pieces]
    if len(fps) == 1:
        return fps[0]
    return FilterPass(
        np.concatenate([f.innovations for f in fps]),
        np.concatenate([f.s for f in fps]),
        np.vstack([f.states for f in fps]),
        fps[0].start,
    )
