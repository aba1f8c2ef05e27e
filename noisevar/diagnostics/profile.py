"""The noise level along a record, and the level of its quietest consistent stretches."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_pdf, chi2_ppf
from noisevar.diagnostics.quiet_set import (
    QUIET_ROUNDS,
    gaussian_seed,
    leave_one_out_dof,
    pooled,
    quiet_set,
    still_if_quiet,
)
from noisevar.diagnostics.regimes import Regime, dispersion_shown, find_regimes, hints_a_change

#: At most this many blocks in a level profile (blocks grow with the record).
PROFILE_BLOCKS = 200
#: At least this many samples per block.
PROFILE_MIN_BLOCK = 32
#: A block joins the quiet set while its level is below the ``1 - QUIET_ALPHA / n_blocks``
#: quantile of the set's (a family-wise level over the blocks).
QUIET_ALPHA = 0.05
#: The quiet set's seed: still blocks whose mean square is at most this many times the
#: still blocks' median mean square.
SEED_FACTOR = 20.0
#: Fewest consecutive blocks left out of the quiet set that make a stretch of motion
#: (:meth:`LevelProfile.left_out_ratio`): one huge spike, spread by the smoother's span,
#: leaves out one block or two.
MOTION_RUN = 3
#: The median of χ²₁.
CHI2_1_MEDIAN = float(chi2_ppf(0.5, 1))
#: Degrees of freedom per sample of a block median of χ²₁ values, ``2 (2 f(m) m)²``.
MEDIAN_DOF = float(2.0 * (2.0 * chi2_pdf(CHI2_1_MEDIAN, 1) * CHI2_1_MEDIAN) ** 2)


@dataclass(frozen=True)
class BackGrid:
    """The reversed record's block grid, in the record's sample indices.

    Attributes
    ----------
    quiet : tuple of (int, int)
        Runs of its quiet blocks.
    spans : tuple of (int, int)
        Runs of all its blocks.
    quiet_variance : float
        Its quiet blocks' pooled level (0 when none is quiet).
    quiet_dof : float
        Its quiet blocks' summed dof, with its quiet set's kurtosis (that level's weight).
    one_quiet_level : bool
        Its :attr:`LevelProfile.one_quiet_level`.
    left_out_ratio : float
        Its :meth:`LevelProfile.left_out_ratio` (runs of :data:`MOTION_RUN` blocks).
    profile : LevelProfile, optional
        The reversed record's profile itself (its own sample indices), made once.
    """

    quiet: tuple[tuple[int, int], ...]
    spans: tuple[tuple[int, int], ...]
    quiet_variance: float
    quiet_dof: float
    one_quiet_level: bool
    left_out_ratio: float
    profile: LevelProfile | None = None


@dataclass(frozen=True)
class LevelProfile:
    """Noise variance per block of the record, with 95 % intervals.

    Attributes
    ----------
    start, stop : ndarray of int, shape (n_blocks,)
        Sample range of each block.
    variance, lo, hi : ndarray, shape (n_blocks,)
        Level of each block and its interval.
    dof : ndarray, shape (n_blocks,)
        Effective degrees of freedom of each level.
    quiet : ndarray of bool, shape (n_blocks,)
        Blocks of the quiet set: the still regimes' blocks, less those with motion in
        part of them (a low median, a high mean square).
    regimes : tuple of Regime
        Stretches of one noise level (:mod:`noisevar.diagnostics.regimes`), in order.
    count : ndarray, shape (n_blocks,), optional
        Residuals kept in each block (fewer than its samples where some were left out
        around level jumps).
    robust : ndarray, shape (n_blocks,), optional
        Each block's robust level (its median square over χ²₁'s), which the regimes are
        found on.
    quiet_dof : ndarray, shape (n_blocks,), optional
        Each block's mean-square dof with the noise kurtosis of the quiet set's other
        blocks (default :attr:`dof`, the record's kurtosis, which motion outside the set
        can raise).
    near_split : bool
        One regime, though a change is hinted (``regimes.hints_a_change``): a split that
        PELT may make on another grid's phase (``diagnostics.both_grids``).
    unmeasured : tuple of (int, int)
        Sample ranges of runs of :data:`MOTION_RUN` blocks or more left with too few
        residuals to measure (all but a handful left out around level jumps): stretches
        where the signal moved faster than the noise, motion of no measured level.
    """

    start: NDArray
    stop: NDArray
    variance: NDArray
    lo: NDArray
    hi: NDArray
    dof: NDArray
    quiet: NDArray
    regimes: tuple[Regime, ...] = ()
    count: NDArray | None = None
    robust: NDArray | None = None
    quiet_dof: NDArray | None = None
    back_grid: BackGrid | None = None
    near_split: bool = False
    unmeasured: tuple[tuple[int, int], ...] = ()

    @property
    def quiet_variance(self) -> float:
        """Pooled level (mean square) of the quiet blocks; with :attr:`back_grid`, the
        level of both grids' quiet blocks, each grid's weighted by its dof (the same for
        the record reversed)."""
        own = pooled(self.variance, self.dof, self.quiet)
        back = self.back_grid
        if back is None or not back.quiet_dof > 0:
            return own
        w = self._quiet_nu
        return (own * w + back.quiet_variance * back.quiet_dof) / (w + back.quiet_dof)

    @property
    def quiet_bounds(self) -> tuple[float, float]:
        """The 95 % interval of :attr:`quiet_variance`: χ² on its quiet blocks' summed dof
        (:attr:`quiet_dof`), the mean of the two grids' with :attr:`back_grid` (both read
        the same samples); NaN without a quiet block."""
        nus = [self._quiet_nu]
        if self.back_grid is not None:
            nus.append(self.back_grid.quiet_dof)
        nus = [v for v in nus if v > 0]
        if not nus:
            return math.nan, math.nan
        nu, v = float(np.mean(nus)), self.quiet_variance
        return nu * v / chi2_ppf(0.975, nu), nu * v / chi2_ppf(0.025, nu)

    @property
    def _quiet_nu(self) -> float:
        """The quiet blocks' summed dof, with the quiet set's own kurtosis."""
        dof = self.dof if self.quiet_dof is None else self.quiet_dof
        return float(np.sum(dof[self.quiet]))

    @property
    def one_quiet_level(self) -> bool:
        """The blocks left out of the quiet set change nothing its interval can tell.

        True when the pooled mean square of every block lies inside the 95 % interval of
        the quiet blocks' pooled mean square (χ² on their summed dof, with the quiet set's
        own kurtosis: :attr:`quiet_dof`): every block quiet, or a few left out by chance or
        by the noise's own tails. The record is then one quiet level, and its quiet level
        is R (docs/algorithms.md §E1 *The quiet level*). False when no block is quiet, or
        the reversed grid (:attr:`back_grid`) finds otherwise (one quiet block of few dof
        has an interval wide enough to hold any level: on one grid only, by its phase).
        """
        if not self.quiet.any() or (
            self.back_grid is not None and not self.back_grid.one_quiet_level
        ):
            return False
        lo, hi = self.quiet_interval
        return bool(lo <= self.pooled_level <= hi)

    @property
    def quiet_interval(self) -> tuple[float, float]:
        """The 95 % interval of the quiet blocks' pooled mean square: χ² on their summed
        dof, with the quiet set's own kurtosis (:attr:`quiet_dof`); NaN without a quiet
        block."""
        if not self.quiet.any():
            return math.nan, math.nan
        dof = self.dof if self.quiet_dof is None else self.quiet_dof
        nu = float(np.sum(dof[self.quiet]))
        quiet = pooled(self.variance, self.dof, self.quiet)
        return nu * quiet / chi2_ppf(0.975, nu), nu * quiet / chi2_ppf(0.025, nu)

    @property
    def pooled_level(self) -> float:
        """The dof-weighted level of every block."""
        return pooled(self.variance, self.dof, np.ones(self.quiet.size, dtype=bool))

    @property
    def still_stretches(self) -> list[tuple[int, int]]:
        """Sample ranges of the quiet blocks that lost no residual around a level jump.

        Runs of such blocks, in order: where the sensor's own noise can be estimated
        again, by any method, with nothing of the record's motion in it.
        """
        whole = (
            self.quiet
            if self.count is None
            else self.quiet & (self.count >= self.stop - self.start)
        )
        edges = np.flatnonzero(np.diff(np.r_[0, whole.view(np.int8), 0]))
        return [
            (int(self.start[a]), int(self.stop[b - 1]))
            for a, b in zip(edges[::2], edges[1::2], strict=True)
        ]

    def left_out_ratio(self, run: int = MOTION_RUN) -> float:
        """Robust level of the quiet set's left-out runs over the quiet blocks'.

        Parameters
        ----------
        run : int
            Fewest consecutive blocks left out of the quiet set that count.

        Returns
        -------
        float
            The largest count-weighted mean of :attr:`robust` over such a run, over the
            quiet blocks'; 0 when there is none, no quiet block, or no robust levels.

        Notes
        -----
        A run of blocks whose medians too are raised is a stretch of motion; one huge
        spike raises the mean square (and, through the smoother, the median) of one
        block or two only. With :attr:`back_grid` (runs of :data:`MOTION_RUN`), the
        smaller of the two grids' ratios: a run of three blocks is found on one grid
        and cut to two by the other's phase (a Pololu gyroscope: reversed, its still
        stretches were apart from R and too short to measure), and the record reversed
        reads the same two grids.
        """
        own = self._left_out_ratio(run)
        if self.back_grid is None or run != MOTION_RUN:
            return own
        return min(own, self.back_grid.left_out_ratio)

    def _left_out_ratio(self, run: int) -> float:
        """:meth:`left_out_ratio` on the record's own grid."""
        if self.robust is None or not self.quiet.any():
            return 0.0
        w = self.stop - self.start if self.count is None else self.count
        quiet = pooled(self.robust, w, self.quiet)
        edges = np.flatnonzero(np.diff(np.r_[0, (~self.quiet).view(np.int8), 0]))
        best = 0.0
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            if b - a >= run and quiet > 0:
                inside = np.zeros(self.quiet.size, dtype=bool)
                inside[a:b] = True
                best = max(best, pooled(self.robust, w, inside) / quiet)
        return best

    @property
    def quiet_share(self) -> float:
        """Share of the record's samples in the quiet blocks of either block grid.

        Over the samples in a block or an :attr:`unmeasured` stretch. The record's own grid
        alone without :attr:`back_grid`; with it, the samples in a quiet block of either grid
        over those in a block (or unmeasured stretch) of either (the same share for the
        record reversed, whose grids are these two swapped).
        """
        moved = sum(b - a for a, b in self.unmeasured)
        if self.back_grid is None:
            sizes = self.stop - self.start
            return float(np.sum(sizes[self.quiet]) / (np.sum(sizes) + moved))
        back = self.back_grid
        own = _runs(self.start, self.stop, np.ones_like(self.quiet)) + self.unmeasured
        n = int(max(b for _, b in (*own, *back.spans)))
        quiet = _union(_runs(self.start, self.stop, self.quiet), back.quiet, n)
        spans = _union(own, back.spans, n)
        return float(quiet / spans) if spans else 0.0

    @property
    def any_quiet(self) -> bool:
        """Whether a block of either grid is quiet (:attr:`back_grid`; the record's own
        grid alone without it): the same for the record reversed."""
        return bool(self.quiet.any() or (self.back_grid is not None and self.back_grid.quiet))

    def to_dict(self) -> dict[str, list]:
        return {
            "start": self.start.tolist(),
            "stop": self.stop.tolist(),
            "variance": self.variance.tolist(),
            "lo": self.lo.tolist(),
            "hi": self.hi.tolist(),
            "quiet": self.quiet.tolist(),
            "regimes": [r.to_dict() for r in self.regimes],
            "unmeasured": [list(r) for r in self.unmeasured],
        }


def _runs(start: NDArray, stop: NDArray, member: NDArray) -> tuple[tuple[int, int], ...]:
    """Sample ranges of the ``member`` blocks, those that touch joined, in order (a
    block left out between two, around a jump, is not bridged)."""
    idx = np.flatnonzero(member)
    ranges = [(int(a), int(b)) for a, b in zip(start[idx], stop[idx], strict=True)]
    return tuple(_holding_runs(ranges, [], int(stop[-1]) if stop.size else 0, 1))


def _union(forward: tuple[tuple[int, int], ...], other: tuple[tuple[int, int], ...], n: int) -> int:
    """Samples of ``0 .. n`` in a range of either set (both in the record's indices)."""
    return sum(b - a for a, b in _holding_runs([*forward, *other], [], n, 1))


def with_back_grid(prof: LevelProfile, back: LevelProfile, n: int) -> LevelProfile:
    """``prof`` (the record's profile, ``n`` samples) with :attr:`LevelProfile.back_grid`:
    that of ``back``, the record reversed's profile (its own sample indices).

    Notes
    -----
    docs/algorithms.md §E1 *Regimes*. Which blocks are quiet moves with the grid's phase:
    a short rest can fill a block of one grid and straddle two of the other, and a quiet
    set of a few blocks can be found on one grid and not on the other (a 953-sample
    IMU channel: 7 % quiet forwards, none reversed, so its verdict flipped between
    "mostly motion" and "no stretch of it is quiet"). Read on both grids, a record and its
    reversal are the same two grids swapped, so the share is the same either way.
    """
    mirror = lambda runs: tuple((n - b, n - a) for a, b in reversed(runs))  # noqa: E731
    quiet = mirror(_runs(back.start, back.stop, back.quiet))
    spans = mirror(sorted(_runs(back.start, back.stop, np.ones_like(back.quiet)) + back.unmeasured))
    return replace(
        prof,
        back_grid=BackGrid(
            quiet,
            spans,
            back.quiet_variance,
            back._quiet_nu,
            back.one_quiet_level,
            back.left_out_ratio(),
            back,
        ),
    )


def block_bounds(n: int, min_block: int = PROFILE_MIN_BLOCK) -> NDArray:
    """Start of each profile block over ``n`` samples (blocks grow with the record)."""
    block = max(min_block, -(-n // PROFILE_BLOCKS))
    return np.arange(max(1, n // block)) * block


def robust_levels(sq: NDArray, first: NDArray) -> NDArray:
    """Each block's median of ``sq`` over the median of χ²₁: a level that spikes do not move.

    Blocks start at ``first`` and have equal sizes but the last (which takes the rest).
    """
    nb = first.size
    size = int(first[1]) if nb > 1 else sq.size
    med = np.empty(nb)
    if nb > 1:
        med[:-1] = np.median(sq[: (nb - 1) * size].reshape(nb - 1, size), axis=1)
    med[-1] = np.median(sq[(nb - 1) * size :])
    if not np.all(med > 0):  # quantised data can have a median square of 0: use the mean
        mean = np.add.reduceat(sq, first) / np.diff(np.r_[first, sq.size]) * CHI2_1_MEDIAN
        med = np.where(med > 0, med, mean)
    return med / CHI2_1_MEDIAN


def level_profile(
    sq: NDArray, pos: NDArray, dof_per_sample: float, eta: float, robust: NDArray | None = None
) -> LevelProfile:
    """Block means of normalised squared residuals ``sq`` and the quiet set.

    Parameters
    ----------
    sq : ndarray, shape (m,)
        Squared residuals, each with expectation the local noise variance.
    pos : ndarray of int, shape (m,)
        The record's sample index of each.
    dof_per_sample : float
        Degrees of freedom per sample of the mean square (``1 / (η + (κ - 3) / 2)``,
        docs/algorithms.md §E1).
    eta : float
        ``Σ ρ²`` of the residual filter (its squares' correlation).
    robust : ndarray, optional
        :func:`robust_levels` of the blocks, if already computed.

    Returns
    -------
    LevelProfile
        Block levels are mean squares (tails included); which blocks are quiet is
        decided on block medians, which a few spikes do not move.
    """
    first = block_bounds(sq.size)
    last = np.r_[first[1:], sq.size]
    count = (last - first).astype(float)
    robust = robust_levels(sq, first) if robust is None else robust
    var = np.add.reduceat(sq, first) / count
    start, stop = pos[first], pos[last - 1] + 1
    return profile_from_blocks(start, stop, count, var, robust, dof_per_sample, eta)


def profile_from_blocks(
    start: NDArray,
    stop: NDArray,
    count: NDArray,
    var: NDArray,
    robust: NDArray,
    dof_per_sample: float,
    eta: float,
    medians: NDArray | None = None,
    tails: tuple[NDArray, NDArray, NDArray] | None = None,
    lsb: float | None = None,
) -> LevelProfile:
    """The profile of blocks with ``count`` squares of mean ``var`` and robust level ``robust``.

    See :func:`level_profile`; ``start``, ``stop`` are the blocks' sample ranges;
    ``medians`` the number of squares each robust level is the median of (default
    ``count``); ``tails`` each block's ``Σ e²/L`` and ``Σ e⁴/L²`` over its robust level
    ``L``, and the residual filter: the quiet set then tests a block's mean square with the
    kurtosis of the other blocks (default: the record's, in ``dof_per_sample``); ``lsb``
    the record's grid step (:func:`~noisevar.diagnostics.regimes.find_regimes`).
    """
    dof = count * dof_per_sample
    lo = dof * var / chi2_ppf(0.975, dof)
    # a block of very few dof has a lower quantile that underflows to 0: its bound is huge
    q = np.maximum(chi2_ppf(0.025, dof), np.finfo(float).tiny)
    with np.errstate(over="ignore"):  # a tail kurtosis so heavy that dof underflow: inf
        hi = np.minimum(dof * var / q, np.finfo(float).max)
    # a median of χ²₁ has relative sd 1 / (2 f(m) m sqrt(n)): as a χ² with 0.368 n dof
    robust_dof = (count if medians is None else medians) * MEDIAN_DOF / eta
    # regimes on the robust levels, which a few spikes do not move (docs/algorithms.md §F1)
    regimes = find_regimes(start, stop, robust, robust_dof, lsb)
    still = np.zeros(robust.size, dtype=bool)
    for r in regimes:
        still |= r.still & (start >= r.start) & (stop <= r.stop)
    level = 1.0 - QUIET_ALPHA / robust.size
    keep = partial(quiet_set, still, var, dof)
    # the still blocks' levels scatter by ``phi`` times more than their dof say (noise
    # low-passed by the sensor, a level that wanders): the rounds read dof / phi, as the
    # floor does (the seed keeps Gaussian noise's test: a tap in part of a block stays out)
    phi = dispersion_shown(robust, robust_dof, _block_spans(regimes, start, stop, count))
    # ... of the blocks it is measured on: one that lost residuals around a jump keeps
    # Gaussian noise's test (a tap in part of it)
    spread = np.where(count >= stop - start, phi, 1.0)
    # the seed: still blocks whose mean square is near the still blocks' median; where the
    # record has motion, only those Gaussian noise explains (handling beside the motion)
    seed = still & (var <= SEED_FACTOR * np.median(var[still]))
    quiet_dof = None
    if tails is None:
        quiet = keep(chi2_ppf(level, dof) / dof, seed)
    else:  # rounds: mean squares tested with the kurtosis of the last set's other blocks
        if not still.all():
            seed &= gaussian_seed(still, count, var, robust, robust_dof, eta, level)
        quiet = seed
        for _ in range(QUIET_ROUNDS):
            nu = leave_one_out_dof(count, robust, tails, quiet, eta, dof) / spread
            again = keep(chi2_ppf(level, nu) / nu, quiet)
            if np.array_equal(again, quiet):
                break
            quiet = again
        quiet_dof = leave_one_out_dof(count, robust, tails, quiet, eta, dof)
    regimes = still_if_quiet(regimes, start, stop, quiet)
    near = len(regimes) == 1 and hints_a_change(robust, robust_dof)
    return LevelProfile(
        start, stop, var, lo, hi, dof, quiet, regimes, count, robust, quiet_dof, None, near
    )


def _block_spans(
    regimes: tuple[Regime, ...], start: NDArray, stop: NDArray, count: NDArray
) -> list[tuple[int, int]]:
    """The block index ranges ``[a, b)`` of the still ``regimes``' runs of blocks that lost no
    residual around a level jump."""
    whole = np.zeros(start.size, dtype=bool)
    for r in regimes:
        whole |= r.still & (start >= r.start) & (stop <= r.stop)
    whole &= count >= stop - start
    edges = np.flatnonzero(np.diff(np.r_[0, whole.view(np.int8), 0]))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def on_both_grids(
    forward: list[tuple[int, int]], backward: list[tuple[int, int]], n: int
) -> list[tuple[int, int]]:
    """Sample ranges still on both block grids: the record's and its reversal's.

    Parameters
    ----------
    forward : list of (int, int)
        Still stretches of the record (:attr:`LevelProfile.still_stretches`).
    backward : list of (int, int)
        Still stretches of the reversed record, in its own sample indices.
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        Their intersection, in order.

    Notes
    -----
    A short rest read on one grid can sit at the floor while the same rest read on a
    grid shifted by a few samples takes a block half in the motion beside it
    (docs/algorithms.md §E1 Regimes). Blocks laid from the start and from the end are
    the two grids a reversal swaps, so the intersection is the same stretch either way.
    """
    return _holding_runs(forward, backward, n, 2)


def on_either_grid(
    forward: list[tuple[int, int]], backward: list[tuple[int, int]], n: int
) -> list[tuple[int, int]]:
    """Sample ranges on the record's block grid or its reversal's: their union, in order.

    As :func:`on_both_grids` (the same arguments), for stretches that each grid finds
    whole where the other may cut them short (a still regime's extent moves by a block
    with the grid's phase): the union is the same stretch either way.
    """
    return _holding_runs(forward, backward, n, 1)


def _holding_runs(
    forward: list[tuple[int, int]], backward: list[tuple[int, int]], n: int, least: int
) -> list[tuple[int, int]]:
    """The runs of samples ``0 .. n`` that at least ``least`` of the ranges hold, in order.

    ``backward`` in reversed indices. Each range adds 1 from its start and takes it off at
    its stop; the count is constant between two of these ends, so the runs are read off
    the ends alone (no array the record's size).
    """
    delta: dict[int, int] = {}
    for a, b in [*forward, *((n - b, n - a) for a, b in backward)]:
        delta[a] = delta.get(a, 0) + 1
        delta[b] = delta.get(b, 0) - 1
    out: list[tuple[int, int]] = []
    count, start = 0, None
    for at in sorted(k for k in delta if k < n):
        count += delta[at]
        if count >= least and start is None:
            start = at
        elif count < least and start is not None:
            if at > start:
                out.append((start, at))
            start = None
    if start is not None and start < n:
        out.append((start, n))
    return out
