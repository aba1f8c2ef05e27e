"""Regimes of a record: stretches of one noise level (still, moving, warming up, vibrating).

A real log is a sequence of regimes. They are change points in the noise level along the
record (docs/algorithms.md §F1): PELT (Killick, Fearnhead & Eckley 2012, through
``ruptures``) over the level profile's blocks, with the Gaussian cost of a block's robust
level, which a few spikes do not move. The cost reads the same forwards and backwards, so
the regimes of a reversed record are the reversed regimes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy import special

from noisevar._distributions import chi2_ppf
from noisevar.diagnostics.quantisation import half_a_step

#: The penalty per change point is ``REGIME_PENALTY * log(number of blocks)``; measured to
#: split white noise of one level in under 5 % of records (tests/diagnostics/test_regimes.py).
REGIME_PENALTY = 6.0
#: A regime more than this many times the lowest regime's upper 95 % bound is never still.
STILL_RATIO = 2.0
#: A regime whose level is above the floor's at this level (one-sided, per step) is not still.
STILL_ALPHA = 1e-3
#: A regime at most this many times the record's highest level is flat: constant samples
#: (a dropout, a held or clipped value) and float rounding, never a still level.
FLAT_RATIO = 1e-16
#: The quiet level's source when R's method reads the still stretches no quieter than the
#: whole record (``estimators.still_quiet.above_record``): no quiet level, so no still R.
ABOVE = "above"
#: The quiet level's source when R's method reads the still stretches above the whole
#: record but R inside their interval (``estimators.still_set.same_level``): they read R's
#: level, so the quiet level, and the R to use, is R itself.
SAME = "same"
#: The quiet level's source when it is the estimate's still R (``estimate.still``).
STILL = "still"
#: The quiet level's source when the still stretches are held values, not noise
#: (``estimators.still_quiet.held_digits``): no still R, for that reason.
HELD = "held"
#: A regime of fewer blocks is all edge (no block away from its ends), which the block
#: grid's phase moves: beside a flat regime, or held values alone, it sets no floor.
FLOOR_BLOCKS = 3


@dataclass(frozen=True)
class Regime:
    """One stretch of the record at one noise level.

    Attributes
    ----------
    start, stop : int
        Sample range.
    variance, lo, hi : float
        Its level (pooled robust level of its blocks) and 95 % interval.
    dof : float
        Degrees of freedom of the level.
    still : bool
        At the record's lowest level: the sensor's own noise, no motion leaking through.
    near_still : bool
        Not still, yet at most :data:`STILL_RATIO` times the lowest regime's upper 95 %
        bound: another still level that the floor's test tells apart (another posture,
        slow sway), not motion.
    """

    start: int
    stop: int
    variance: float
    lo: float
    hi: float
    dof: float
    still: bool
    near_still: bool = False

    def to_dict(self) -> dict[str, float | int | bool]:
        return {
            "start": self.start,
            "stop": self.stop,
            "variance": self.variance,
            "ci95_low": self.lo,
            "ci95_high": self.hi,
            "still": self.still,
            "near_still": self.near_still,
        }


@dataclass(frozen=True)
class StillLevel:
    """A near-still regime's level on the R to use's own residual, over the R to use.

    Attributes
    ----------
    start, stop : int
        Sample range it was measured on (the regime less one profile block at either end).
    ratio, lo, hi : float
        Its level and 95 % interval over the R to use (unit-free).
    """

    start: int
    stop: int
    ratio: float
    lo: float
    hi: float

    def to_dict(self) -> dict[str, float | int]:
        return {"start": self.start, "stop": self.stop, "ratio": self.ratio,
                "ci95_low": self.lo, "ci95_high": self.hi}  # fmt: skip


@dataclass(frozen=True)
class QuietLevel:
    """The quiet level: the still regimes pooled, on the same residual as R.

    Set by the estimate (``noisevar.estimators.still_quiet.quiet_level``), which measures
    it with R's own method (docs/algorithms.md §E1 *The quiet level*).

    Attributes
    ----------
    variance, lo, hi : float or None
        The level and its 95 % interval; None when the record has none.
    share : float
        Share of the record's samples in the quiet blocks.
    source : str
        ``"still"``: R's method on the still stretches (the estimate's ``.still``);
        ``"record"``: the whole record is one quiet level, so R itself (every block quiet,
        or those left out change nothing the quiet level's interval can tell);
        ``"quiet stretches"``: R's method on the quiet stretches of a one-level record
        whose other blocks change its level; ``""`` when absent.
    reason : str
        Why there is none (``""`` when there is one).
    """

    variance: float | None
    lo: float | None
    hi: float | None
    share: float
    source: str = ""
    reason: str = ""

    def mapped(self, f: Callable[[float], float]) -> QuietLevel:
        """The level, ``lo`` and ``hi`` through ``f`` (into other units); absent stays absent."""
        if self.variance is None or self.lo is None or self.hi is None:
            return self
        return replace(self, variance=f(self.variance), lo=f(self.lo), hi=f(self.hi))

    @property
    def held(self) -> bool:
        """The still stretches are held values, not noise (source :data:`HELD`): no still R,
        for :attr:`reason`."""
        return self.source == HELD

    def to_dict(self) -> dict[str, float | str | None]:
        return {"variance": self.variance, "ci95_low": self.lo, "ci95_high": self.hi,
                "share": self.share, "source": self.source, "reason": self.reason}  # fmt: skip


def read_above(quiet: QuietLevel | None) -> bool:
    """R's method read the still stretches no quieter than R (:data:`ABOVE` or
    :data:`SAME`): no still R apart from R.

    Where they are half the record or more and the noise is not white, the verdict says
    its colour first, not a level change that only the level profile's residual reads
    (sktime's solar generation: PELT splits it on one block grid's phase, not on others).
    """
    return quiet is not None and quiet.source in (ABOVE, SAME)


class _Cost:
    """``W log(Σ w x / W)`` over blocks ``[a, b)`` of level ``x`` and dof ``w``.

    ``-2 log L`` of χ² levels with one variance, up to a constant (docs/algorithms.md §F1).
    """

    def __init__(self, x: NDArray, w: NDArray) -> None:
        self.cw = np.r_[0.0, np.cumsum(w)]
        self.cwx = np.r_[0.0, np.cumsum(w * x)]

    def __call__(self, a: NDArray | int, b: NDArray | int) -> NDArray:
        w = self.cw[b] - self.cw[a]
        # a difference of running sums can round to 0 (or below) for the smallest levels
        tiny = np.finfo(float).tiny
        return w * np.log(np.maximum(self.cwx[b] - self.cwx[a], tiny) / np.maximum(w, tiny))


def _gain_of_two_splits(cost: _Cost, m: int) -> float:
    """The largest fall in cost from one or two change points (every pair, as arrays)."""  # noqa
    k = np.arange(1, m)
    one = cost(0, m) - (cost(0, k) + cost(k, m))
    i, j = np.triu_indices(m - 1, k=1)
    two = cost(0, m) - (cost(0, k[i]) + cost(k[i], k[j]) + cost(k[j], m))
    return float(max(one.max(initial=0.0), two.max(initial=0.0)))


def _pelt(cost: _Cost, m: int, pen: float) -> list[int]:
    """``ruptures``' PELT with :class:`_Cost` (imported here: it brings ``scipy.stats``).

    The cost of every stretch of blocks is computed at once (at most ``PROFILE_BLOCKS``
    blocks: a small table; the same numbers as one call per stretch) and looked up, one
    Python float per stretch PELT asks for (it prunes most of them: no list of them all).
    """
    import ruptures

    a, b = np.triu_indices(m + 1, k=1)
    table = np.zeros((m + 1, m + 1))
    table[a, b] = cost(a, b)
    item = table.item

    class LevelCost(ruptures.base.BaseCost):
        model = "noise-level"
        min_size = 1

        def fit(self, signal: NDArray) -> LevelCost:
            self.signal = signal
            return self

        def error(self, start: int, end: int) -> float:
            return item(start, end)

    algo = ruptures.Pelt(custom_cost=LevelCost(), min_size=1, jump=1)
    return algo.fit(np.zeros((m, 1))).predict(pen=pen)[:-1]


def regime_breaks(level: NDArray, dof: NDArray, penalty: float = REGIME_PENALTY) -> list[int]:
    """Block indices where a new regime starts (0 first), by PELT on the blocks' levels.

    Parameters
    ----------
    level : ndarray, shape (m,)
        Each block's noise level (positive).
    dof : ndarray, shape (m,)
        Its degrees of freedom.
    penalty : float
        Per change point, times ``log m``.

    Returns
    -------
    list of int
    """
    cost, pen = _level_cost(level, dof, penalty)
    # no one change point worth half its penalty, no two worth one: one level, no search
    # (a heuristic screen: PELT itself decides whenever there is a hint of a change)
    if cost is None or not hints_a_change(level, dof, penalty, cost):
        return [0]
    return [0, *_pelt(cost, level.size, pen)]


def _level_cost(level: NDArray, dof: NDArray, penalty: float) -> tuple[_Cost | None, float]:
    """The blocks' cost (None: fewer than two blocks, or no positive level) and the
    penalty per change point."""
    m = level.size
    top = float(np.max(level, initial=0.0))
    if m < 2 or not (np.isfinite(top) and top > 0):
        return None, 0.0
    # levels over the largest (no overflow); a level of 0 (a still, quantised stretch) costs
    # as the smallest positive one
    return _Cost(np.maximum(level / top, np.finfo(float).tiny), dof), penalty * np.log(m)


def hints_a_change(
    level: NDArray, dof: NDArray, penalty: float = REGIME_PENALTY, cost: _Cost | None = None
) -> bool:
    """Whether one change point is worth half its penalty, or two worth one: the screen
    :func:`regime_breaks` searches past (a hint of a change, which PELT then decides).

    Parameters
    ----------
    level, dof : ndarray, shape (m,)
        As :func:`regime_breaks`.
    penalty : float
        Per change point, times ``log m``.
    cost : _Cost, optional
        The blocks' cost, if already made.

    Returns
    -------
    bool

    Notes
    -----
    On white noise of one level the gain is under half the penalty in 87-95 % of records
    and under the full penalty in all of 300 (500-1e5 samples); a short rest whose split
    PELT makes on one block grid's phase and not on the next gains 1.4-2x the penalty on
    the grid that does not split it (docs/algorithms.md §F1).
    """
    if cost is None:
        cost, pen = _level_cost(level, dof, penalty)
    else:
        pen = penalty * np.log(level.size)
    return cost is not None and _gain_of_two_splits(cost, level.size) > pen / 2


def _pool(level: NDArray, dof: NDArray) -> tuple[float, float]:
    """The dof-weighted level of blocks and its dof."""
    w = float(np.sum(dof))
    top = float(np.max(level))
    if not top > 0:
        return 0.0, w
    return float(np.sum(dof * level / top) / w) * top, w


def _interval(x: float, nu: float) -> tuple[float, float]:
    return nu * x / float(chi2_ppf(0.975, nu)), nu * x / float(chi2_ppf(0.025, nu))


def find_regimes(
    start: NDArray, stop: NDArray, level: NDArray, dof: NDArray, lsb: float | None = None
) -> tuple[Regime, ...]:
    """The record's regimes from its profile blocks (sample ranges, levels and their dof).

    ``lsb``: the record's grid step (``diagnostics.lsb``), None off a grid.

    Notes
    -----
    The still regimes are the floor (:func:`_floor`): from the lowest regime up, in order
    of level, each regime whose level is consistent with the floor's pooled level so far
    (a one-sided F test at :data:`STILL_ALPHA` per step, its dof divided by the blocks'
    dispersion, :func:`dispersion`) and at most :data:`STILL_RATIO` times the lowest
    regime's upper 95 % bound joins it. One regime is one level: still, as far as the
    record can tell. A regime the test leaves out below that bound is near-still: another
    still level (another posture, slow sway), which the result reports on its own. A flat
    regime (:data:`FLAT_RATIO`: constant samples, a dropout) is neither, and takes no part,
    nor does a regime of fewer than :data:`FLOOR_BLOCKS` blocks at its edge
    (:func:`_not_flat`), nor a floor of such short regimes held on a grid
    (:func:`_supported_floor`). On a grid, regimes held on it
    (each under half a step's error variance, :func:`_floor`) are one still level.
    """
    breaks = regime_breaks(level, dof)
    bounds = [*breaks, level.size]
    spans = list(zip(bounds, bounds[1:], strict=False))
    pooled = [_pool(level[a:b], dof[a:b]) for a, b in spans]
    held = 0.0 if lsb is None else half_a_step(lsb)
    live, floor, cap = _supported_floor(level, dof, spans, pooled, held)
    out = []
    for i, ((a, b), (x, nu)) in enumerate(zip(spans, pooled, strict=True)):
        lo, hi = _interval(x, nu)
        still = i in floor
        near = not still and i in live and x <= cap
        out.append(Regime(int(start[a]), int(stop[b - 1]), x, lo, hi, nu, still, near))
    return tuple(out)


def _supported_floor(
    level: NDArray,
    dof: NDArray,
    spans: list[tuple[int, int]],
    pooled: list[tuple[float, float]],
    held: float,
) -> tuple[list[int], set[int], float]:
    """The regimes that take part, the floor among them (:func:`_floor`) and its cap.

    A floor of held values alone (each regime under ``held``, on a grid) with no regime
    of :data:`FLOOR_BLOCKS` blocks is left out, and the floor is sought again above it.

    Notes
    -----
    A regime of one or two blocks has no block away from its edges. Inside a short hold
    (a calm wind written 0) the residual's span reaches the hold's ends, so one block of
    it reads 1e-3 of the sensor's level on one phase of the block grid, and on another
    the hold is flat or shared with the noise beside it: one sample dropped at the
    record's start makes it the floor or not. As the floor it set the cap and left every
    other stretch out (SURFRAD wind speed: 1 block of 40 still, 33 with 3 samples fewer).
    Held values are no noise level (docs/algorithms.md §E3); a long hold stays the floor
    (BSRN's nights). The regimes left out are neither still nor near-still.
    """
    live = _not_flat(pooled, spans)
    while True:
        cap = _cap([pooled[i] for i in live])
        phi = dispersion(level, dof, [spans[i] for i in live if pooled[i][0] <= cap])
        lows = _floor([(pooled[i][0], pooled[i][1] / phi) for i in live], cap, held)
        floor = {live[j] for j in lows}
        rest = [i for i in live if i not in floor]
        if not rest or not _held_and_short(floor, spans, pooled, held):
            return live, floor, cap
        live = rest


def _held_and_short(
    floor: set[int], spans: list[tuple[int, int]], pooled: list[tuple[float, float]], held: float
) -> bool:
    """Every regime of ``floor`` is held values (under ``held``), none of
    :data:`FLOOR_BLOCKS` blocks."""
    return all(pooled[i][0] < held and spans[i][1] - spans[i][0] < FLOOR_BLOCKS for i in floor)


def _not_flat(pooled: list[tuple[float, float]], spans: list[tuple[int, int]]) -> list[int]:
    """Indices of the regimes that are no flat stretch, nor all edge beside a flat one.

    A flat regime (level at most :data:`FLAT_RATIO` times the highest) is constant samples;
    a regime of fewer than :data:`FLOOR_BLOCKS` blocks beside it is all edge: a block
    straddling the flat one's end, its mean square diluted by the constant samples it
    holds, and one at its other end (MIDC SRRL's temperature between two runs of its
    -7999 code: one regime of 2 blocks, or 2 lone blocks, with the grid's phase). Those
    beside a flat one too when no other is left (a walk held on a grid for hundreds of
    samples at a time, with spikes); all of them when every regime is flat.
    """
    top = max(x for x, _ in pooled)
    flat = {i for i, (x, _) in enumerate(pooled) if x <= FLAT_RATIO * top}
    edge = {i for i, (a, b) in enumerate(spans) if b - a < FLOOR_BLOCKS and flat & {i - 1, i + 1}}
    every = range(len(spans))
    return (
        [i for i in every if i not in flat | edge]
        or [i for i in every if i not in flat]
        or [*every]
    )


def _cap(pooled: list[tuple[float, float]]) -> float:
    """:data:`STILL_RATIO` times the lowest regime's upper 95 % bound: above it, never still.

    The floor is known to its interval: the lowest of many short regimes can sit far below
    the sensor's level by chance (one block of a shifted grid), and twice it is not yet
    motion; a short stretch at twice the floor is not the sensor's still noise.
    """
    low, low_dof = min(pooled)
    return STILL_RATIO * _interval(low, low_dof)[1]


def dispersion(level: NDArray, dof: NDArray, spans: list[tuple[int, int]]) -> float:
    """How much more the blocks' levels scatter inside their regimes than their dof say.

    Each block's log level about its regime's median, squared over its variance
    ``ψ'(ν/2)`` (a log χ²_ν) and by ``B / (B - 1)`` for a regime of ``B`` blocks; the median
    of these over the regimes ``spans`` (those that may be still), over the median of χ²₁:
    a robust quasi-likelihood dispersion (McCullagh & Nelder 1989, §9.2), at least 1. A
    block's dof count its squares as independent, which noise low-passed by the sensor is
    not: there the still regimes' levels differ by more than the dof allow and the F test
    of :func:`_floor` would cut the still stretches apart. A median, so that the blocks at
    a regime's edge, half in the motion beside it, do not count.
    """
    dev = _log_deviations(level, dof, spans)
    if not dev.size:
        return 1.0
    return max(float(np.median(dev) / chi2_ppf(0.5, 1.0)), 1.0)


def dispersion_shown(
    level: NDArray, dof: NDArray, spans: list[tuple[int, int]], alpha: float = 0.05
) -> float:
    """The dispersion of :func:`dispersion` the blocks show: its one-sided ``1 - alpha``
    lower confidence bound, at least 1.

    Notes
    -----
    The median's distribution-free bound: the ``k``-th smallest of the ``m`` deviations,
    ``k`` the largest with ``P(Bin(m, 1/2) <= k - 1) <= alpha`` (none, under 5 deviations:
    1). A few blocks, one half in motion, can read any dispersion (5 blocks of a humidity
    record's still start: 4.7-10.9); over 16-31 blocks a met mast's wind reads 1.45-2.71.
    """
    dev = np.sort(_log_deviations(level, dof, spans))
    m = dev.size
    k = 0
    while k < m and special.bdtr(k, m, 0.5) <= alpha:
        k += 1
    if k == 0:
        return 1.0
    return max(float(dev[k - 1] / chi2_ppf(0.5, 1.0)), 1.0)


def _log_deviations(level: NDArray, dof: NDArray, spans: list[tuple[int, int]]) -> NDArray:
    """:func:`dispersion`'s squared log deviations of the blocks in ``spans``, over their
    variance."""
    dev = [np.empty(0)]
    for a, b in spans:
        if b - a >= 2 and np.all(level[a:b] > 0):
            r = np.log(level[a:b])
            r = r - np.median(r)
            dev.append(r * r / special.polygamma(1, dof[a:b] / 2.0) * (b - a) / (b - a - 1))
    return np.concatenate(dev)


def _floor(pooled: list[tuple[float, float]], cap: float, held: float = 0.0) -> set[int]:
    """Indices of the still regimes among ``pooled`` (level, dof): the record's floor.

    A forward search in order of level: the floor starts as the lowest regime and takes the
    next one while its level is below the ``1 - STILL_ALPHA`` quantile of ``F(ν, ν_floor)``
    times the floor's pooled level, and below ``cap``. Testing against the pooled floor,
    not the lowest regime alone, keeps a long stretch at twice the floor out (its dof make
    the difference plain) where the lowest regime's few dof would let it in. The search
    stops at its first rejection, so each step is tested at the full level, as in a
    fixed-sequence procedure: the motion regimes above are never tested, and how many a
    record has does not change how much evidence it takes to leave a stretch out.

    On a grid, ``held`` is half a step's error variance: the next regime also joins when
    its level is under it (the floor's is then too). Held values read far under the
    rounding error they carry (a night near a grid point ~1e-4 step², one flipping near
    half a step ~0.5): their levels differ by where the signal sits within a step, not by
    what the sensor does (docs/algorithms.md §E3). The levels are block medians, so
    spikes on held values raise no regime to it.
    """
    order = sorted(range(len(pooled)), key=lambda i: pooled[i])
    low, low_dof = pooled[order[0]]
    floor, sx, sw = {order[0]}, low * low_dof, low_dof
    for i in order[1:]:
        x, nu = pooled[i]
        if not (x <= min(sx / sw * _f_quantile(1.0 - STILL_ALPHA, nu, sw), cap) or x < held):
            break
        floor.add(i)
        sx, sw = sx + x * nu, sw + nu
    return floor


def _f_quantile(q: float, nu1: float, nu2: float) -> float:
    """Quantile ``q`` of F(ν1, ν2), as ``scipy.stats.f.ppf``."""
    return float(special.fdtri(nu1, nu2, q))
