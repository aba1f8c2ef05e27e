"""The diagnostics of a record from its stretches: :func:`diag_part` maps, :class:`DiagSums` adds.

A record in memory is one stretch per uniform segment; a record streamed from disk is
one stretch per chunk (``auto``'s chunked engine). Stretches are added in record order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.plan import (
    DIAG_ORDER,
    DIAG_SPAN,
    PROFILE_MIN_KEPT,
    UNIQUE_MAX,
    DiagPlan,
    Grid,
    Piece,
    Windows,
    block_level,
    block_pieces,
)
from noisevar.diagnostics.quantisation import (
    joined_step,
    level_step,
    on_grid,
    second_difference_step,
)
from noisevar.diagnostics.whiteness import WHITE_LAGS
from noisevar.errors import NoisevarError
from noisevar.numeric.fir import residual_sequence, rounded_fir


@dataclass
class DiagPart:
    """What one stretch of a record adds to the diagnostics."""

    profile: dict[int, Piece]
    wide: dict[int, Piece]
    white: list[tuple[int, NDArray, NDArray]]  # (index, residuals, kept)
    incr: list[tuple[int, NDArray, NDArray]]  # (index, first differences, used)
    on_grid: bool
    uniques: NDArray | None  # distinct values, when the quantisation probe was flat
    # the reversed record's (profile, wide) pieces (diag_part's ``back``)
    back: tuple[dict[int, Piece], dict[int, Piece]] = field(default_factory=lambda: ({}, {}))
    # the grid step of the stretch's second differences (quantisation.second_difference_step)
    d2_step: float | None = 0.0


def _sequence() -> NDArray:
    return residual_sequence(DIAG_SPAN, DIAG_ORDER)


def _residual_part(
    z: NDArray, wa: int, k0: int, k1: int, exclude: NDArray | None
) -> tuple[NDArray, NDArray]:
    """Residuals centred on samples ``k0 .. k1`` of the window starting at ``wa``, kept mask."""
    h = DIAG_SPAN // 2
    x = z[k0 - wa - h : k1 - wa + h]
    # at float rounding: 0 (a held stretch plus a trend is no still level, issue 26)
    e = rounded_fir(x, _sequence())
    x = None if exclude is None else exclude[k0 - wa - h : k1 - wa + h]
    if x is None or not x.any():
        return e, np.ones(e.size, dtype=bool)
    # a residual whose window touches an excluded sample (a level jump) is not kept
    c = np.r_[0, np.cumsum(x, dtype=np.int64)]
    return e, c[DIAG_SPAN:] == c[: c.size - DIAG_SPAN]


#: A first difference this many robust standard deviations out, by a level jump, is the jump.
JUMP_INCREMENT = 5.0


def _untouched(exclude: NDArray | None, k: int, dz: NDArray) -> NDArray:
    """The first differences ``dz`` (from window index ``k``) that are no level jump: those
    that touch samples left out around a jump and lie beyond :data:`JUMP_INCREMENT` robust
    standard deviations of the part's differences are left out (27 leap seconds made
    UT1-UTC's first difference read white, "a random walk", its interval from 0; a walk's
    own steps, which the step detector flags too, stay: they are its increments)."""
    keep = np.ones(dz.size, dtype=bool)
    if exclude is None or not dz.size:
        return keep
    x = exclude[k : k + dz.size + 1]
    touch = x[:-1] | x[1:]
    if touch.any():  # about their median: a trend (a constant on dz) moves nothing
        dev = np.abs(dz - np.median(dz))
        mad = float(np.median(dev)) / 0.6744897501960817  # a robust std
        keep &= ~(touch & (dev > JUMP_INCREMENT * mad))
    return keep


def diag_part(
    z: NDArray,
    wa: int,
    own: tuple[int, int],
    seg: int,
    plan: DiagPlan,
    exclude: NDArray | None = None,
    profile_only: bool = False,
    back: bool = False,
) -> DiagPart:
    """The share of the samples ``own`` (record indices) of segment ``seg``.

    Parameters
    ----------
    z : ndarray
        A window of the record starting at record index ``wa``: ``own`` and, where the
        segment goes on, :data:`DIAG_SPAN` samples either side.
    own : (int, int)
        The stretch (record indices), inside segment ``seg``.
    plan : DiagPlan
    exclude : ndarray of bool, optional
        Over the window: samples left out (around level jumps).
    profile_only : bool
        Only the level profile's blocks (no whiteness windows, increments or
        quantisation probe): what :func:`~noisevar.diagnostics.profile_of` needs.
    back : bool
        Also the pieces of the reversed record's profile (and shape) grid, from the same
        residuals read backwards (``DiagPart.back``; a plan of one segment). The residual
        filter is symmetric and the compiled filter adds each pair of taps first, so the
        reversed record's residuals are these, mirrored, to the last bit, and so is the
        kept mask (a residual is kept when no sample under its window is left out): the
        reversed grid's blocks without a pass over the reversed record.
    """
    a, b = plan.segments[seg]
    lo, hi = own
    h = plan.h
    d = _sequence()
    norm = 1.0 / float(np.dot(d, d))
    profile: dict[int, Piece] = {}
    wide: dict[int, Piece] = {}
    white: list[tuple[int, NDArray, NDArray]] = []
    rank = sum(s is not None for s in plan.slot0[:seg])
    s_first = plan.slot0[seg]
    mirrored: tuple[dict[int, Piece], dict[int, Piece]] = ({}, {})
    if s_first is not None:
        k0, k1 = max(lo, a + h), min(hi, b - h)
        r_sep = s_first + (b - a - 2 * h) + WHITE_LAGS * rank  # this segment's separator
        if k0 < k1:
            e, keep = _residual_part(z, wa, k0, k1, exclude)
            s0 = s_first + k0 - (a + h)
            profile = block_pieces(plan.profile, s0, e, keep, norm)
            same = plan.wide == plan.profile
            wide = profile if same else block_pieces(plan.wide, s0, e, keep, norm)
            if not profile_only:
                white += _inside(plan.white, s0 + WHITE_LAGS * rank, e, keep)
            if back:
                mirrored = _mirrored(plan, s0, e, keep, norm)
        if hi == b and not profile_only:
            white.append((r_sep, np.zeros(WHITE_LAGS), np.zeros(WHITE_LAGS, dtype=bool)))
    if profile_only:
        return DiagPart(profile, wide, white, [], True, None, mirrored)
    d0 = sum(b_ - a_ - 1 + WHITE_LAGS for a_, b_ in plan.segments[:seg])
    incr = []
    for p, q in plan.incr:  # first differences inside the windows only
        i0, i1 = max(p, d0 + lo - a), min(q, d0 + min(hi, b - 1) - a)
        if i0 < i1:
            k = i0 - d0 + a - wa  # window index of the first difference's first sample
            dz = np.diff(z[k : k + i1 - i0 + 1])
            incr.append((i0, dz, _untouched(exclude, k, dz)))
    if hi == b:
        incr.append((d0 + b - a - 1, np.zeros(WHITE_LAGS), np.zeros(WHITE_LAGS, dtype=bool)))
    own_z = z[lo - wa : hi - wa]
    sits, uniques = True, None
    if isinstance(plan.probe, tuple):
        sits = on_grid(own_z - plan.probe[0], plan.probe[1])
    elif plan.probe == "flat":
        uniques = np.unique(own_z)[: UNIQUE_MAX + 1]
    step = second_difference_step(own_z)
    return DiagPart(profile, wide, white, incr, sits, uniques, mirrored, step)


def _mirrored(
    plan: DiagPlan, s0: int, e: NDArray, keep: NDArray, norm: float
) -> tuple[dict[int, Piece], dict[int, Piece]]:
    """The pieces of the reversed record's grids that residual slots ``s0 ..`` fall in.

    Slot ``s`` of a record of ``m`` slots (one segment) is slot ``m - 1 - s`` of the
    record reversed; contiguous copies, so that the sums run as on the reversed record.
    """
    if len(plan.segments) != 1:
        raise NoisevarError("the reversed grid is read off a record of one segment only")
    r0 = plan.profile.m - s0 - e.size
    e_r, keep_r = np.ascontiguousarray(e[::-1]), np.ascontiguousarray(keep[::-1])
    profile = block_pieces(plan.profile, r0, e_r, keep_r, norm)
    same = plan.wide == plan.profile
    return profile, profile if same else block_pieces(plan.wide, r0, e_r, keep_r, norm)


def _inside(
    spans: tuple[tuple[int, int], ...], start: int, x: NDArray, keep: NDArray
) -> list[tuple[int, NDArray, NDArray]]:
    """The pieces of ``x`` (indices from ``start``) inside the windows ``spans``."""
    out = []
    for p, q in spans:
        i0, i1 = max(p, start), min(q, start + x.size)
        if i0 < i1:
            out.append((i0, x[i0 - start : i1 - start].copy(), keep[i0 - start : i1 - start]))
    return out


def _entry(piece: Piece) -> tuple[int, float, float, int, float, float]:
    """A closed block's profile entry: count, Σ squares, robust level, median's squares,
    Σ e²/L and Σ e⁴/L²."""
    level = block_level(piece)
    k2 = k4 = 0.0
    if piece.count and level > 0:
        # Σ e²/L = (peak² / L) Σ (e/peak)², and the same for the fourth powers
        # (huge levels may overflow to inf here: the caller ignores the warning)
        r = piece.peak**2 / level
        k2, k4 = r * piece.s2, r * r * piece.s4
    return (piece.count, piece.total, level, piece.n_values, k2, k4)


class DiagSums:
    """Running sums of the diagnostics; blocks are reduced as soon as they are complete."""

    def __init__(self, plan: DiagPlan, back: bool = False) -> None:
        self.plan = plan
        #: The reversed record's profile sums (from the parts' ``back`` pieces), when asked.
        self.back: DiagSums | None = DiagSums(plan) if back else None
        self.open: tuple[dict[int, Piece], dict[int, Piece]] = ({}, {})
        # block: kept count, Σ squares, robust level, squares its median was taken over,
        # Σ e²/L and Σ e⁴/L² (the block's tails, for the quiet set)
        self.profile: dict[int, tuple[int, float, float, int, float, float]] = {}
        self.wide: dict[int, tuple[int, float]] = {}  # block: count, level
        self.k2 = self.k4 = 0.0  # Σ e²/L and Σ e⁴/L² over the kept residuals
        self.white = Windows(plan.white)
        self.incr = Windows(plan.incr)
        self.on_grid = True
        self.d2_steps: list[float | None] = []
        self.uniques: NDArray | None = np.zeros(0) if plan.probe == "flat" else None

    def add(self, part: DiagPart) -> None:
        """Add one stretch (in record order)."""
        self._blocks(0, part.profile, self.plan.profile)
        if self.plan.wide != self.plan.profile:
            self._blocks(1, part.wide, self.plan.wide)
        if self.back is not None:
            self.back._blocks(0, part.back[0], self.plan.profile)
            if self.plan.wide != self.plan.profile:
                self.back._blocks(1, part.back[1], self.plan.wide)
        for start, e, keep in part.white:
            self.white.add(start, e, keep)
        for start, dz, used in part.incr:
            self.incr.add(start, dz, used)
        self.on_grid &= part.on_grid
        self.d2_steps.append(part.d2_step)
        if self.uniques is not None and part.uniques is not None:
            self.uniques = np.union1d(self.uniques, part.uniques)[: UNIQUE_MAX + 1]

    def _blocks(self, which: int, pieces: dict[int, Piece], grid: Grid) -> None:
        open_ = self.open[which]
        with np.errstate(over="ignore"):  # once for all blocks (see _close)
            for b, piece in pieces.items():
                if b in open_:
                    open_[b].merge(piece)
                else:
                    open_[b] = piece
                size = grid.end(b) - b * grid.size
                if open_[b].seen == size:
                    self._close(which, b, open_.pop(b))

    def _close(self, which: int, b: int, piece: Piece) -> None:
        entry = _entry(piece)
        if which == 0:
            self.profile[b] = entry
        if which == 1 or self.plan.wide == self.plan.profile:
            self.wide[b] = (piece.count, entry[2])
            self.k2 += entry[4]
            self.k4 += entry[5]

    def reblock(self, b: int, piece: Piece) -> None:
        """Profile block ``b`` anew from its whole ``piece`` (the shape grid's sums, the
        kurtosis' and the whiteness windows' stay): :mod:`noisevar.diagnostics.glitches`."""
        with np.errstate(over="ignore"):
            self.profile[b] = _entry(piece)

    def lsb(self) -> float | None:
        """The quantisation step, when every stretch sat on the probe's grid."""
        probe = self.plan.probe
        if isinstance(probe, tuple):
            return probe[1] if self.on_grid else None
        if probe is None or self.uniques is None or not 2 <= self.uniques.size <= UNIQUE_MAX:
            return None
        return level_step(self.uniques)

    def held_step(self, lsb: float | None) -> float | None:
        """The grid step held values are judged on: the step the record's second
        differences sit on (a trend or an offset keeps it), else ``lsb``."""
        step = joined_step(self.d2_steps)
        return lsb if step is None else step

    def check(self) -> None:
        """Refuse a record with no residual kept (nothing to diagnose)."""
        if not any(v[0] >= PROFILE_MIN_KEPT for v in self.profile.values()):
            raise NoisevarError(
                f"the record is too short to diagnose: no stretch of it has {2 * DIAG_SPAN} "
                f"uniformly sampled samples (span {DIAG_SPAN}) free of jumps"
            )
