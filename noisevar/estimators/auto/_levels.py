"""``auto``'s local noise levels on two block grids, one from each end (docs/algorithms.md §F5.4).

A threshold read off one grid anchored at the record's start moves when the record is
reversed: the blocks fall elsewhere, and a motion transient was an outlier one way and a
jump the other (issue 26). Here a sample is above the local level only when it is above on
both grids, the second anchored at the record's end, where the reversed record's own grid
lies; so the reversed record sees the same thresholds. A window of a longer record (a
chunk) places its second grid on the record's, given the samples after it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.numeric.blocks import (
    abs_block_maxima,
    block_counts,
    block_medians,
    flagged_per_block,
    kept_block_sums,
    medians_needed,
)
from noisevar.numeric.fir import ROUNDING_ULPS
from noisevar.numeric.steps import above_on_two_grids, above_on_two_grids_at


@dataclass(frozen=True)
class Grids:
    """Blocks of ``block`` samples over a window of ``m``: from its start and the record's end.

    The second grid is the first grid of the reversed window after its first ``q``
    samples (``q = 0`` for a whole record; a chunk's window ends ``after`` samples before
    the record's end, ``q = -after mod block``).
    """

    m: int
    block: int
    nb: int
    q: int
    nbb: int

    @classmethod
    def make(cls, m: int, block: int, after: int = 0) -> Grids:
        q = (-after) % block
        if m - q < block:
            q = 0
        return cls(m, block, max(1, m // block), q, max(1, (m - q) // block))

    def back(self, x: NDArray) -> NDArray:
        """``x`` reversed, from the second grid's first sample (a view)."""
        return x[::-1][self.q :]

    def back_index(self, idx: NDArray) -> NDArray:
        """Indices of the window on the reversed axis of :meth:`back` (negative: before it)."""
        return self.m - 1 - idx - self.q


def rounding_floors(z: NDArray, g: Grids) -> tuple[NDArray, NDArray]:
    """The least level of each block on both grids: the rounding of its samples.

    ``(ROUNDING_ULPS · ε · max |z|)²`` over each block of ``z`` (the window the squares
    are of), ``ε`` float64's machine epsilon (:data:`~noisevar.numeric.fir.ROUNDING_ULPS`):
    against a level of 0 (a held stretch) the rounding that an offset, a scale or a trend
    leaves in a residual was above or not by chance, and R moved (issue 26).
    """
    unit = ROUNDING_ULPS * np.finfo(float).eps
    fwd = abs_block_maxima(z, g.block, g.nb)
    bwd = abs_block_maxima(z, g.block, g.nbb, g.q, back=True)
    return (unit * fwd) ** 2, (unit * bwd) ** 2


def medians(sq: NDArray, g: Grids) -> tuple[NDArray, NDArray]:
    """Block medians of the squares on both grids, every square of each block.

    Not every fourth one: which fourth a block takes moves with the samples dropped
    before it, and where a burst of motion fills part of a block its median sits in the
    burst, so a subsample's median moved by 1.6x with one leading sample dropped, the
    burst was excluded from the level or not, and R moved 19x (issue 26, the Pololu
    record's acc_y). All of them: the block's content alone sets its median.
    """
    back = block_medians(g.back(sq), g.block, g.nbb, 1)
    return block_medians(sq, g.block, g.nb, 1), back


def above_medians(
    sq: NDArray, g: Grids, scale: float, floors: tuple[NDArray, NDArray] | None = None
) -> NDArray:
    """``sq`` above ``scale`` times its block's median (at least its floor) on both grids.

    :func:`above_own` with the levels ``max(median, floor) scale`` of :func:`medians`; a
    block's median is taken only where a square within its reach may exceed it
    (:func:`~noisevar.numeric.blocks.medians_needed`): elsewhere no square is above
    whatever the median, and the level is left infinite. The same flags.
    """
    floor_f, floor_b = (None, None) if floors is None else floors
    need = medians_needed(sq, g.block, g.nb, scale)
    fwd = _scaled_medians(sq, g.block, g.nb, scale, floor_f, need)
    need = medians_needed(sq, g.block, g.nbb, scale, g.q, back=True)
    bwd = _scaled_medians(g.back(sq), g.block, g.nbb, scale, floor_b, need)
    return above_own(sq, fwd, bwd, g)


def _scaled_medians(
    x: NDArray, block: int, nb: int, scale: float, floor: NDArray | None, need: NDArray | None
) -> NDArray:
    """``max(median, floor) scale`` of the blocks ``need`` (None: all), ``inf`` elsewhere."""
    if need is None:
        need = np.ones(nb, dtype=bool)
    out = np.full(nb, np.inf)
    if need.any():
        rows = x[: nb * block].reshape(nb, block)[need]  # those blocks' values, in order
        med = block_medians(rows.reshape(-1), block, rows.shape[0], 1)
        out[need] = (med if floor is None else np.maximum(med, floor[need])) * scale
    return out


def above_own(x: NDArray, fwd: NDArray, bwd: NDArray, g: Grids) -> NDArray:
    """``x`` above its own block's level on both grids."""
    n, nb, block = x.size, g.nb, g.block
    hit = np.empty(n, dtype=bool)
    np.greater(
        x[: nb * block].reshape(nb, block), fwd[:, None], out=hit[: nb * block].reshape(nb, block)
    )
    np.greater(x[nb * block :], fwd[-1], out=hit[nb * block :])
    idx = np.flatnonzero(hit)
    if idx.size:
        j = g.back_index(idx)
        own = np.clip(j // block, 0, g.nbb - 1)
        hit[idx[x[idx] <= bwd[own]]] = False
    return hit


def kept_levels(
    sq: NDArray,
    idx: NDArray | None,
    g: Grids,
    scale: float,
    floors: tuple[NDArray, NDArray] | None = None,
) -> tuple[NDArray, NDArray]:
    """``scale`` times each block's mean square off the samples ``idx``, on both grids.

    ``floors`` (:func:`rounding_floors`): each block's least level, before ``scale``.
    Each level is read off its block's own samples, as the medians are: the samples past
    the last block take its level but do not make it, so that dropping leading samples
    moves no level of the grid from the record's end (a lone step's threshold moved 3 %
    with the record's first edge residuals and R x2.3, issue 26).
    """
    out = []
    back = None if idx is None else g.back_index(idx)
    least = (None, None) if floors is None else floors
    for x, i, nb, f in ((sq, idx, g.nb, least[0]), (g.back(sq), back, g.nbb, least[1])):
        x = x[: nb * g.block]  # the blocks' own samples: the rest takes the last level
        kept_n = block_counts(g.block, nb, x.size)
        if i is None or not i.size:
            kept_sum = kept_block_sums(x, np.zeros(0, dtype=int), g.block, nb)
        else:
            i = np.sort(i[(i >= 0) & (i < x.size)])
            kept_sum = kept_block_sums(x, i, g.block, nb)
            kept_n = kept_n - flagged_per_block(i, g.block, nb)
        level = kept_sum / np.maximum(kept_n, 1.0)
        out.append(scale * (level if f is None else np.maximum(level, f)))
    return out[0], out[1]


def bracketing(idx: NDArray, local: NDArray, block: int) -> NDArray:
    """The larger local level of the two block centres around each sample ``idx``."""
    nb = local.size
    if block % 2 == 0:  # the level of each half block, looked up (the same maxima)
        # past the last block (the rest of the record): its second half's, the last level
        return half_levels(local)[np.minimum(idx // (block // 2), 2 * nb - 1)]
    own = np.minimum(idx // block, nb - 1)
    side = np.where(idx - own * block < block // 2, own - 1, own + 1)
    side = np.clip(side, 0, nb - 1)  # the rest of the record: the last block's level
    return np.maximum(local[own], local[side])


def half_levels(local: NDArray) -> NDArray:
    """The bracketing level of each half block (an even block): its own and its neighbour's."""
    nb = local.size
    j = np.arange(nb)
    halves = np.empty(2 * nb)
    np.maximum(local, local[np.maximum(j - 1, 0)], out=halves[0::2])
    np.maximum(local, local[np.minimum(j + 1, nb - 1)], out=halves[1::2])
    return halves


def above_local(x: NDArray, local: NDArray, block: int) -> NDArray:
    """``x`` above the larger local level of the two block centres around each sample.

    Block ``j``'s level holds at its centre ``(j + 1/2) block``; a sample is
    compared with the larger of the levels of the two centres around it (the
    rest of the record after the last block with the last level), so that near a
    change of noise level the threshold is the louder side's (§F5.4). One
    blockwise comparison with the block's own level (a lower bound) finds the few
    candidates; only those are compared with the bracketing level.
    """
    n, nb = x.size, local.size
    hit = np.empty(n, dtype=bool)
    np.greater(
        x[: nb * block].reshape(nb, block), local[:, None], out=hit[: nb * block].reshape(nb, block)
    )
    np.greater(x[nb * block :], local[-1], out=hit[nb * block :])
    idx = np.flatnonzero(hit)
    if idx.size and nb > 1:
        hit[idx[x[idx] <= bracketing(idx, local, block)]] = False
    return hit


def above_both(x: NDArray, fwd: NDArray, bwd: NDArray, g: Grids) -> NDArray:
    """``x`` above the bracketing level (:func:`above_local`) on both grids."""
    hit = above_local(x, fwd, g.block)
    idx = np.flatnonzero(hit)
    if idx.size:
        j = g.back_index(idx)
        level = np.where(j >= 0, bracketing(np.maximum(j, 0), bwd, g.block), bwd[0])
        hit[idx[x[idx] <= level]] = False
    return hit


def above_both_at(values: NDArray, idx: NDArray, fwd: NDArray, bwd: NDArray, g: Grids) -> NDArray:
    """:func:`above_both` of samples that are ``values`` at ``idx``, read at ``idx`` only.

    The same comparisons: the blockwise test of :func:`above_local` is implied by its
    bracketing one (the bracketing level is never below the block's own).
    """
    hit = values > bracketing(idx, fwd, g.block)
    j = g.back_index(idx)
    level = np.where(j >= 0, bracketing(np.maximum(j, 0), bwd, g.block), bwd[0])
    return hit & (values > level)


#: The median of χ²₁ over its mean: a Gaussian statistic's squares' block median reads this
#: much of their mean.
CHI2_1_MEDIAN = 0.4549364231195724
#: A block's own level of the step statistic raises its threshold only beyond this many
#: times white noise's (the spread of a block's median: :meth:`Above.raised`).
OWN_MARGIN = 2.0
#: Levels are raised block by block only on a grid of at least this many blocks
#: (:meth:`Above.raised`).
OWN_MIN_BLOCKS = 8
#: On fewer blocks, every level is raised (and only lone steps are jumps) beyond this many
#: times white noise's level, read off the whole window (:meth:`Above._raised_whole`).
OWN_WHOLE_MARGIN = 3.0
#: ... read off at least this many values of the statistic (the verdict's checks need ~100).
OWN_WHOLE_VALUES = 100
#: A value of the statistic under this fraction of its level is float rounding, not noise.
ROUNDING_RATIO = 1e-12


def _raised(
    x: NDArray, idx: NDArray, level: NDArray, block: int, nb: int, expected: float
) -> NDArray:
    """``level`` raised in the blocks of ``idx`` and beside them (:meth:`Above.raised`)."""
    own = np.minimum(idx // block, nb - 1)
    need = np.zeros(nb, dtype=bool)
    need[own] = True
    need[np.maximum(own - 1, 0)] = True
    need[np.minimum(own + 1, nb - 1)] = True
    need &= level > 0
    if not need.any():
        return level
    rows = x[: nb * block].reshape(nb, block)[need]
    med = block_medians(rows.reshape(-1), block, rows.shape[0], 1)
    r = med / CHI2_1_MEDIAN / (expected * level[need])
    if not (r > OWN_MARGIN).any():
        return level
    out = level.copy()
    out[need] *= np.maximum(1.0, r / OWN_MARGIN)
    return out


@dataclass(frozen=True)
class Above:
    """``x`` above ``κ²`` times its local level on both grids (:func:`above_both`).

    Called on a window's samples; :meth:`at` reads only some of them (a sparse probe).
    """

    fwd: NDArray
    bwd: NDArray
    g: Grids
    #: Each grid's least levels (the rounding of the samples, :func:`rounding_floors`, times
    #: the levels' scale): a block at its floor is held (None: not known).
    floors: tuple[NDArray, NDArray] | None = None
    #: Raised over the whole window (a grid of few blocks: :meth:`_raised_whole`).
    whole: bool = False

    def __call__(self, x: NDArray) -> NDArray:
        return above_both(x, self.fwd, self.bwd, self.g)

    def at(self, values: NDArray, idx: NDArray) -> NDArray:
        """``self(x)[idx]`` for ``x`` that is ``values`` at ``idx``."""
        return above_both_at(values, idx, self.fwd, self.bwd, self.g)

    def sides(self, x: NDArray) -> NDArray | None:
        """``self(x)`` at ``k`` and at ``k - 1`` alike, at ``k >= 1`` (None: not compiled).

        :func:`~noisevar.numeric.steps.above_on_two_grids`: one compiled pass over ``x`` with
        each half block's level looked up (an even block, ``x`` the window's size).
        """
        g = self.g
        if g.block % 2 or x.size != g.m:
            return None
        return above_on_two_grids(
            x, self.floor, self._halves(), float(self.bwd[0]), g.block // 2, g.q
        )

    def sides_at(self, values: NDArray, idx: NDArray) -> NDArray | None:
        """:meth:`sides` of samples that are ``values`` at ``idx`` (0 elsewhere), read there."""
        g = self.g
        if g.block % 2:
            return None
        halves, first = self._halves(), float(self.bwd[0])
        return above_on_two_grids_at(values, idx, halves, first, g.block // 2, g.m - g.q)

    def raised(self, x: NDArray, idx: NDArray, expected: float) -> Above:
        """The levels raised where ``x``'s own block level is above ``expected`` times them.

        Parameters
        ----------
        x : ndarray, shape (m,)
            The window's values (squares of a statistic of the noise; a Gaussian one's
            median is :data:`CHI2_1_MEDIAN` of its mean).
        idx : ndarray of int
            The samples whose levels matter: their blocks and the blocks beside them are
            read (a level elsewhere only raises a threshold nothing there exceeds).
        expected : float
            ``x``'s mean over the level for white noise.

        Returns
        -------
        Above
            Each read block's level times ``max(1, r / OWN_MARGIN)``, ``r`` its own
            median-based mean of ``x`` over ``expected`` times the level (``self`` when
            none is raised: the same numbers).

        Notes
        -----
        A block's median of 256 correlated values is known to about half of itself,
        so white noise sits at ``r`` = 1 and below :data:`OWN_MARGIN`; low-passed noise
        reads ``r`` = 3 to 18 (lag-one correlation 0.5 to 0.98). Read on both grids. On
        fewer than :data:`OWN_MIN_BLOCKS` blocks the levels stay: there the fast-signal rule's
        window (two blocks) is most of the record, and a raise read off one or two blocks'
        medians moved a GPS track's flags across it with 3 samples dropped (R x27).
        """
        g = self.g
        if min(g.nb, g.nbb) < OWN_MIN_BLOCKS:
            return self._raised_whole(x, expected)
        fwd = _raised(x, idx, self.fwd, g.block, g.nb, expected)
        j = g.back_index(idx)
        bwd = _raised(g.back(x), j[j >= 0], self.bwd, g.block, g.nbb, expected)
        if fwd is self.fwd and bwd is self.bwd:
            return self
        return Above(fwd, bwd, g, self.floors)

    def _raised_whole(self, x: NDArray, expected: float) -> Above:
        """:meth:`raised` on a grid of few blocks: every level times ``1 + (r - m) / 2`` where
        ``r``, read off the whole window (the median of ``x`` over its own level, the larger
        of both grids', held blocks left out), exceeds ``m`` (:data:`OWN_WHOLE_MARGIN`; 1 at
        the margin: continuous); lone steps are then jumps, the other flags judged by the
        flags before the raise (:class:`~noisevar.numeric.steps.StepFlags`).

        White noise under a signal reads ``r`` up to 2.3 (``steps-ramps``, 1,000 samples),
        AR(1) noise of lag-one correlation 0.7-0.9 reads 4.2-9, a GPS track 40-1,300 (its
        walk): at raised levels its fast signal would flag under a fifth of the record and
        be believed (docs/algorithms.md §F5.3).
        """
        g = self.g
        k = np.flatnonzero(x > 0.0)  # D3 is 0 where it is not defined
        fi = np.minimum(k // g.block, g.nb - 1)
        bi = np.clip(g.back_index(k) // g.block, 0, g.nbb - 1)
        lf, lb = self.fwd[fi], self.bwd[bi]
        ok = (lf > 0) & (lb > 0) & np.isfinite(lf) & np.isfinite(lb)
        if self.floors is not None:  # held blocks: their D3 is 0, or rounding under an offset
            ok &= (lf > self.floors[0][fi]) & (lb > self.floors[1][bi])
        # D3 at float rounding is no level: a scale moves which such values are exactly 0
        # (a gyroscope in deg/s: one value more, R 0.015 % off rad/s's)
        ok &= (x[k] > ROUNDING_RATIO * lf) & (x[k] > ROUNDING_RATIO * lb)
        if ok.sum() < OWN_WHOLE_VALUES:
            return self
        r = max(np.median(x[k][ok] / lf[ok]), np.median(x[k][ok] / lb[ok]))
        r /= CHI2_1_MEDIAN * expected
        if not r > OWN_WHOLE_MARGIN:
            return self
        f = 1.0 + (r - OWN_WHOLE_MARGIN) / OWN_MARGIN  # continuous: 1 at the margin
        return Above(self.fwd * f, self.bwd * f, self.g, self.floors, whole=True)

    def _halves(self) -> tuple[NDArray, NDArray]:
        return half_levels(self.fwd), half_levels(self.bwd)

    @property
    def floor(self) -> float:
        """No value at or below this is above: every threshold is at least both grids' least
        level (a NaN level is never exceeded; -inf when every level is NaN)."""
        least = [float(np.fmin.reduce(v)) if v.size else -np.inf for v in (self.fwd, self.bwd)]
        top = max(least)
        return -np.inf if np.isnan(top) else top
