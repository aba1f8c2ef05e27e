"""Held values on a grid: how often noise of a level repeats itself (docs/algorithms.md §E3).

White noise of variance ``v`` read on a grid of step ``Δ`` stays on one grid value from one
sample to the next only so often; a stretch whose samples hold one value far more often
than that is not that noise (a padded log end, a stale sensor, a logger's hold).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import special

#: "Mostly": held values are over this share of the second differences a level rests on.
HELD_MOST = 0.5
#: One-sided tail beyond which a held share is not what the noise gives (a 95 % interval's).
HELD_TAIL = 0.025
#: Over this many grid steps² of variance the offset within a step no longer matters and
#: Sheppard's rounding (Δ²/12, independent of the noise) reads the share to 1e-4.
WIDE_STEPS2 = 4.0
#: Grid values either side of the noise's centre summed where it is narrower.
_K = 24


@dataclass(frozen=True)
class HeldShare:
    """Second differences of 0 on a grid, against those white noise of a level gives.

    Attributes
    ----------
    held, count : int
        Second differences within half a step of 0, and all of them.
    noise : float
        The share white noise of the level gives (:func:`flat_share`), at most.
    step : float
        The grid step it is given on (:func:`moved_step`).
    """

    held: int
    count: int
    noise: float
    step: float

    @property
    def share(self) -> float:
        """The held share ``held / count``."""
        return self.held / self.count if self.count else 0.0

    @property
    def beyond_noise(self) -> bool:
        """Mostly held (over :data:`HELD_MOST`) and over the noise's share beyond its
        one-sided :data:`HELD_TAIL` (a binomial on every third second difference, which
        share no sample: independent under white noise)."""
        n = self.count // 3
        k = int(np.floor(self.share * n))
        tail = float(special.bdtrc(k - 1, n, self.noise)) if n and k else 1.0
        return bool(self.share > HELD_MOST and tail < HELD_TAIL)


def flat_share(variance: float, lsb: float) -> float:
    """The share of second differences of 0 that white Gaussian noise, of variance
    ``variance`` as read on a grid of step ``lsb``, gives at most.

    Parameters
    ----------
    variance : float
        The noise's variance as the rounded samples read it (``Var(q(x))``).
    lsb : float
        The grid step.

    Returns
    -------
    float
        ``P(q_1 - 2 q_2 + q_3 = 0)`` at the offset that holds most (the noise centred on a
        grid value), 1 when ``variance`` is 0.

    Notes
    -----
    docs/algorithms.md §E3 *Held values*. Second differences, not repeats: a trend moves
    every sample of a held stretch off its value and leaves its second differences at 0.
    Wide noise (over :data:`WIDE_STEPS2` steps²): the samples are the noise plus an
    independent rounding error of Δ²/12, so the second difference has variance 6v and the
    share is Δ's worth of its density at 0, ``Δ / sqrt(12 π v)``. Narrower: the rounded
    noise's own distribution, its σ found so that it reads ``variance``.
    """
    if not variance > 0.0:
        return 1.0
    r = variance / (lsb * lsb)
    if r >= WIDE_STEPS2:
        return float(min(1.0, 1.0 / np.sqrt(12.0 * np.pi * r)))
    lo, hi = 0.0, np.sqrt(r) + 1.0
    for _ in range(60):  # the rounded variance grows with σ
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _rounded_variance(mid) < r else (lo, mid)
    return _flat(_pmf(0.5 * (lo + hi)))


def held_share(pieces: list[NDArray], variance: float, lsb: float) -> HeldShare:
    """The held share of ``pieces`` (samples on a grid of step ``lsb``) against noise of
    ``variance`` on the grid they move on (:func:`flat_share`, :func:`moved_step`)."""
    d1 = [np.diff(np.asarray(p, dtype=float)) for p in pieces if len(p) >= 3]
    d2 = np.concatenate([np.diff(d) for d in d1]) if d1 else np.empty(0)
    flat = np.abs(d2) < 0.5 * lsb
    step = moved_step(d1, lsb)
    return HeldShare(int(np.count_nonzero(flat)), int(d2.size), flat_share(variance, step), step)


def moved_step(d1: list[NDArray], lsb: float) -> float:
    """The coarsest grid step the pieces' first differences ``d1`` allow: their smallest
    move off the held difference (at least ``lsb``).

    Notes
    -----
    The held difference is the median first difference where the second difference is 0
    (0, or a trend's step). A sensor whose grid is coarser than the written one (GENEActiv's
    light, 19.2 lux steps written as whole lux: ``lsb`` 1) holds values as noise on its
    own grid does; its smallest move, 19, is that grid. Coarser is the safe side: the
    share :func:`flat_share` gives only grows with the step.
    """
    both = [(d[1:], np.abs(np.diff(d)) < 0.5 * lsb) for d in d1 if d.size >= 2]
    held = np.concatenate([d[f] for d, f in both]) if both else np.empty(0)
    if not held.size:
        return lsb
    moves = np.abs(np.concatenate(d1) - np.median(held))
    moves = moves[moves >= 0.5 * lsb]
    return float(max(lsb, moves.min())) if moves.size else lsb


def _pmf(s: float) -> NDArray:
    """Grid values -_K .. _K's probabilities for noise of σ = ``s`` steps centred on 0."""
    if s <= 0.0:
        return (np.arange(-_K, _K + 1) == 0).astype(float)
    edges = (np.arange(-_K, _K + 2) - 0.5) / s
    return np.diff(special.ndtr(edges))


def _rounded_variance(s: float) -> float:
    """The variance (steps²) of noise of σ = ``s`` steps rounded to the grid, centred."""
    k = np.arange(-_K, _K + 1)
    return float(np.sum(k * k * _pmf(s)))


def _flat(p: NDArray) -> float:
    """``P(a - 2b + c = 0)`` for independent a, b, c of probabilities ``p`` (-_K .. _K)."""
    pairs = np.convolve(p, p)  # a + c, from -2 _K
    return float(np.sum(p * pairs[::2]))
