"""Diagnostics as a sum over stretches of a record, so that a record streamed in chunks gets them.

Every statistic of :func:`noisevar.diagnostics.diagnose` is laid on a grid fixed before
the record is read (:class:`DiagPlan`): residual slots in blocks, whiteness windows,
the quantisation probe. Each stretch of the record adds what falls on its part of the
grid (:meth:`DiagSums.add`); a block's median is taken once all of its slots have been
seen, so that memory stays bounded whatever the record's length (docs/algorithms.md §E1).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from noisevar._arrays import median_inplace
from noisevar.diagnostics.profile import CHI2_1_MEDIAN, PROFILE_BLOCKS, PROFILE_MIN_BLOCK
from noisevar.diagnostics.quantisation import LSB_PROBE, level_step
from noisevar.diagnostics.whiteness import WHITE_LAGS
from noisevar.numeric.blocks import row_medians

#: At most this many samples enter the whiteness tests (spread over the record).
WHITE_MAX = 2**18
#: Samples per block of the level that the kurtosis is taken relative to (at least).
SHAPE_BLOCK = 256
#: Span and order of the local-polynomial residual the diagnostics look through.
DIAG_SPAN = 21
DIAG_ORDER = 3
#: A block's robust level is the median of at most this many of its residuals.
MEDIAN_MAX = 2**16
#: A profile block with fewer kept residuals than this is left out of the profile.
PROFILE_MIN_KEPT = 8
#: At most this many distinct values are collected when the quantisation probe is flat.
UNIQUE_MAX = 4096


@dataclass(frozen=True)
class Grid:
    """Blocks of ``size`` residual slots over ``m`` slots; the last takes the rest."""

    m: int
    size: int

    @classmethod
    def over(cls, m: int, min_block: int) -> Grid:
        return cls(m, max(min_block, -(-m // PROFILE_BLOCKS)))

    @property
    def count(self) -> int:
        return max(1, self.m // self.size)

    def stop(self, b: NDArray) -> NDArray:
        return np.where(b == self.count - 1, self.m, (b + 1) * self.size)

    def end(self, b: int) -> int:
        """:meth:`stop` of one block, without NumPy (the last block takes the rest)."""
        return self.m if b == self.count - 1 else (b + 1) * self.size

    @property
    def stride(self) -> int:
        """Every ``stride``-th slot of a block enters its median."""
        return max(1, -(-self.size // MEDIAN_MAX))


def windows(total: int, most: int = WHITE_MAX) -> tuple[tuple[int, int], ...]:
    """At most ``most`` indices of ``range(total)`` in 16 windows spread over it."""
    if total <= most:
        return ((0, total),)
    width = most // 16
    return tuple((int(a), int(a) + width) for a in np.linspace(0, total - width, 16).astype(int))


@dataclass(frozen=True)
class DiagPlan:
    """Where the diagnostics look, fixed before the record is read.

    ``segments``: uniform stretches ``(a, b)`` of the record; ``slot0`` the first residual
    slot of each (None: too short to diagnose); ``probe``: the quantisation probe's
    candidate ``(z0, step)`` (None: not on a grid; ``"flat"``: the probe has one value).
    """

    n: int
    segments: tuple[tuple[int, int], ...]
    slot0: tuple[int | None, ...]
    profile: Grid
    wide: Grid
    white: tuple[tuple[int, int], ...]
    incr: tuple[tuple[int, int], ...]
    probe: tuple[float, float] | str | None

    @property
    def h(self) -> int:
        return DIAG_SPAN // 2


def make_plan(
    n: int, segments: tuple[tuple[int, int], ...], probe: NDArray, block: int | None = None
) -> DiagPlan:
    """The plan for a record of ``n`` samples in ``segments``; ``probe`` from :func:`probe_of`;
    ``block``: the profile's block size (default: from the residuals' count)."""
    h = DIAG_SPAN // 2
    slot0: list[int | None] = []
    m = 0
    for a, b in segments:
        slot0.append(m if b - a >= 2 * DIAG_SPAN else None)
        m += b - a - 2 * h if b - a >= 2 * DIAG_SPAN else 0
    used = sum(1 for s in slot0 if s is not None)
    diffs = sum(b - a - 1 for a, b in segments)
    return DiagPlan(
        n, tuple(segments), tuple(slot0),
        Grid.over(m, PROFILE_MIN_BLOCK) if block is None else Grid(m, block),
        Grid.over(m, SHAPE_BLOCK), windows(m + WHITE_LAGS * used),
        windows(diffs + WHITE_LAGS * len(segments)), _grid_candidate(probe),
    )  # fmt: skip


def probe_of(read: object, n: int) -> NDArray:
    """The quantisation probe: every ``n // LSB_PROBE``-th sample (``read(slice)`` gives them)."""
    return np.asarray(read(slice(0, n, max(1, n // LSB_PROBE))), dtype=float)  # type: ignore[operator]


def _grid_candidate(probe: NDArray) -> tuple[float, float] | str | None:
    """``(z0, step)`` proposed by the probe (docs/algorithms.md §E3)."""
    levels = np.unique(probe)
    if levels.size < 2:
        return "flat"
    step = level_step(levels)
    return None if step is None else (float(levels[0]), step)


@dataclass
class Piece:
    """What one stretch adds to one block: seen slots, kept count, sums, median values."""

    seen: int
    count: int
    total: float
    values: list[NDArray]
    peak: float = 0.0  # largest |e| of the kept residuals (the fourth powers' scale)
    s2: float = 0.0  # Σ (e / peak)²
    s4: float = 0.0  # Σ (e / peak)⁴
    level: float | None = None  # the block's robust level, when the piece is the whole block
    n_values: int = 0  # squares its median is taken over (every ``stride``-th kept slot)

    def merge(self, other: Piece) -> None:
        self.seen += other.seen
        self.count += other.count
        self.total += other.total
        self.values += other.values
        self.n_values += other.n_values
        if other.peak > self.peak:  # rescale the sums to the larger peak
            r = (self.peak / other.peak) ** 2
            self.s2, self.s4 = self.s2 * r + other.s2, self.s4 * r * r + other.s4
            self.peak = other.peak
        elif other.peak > 0:
            r = (other.peak / self.peak) ** 2
            self.s2, self.s4 = self.s2 + other.s2 * r, self.s4 + other.s4 * r * r


def block_pieces(grid: Grid, s0: int, e: NDArray, keep: NDArray, norm: float) -> dict[int, Piece]:
    """The pieces of the blocks that slots ``s0 .. s0 + e.size`` fall in.

    ``norm`` turns ``e²`` into the squares whose expectation is the noise variance.
    """
    s1 = s0 + e.size
    first, last = s0 // grid.size, min((s1 - 1) // grid.size, grid.count - 1)
    whole = _whole_pieces(grid, s0, e, keep, norm)
    out = {}  # in block order: the sums add the blocks' shares in this order
    for b in range(min(first, grid.count - 1), last + 1):
        if b in whole:
            out[b] = whole[b]
            continue
        a = max(b * grid.size, s0)
        z = grid.end(b)
        sl = slice(a - s0, min(z, s1) - s0)
        every = bool(keep[sl].all())
        kept = e[sl] if every else e[sl][keep[sl]]
        # the first slot of the block's stride at or after a
        offset = (grid.size - (a - b * grid.size) % grid.stride) % grid.stride
        strided = e[sl][offset :: grid.stride]
        values = strided * strided if every else strided[keep[sl][offset :: grid.stride]] ** 2
        values *= norm
        peak = max(float(kept.max(initial=0.0)), -float(kept.min(initial=0.0)))
        s2 = s4 = 0.0
        if peak > 0:
            x2 = kept / peak
            x2 *= x2
            s2, s4 = float(x2.sum()), float(np.einsum("i,i->", x2, x2))  # no BLAS threads
        total = s2 * peak * peak * norm  # Σ e² norm
        piece = Piece(sl.stop - sl.start, int(kept.size), total, [values], peak, s2, s4)
        piece.n_values = int(values.size)
        if piece.seen == z - b * grid.size:  # the whole block: its level here (in parallel)
            piece.level, piece.values = block_level(piece), []
        out[b] = piece
    return out


def _whole_pieces(grid: Grid, s0: int, e: NDArray, keep: NDArray, norm: float) -> dict[int, Piece]:
    """:func:`block_pieces` of the blocks wholly inside the slots, none left out, at once.

    The same numbers as the loop over blocks (row by row: the same sums, products and
    order statistics), without its per-block calls; the last block of the grid, which
    takes the rest, and blocks with a left-out slot are the loop's.
    """
    size, stride = grid.size, grid.stride
    b0, b1 = -(-s0 // size), min((s0 + e.size) // size, grid.count - 1)
    if b1 <= b0:
        return {}
    lo = b0 * size - s0
    rows = e[lo : lo + (b1 - b0) * size].reshape(-1, size)
    every = keep[lo : lo + (b1 - b0) * size].reshape(-1, size).all(axis=1)
    if not every.all():
        rows = rows[every]
    top, low = rows.max(axis=1, initial=0.0), -rows.min(axis=1, initial=0.0)
    peak = np.where(low > top, low, top)  # as max(top, low): +0.0 when both are zero
    with np.errstate(invalid="ignore", divide="ignore"):
        x2 = rows / peak[:, None]
    x2 *= x2
    on = peak > 0
    s2 = np.where(on, x2.sum(axis=1), 0.0)
    s4 = np.where(on, np.einsum("ij,ij->i", x2, x2), 0.0)
    total = s2 * peak * peak * norm  # Σ e² norm
    strided = rows[:, size % stride :: stride]  # the loop's offset for a block's first slot
    values = strided * strided
    values *= norm
    med = row_medians(values)
    out = {}
    for i, b in enumerate(np.flatnonzero(every) + b0):
        piece = Piece(size, size, float(total[i]), [], float(peak[i]), float(s2[i]), float(s4[i]))
        piece.n_values = values.shape[1]
        piece.level = _level(float(med[i]), piece)
        out[int(b)] = piece
    return out


def block_level(piece: Piece) -> float:
    """A block's robust level: the median of its squares over the median of χ²₁."""
    if piece.level is not None:
        return piece.level
    v = np.concatenate(piece.values) if piece.values else np.zeros(0)
    return _level(median_inplace(v) if v.size else 0.0, piece)


def _level(med: float, piece: Piece) -> float:
    """The level of a block whose squares have the median ``med``."""
    if not med > 0 and piece.count:  # quantised data: a median square of 0, use the mean
        med = piece.total / piece.count * CHI2_1_MEDIAN
    return med / CHI2_1_MEDIAN


@dataclass
class Windows:
    """Pieces of a sequence inside fixed windows, assembled with separators between windows."""

    spans: tuple[tuple[int, int], ...]
    got: dict[int, tuple[NDArray, NDArray]] = field(default_factory=dict)

    def add(self, start: int, x: NDArray, keep: NDArray) -> None:
        for a, b in self.spans:
            lo, hi = max(a, start), min(b, start + x.size)
            if lo < hi:
                self.got[lo] = (x[lo - start : hi - start], keep[lo - start : hi - start])

    def _pieces(self) -> Iterator[tuple[int, NDArray, NDArray]]:
        """``(position, samples, kept)`` of each piece in order; ``-1`` for the separators."""
        sep = np.zeros(WHITE_LAGS)
        for a, b in self.spans:
            for lo in sorted(k for k in self.got if a <= k < b):
                yield lo, *self.got[lo]
            if len(self.spans) > 1:
                yield -1, sep, sep.astype(bool)

    def joined(self) -> tuple[NDArray, NDArray]:
        """The windows' samples in order, each window followed by ``WHITE_LAGS`` unused slots."""
        pieces = list(self._pieces())
        if not pieces:
            return np.zeros(0), np.zeros(0, dtype=bool)
        return np.concatenate([x for _, x, _ in pieces]), np.concatenate([k for *_, k in pieces])

    def joined_runs(self) -> list[tuple[int, int]]:
        """``(position, size)`` of each piece of :meth:`joined`, in order (``-1``: unused slots)."""
        return [(lo, x.size) for lo, x, _ in self._pieces()]

    def joined_slots(self) -> NDArray:
        """The position of each sample of :meth:`joined` (-1 for the unused slots)."""
        slots = [np.arange(lo, lo + x.size) if lo >= 0 else np.full(x.size, -1)
                 for lo, x, _ in self._pieces()]  # fmt: skip
        return np.concatenate(slots) if slots else np.zeros(0, dtype=int)
