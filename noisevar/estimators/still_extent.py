"""A short rest's extent to the sample, where the block grids cut it too short (issue 26 item 2).

Both block grids find a rest of 64-95 samples inside motion still, but each cuts it into
whole blocks, one or two as its phase falls, so the stretch R's method could read came
and went as leading samples were dropped. Here its ends are read off the samples
themselves: the runs of samples whose residual windows read the quiet level, which do
not depend on where a grid starts (docs/algorithms.md §E1 *A still stretch inside the
record*).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf
from noisevar.diagnostics.plan import DIAG_ORDER, DIAG_SPAN
from noisevar.diagnostics.profile import QUIET_ALPHA, LevelProfile
from noisevar.diagnostics.quiet_set import QUIET_ROUNDS, pooled
from noisevar.estimators.results import chi2_interval
from noisevar.estimators.still_set import STILL_MIN
from noisevar.numeric.fir import centred_fir, residual_sequence


def to_the_sample(
    pieces: list[tuple[int, int]],
    prof: LevelProfile,
    back: LevelProfile,
    read: Callable[[int, int], NDArray] | None,
    n: int,
) -> list[tuple[int, int]]:
    """The rests around ``pieces``, their ends read to the sample.

    Parameters
    ----------
    pieces : list of (int, int)
        Stretches still on both block grids (each too short for R's method).
    prof, back : LevelProfile
        The record's level profile (its block size and dof per sample) and the reversed
        record's: the bound is over their quiet level (:func:`quiet_floor`).
    read : callable or None
        ``read(a, b)``: samples ``a .. b`` of the record (None: nothing is read).
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        In order, each run of samples that a window of one profile block of the
        diagnostics' residual reading the quiet level covers (each residual at its centre
        sample) and that holds a piece; runs of at least :data:`STILL_MIN` samples.

    Notes
    -----
    docs/algorithms.md §E1 (*A still stretch inside the record*). A window passes when its
    mean square is under the quiet set's bound (the χ² quantile the profile's blocks are
    tested at, on a block's dof, over the quiet level). The union of the passing windows
    is a run of samples fixed by the record's content: whichever grid phase seeded it,
    the same rest, so dropping leading samples or reversing the record leaves it where it
    is (a reversed record's residual is the record's mirrored, the filter being
    symmetric). Only the bound moves with the grids (their quiet levels).
    """
    level, dof = quiet_floor(prof, back)
    if not pieces or read is None or not level > 0.0:
        return []
    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    h = d.size // 2
    count = prof.stop - prof.start if prof.count is None else prof.count
    w = int(prof.stop[0] - prof.start[0])
    nu = w * float(prof.dof[0] / count[0])
    factor = chi2_ppf(1.0 - QUIET_ALPHA / prof.start.size, nu) / nu
    out: list[tuple[int, int]] = []
    for a, b in pieces:
        lo, hi = max(0, a - 2 * w - h), min(n, b + 2 * w + h)
        runs = _own_level_runs(read(lo, hi), d, w, factor, level, dof, (a - lo, b - lo))
        out += [(lo + c, lo + e) for c, e in runs]
    return [(a, b) for a, b in sorted(set(out)) if b - a >= STILL_MIN]


def _own_level_runs(
    x: NDArray,
    d: NDArray,
    w: int,
    factor: float,
    level: float,
    dof: float,
    piece: tuple[int, int],
) -> list[tuple[int, int]]:
    """The runs of ``x`` under ``factor`` times a level that hold ``piece`` (``x``'s own
    indices): the level first ``level`` (on ``dof``), then the runs' own mean square half
    a window in from their ends (as the grids' quiet level is their quiet blocks' pooled
    mean square) within ``level``'s 95 % interval, in rounds until the runs no longer
    change.

    The grids' quiet level, one block or two of a short rest, moves with the grid's phase
    and the runs' ends with it (a 71-sample rest read 64 samples at 0.0118 and none of 64
    at 0.0114, with 2 dropped); the runs' own level is the samples', which no phase moves,
    and where the grids' levels on two phases agree within their intervals both settle on
    it (docs/algorithms.md §E1 *A still stretch at the minimum length*). Read at their
    ends too it rose round by round into slow motion beside them (MIDC UAT's accumulated
    energy: a run of 140 samples grew to 152 and read 32x), hence half a window in.
    """
    h = d.size // 2
    if x.size < w + 2 * h:
        return []
    e2 = centred_fir(np.asarray(x, dtype=float), d, square=True) / float(np.dot(d, d))
    low, high = chi2_interval(level, dof)
    runs: list[tuple[int, int]] = []
    for _ in range(QUIET_ROUNDS):
        found = [(c, e) for c, e in _passing_runs(e2, h, w, factor * level)
                 if c < piece[1] and piece[0] < e]  # fmt: skip
        if found == runs or not found:
            return found
        runs = found
        inner = [e2[c - h + w // 2 : e - h - w // 2] for c, e in runs]  # away from their ends
        own = float(np.mean(np.concatenate(inner))) if sum(r.size for r in inner) else level
        level = min(max(own, low), high)
    return runs


def quiet_floor(prof: LevelProfile, back: LevelProfile) -> tuple[float, float]:
    """The quiet level of the grids whose level varies: their quiet blocks pooled by dof
    (as :attr:`~noisevar.diagnostics.profile.LevelProfile.quiet_variance`), and its dof
    (their sum); ``(0, 0)`` when neither's level varies.

    A grid whose blocks are all quiet finds the record one level, the motion's too (as
    :func:`~noisevar.estimators.still_grids.grown_to_either`: a 75-sample rest's bound was
    16x its noise); reversal swaps the two grids and leaves the pooled level as it is.
    """
    grids = [p for p in (prof, back) if p.quiet.any() and not p.quiet.all()]
    nu = [float(np.sum(p.dof[p.quiet])) for p in grids]
    if not sum(nu) > 0.0:
        return 0.0, 0.0
    levels = [pooled(p.variance, p.dof, p.quiet) for p in grids]
    return float(np.dot(levels, nu)) / sum(nu), float(sum(nu))


def _passing_runs(e2: NDArray, h: int, w: int, bound: float) -> list[tuple[int, int]]:
    """Runs of samples (the record piece's own indices) under a window of ``w`` of the
    squared residuals ``e2`` whose mean square is at most ``bound``, each residual at its
    centre sample (residual ``i`` is that of sample ``i + h``)."""
    c = np.r_[0.0, np.cumsum(e2)]
    ok = (c[w:] - c[:-w]) / w <= bound  # window j: residuals j .. j + w - 1
    cover = np.zeros(e2.size + 1, dtype=int)
    np.add.at(cover, np.flatnonzero(ok), 1)
    np.add.at(cover, np.flatnonzero(ok) + w, -1)
    covered = np.cumsum(cover[:-1]) > 0
    edges = np.flatnonzero(np.diff(np.r_[0, covered.view(np.int8), 0]))
    # residual i is that of sample i + h of x (it reads samples i .. i + 2h)
    return [(int(i) + h, int(j) + h) for i, j in zip(edges[::2], edges[1::2], strict=True)]
