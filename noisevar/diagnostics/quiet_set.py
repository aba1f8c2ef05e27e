"""The quiet set of a level profile's blocks: its seed, its rounds, its pooled level.

The blocks of the still regimes whose mean square is consistent with their pooled level
(docs/algorithms.md §E1 *The still set*); :func:`~noisevar.diagnostics.profile.profile_from_blocks`
runs them.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf
from noisevar.diagnostics.regimes import Regime

#: At most this many rounds of the quiet set, each testing mean squares with the kurtosis
#: of the last round's other blocks.
QUIET_ROUNDS = 5


def still_if_quiet(
    regimes: tuple[Regime, ...], start: NDArray, stop: NDArray, quiet: NDArray
) -> tuple[Regime, ...]:
    """``regimes``, a still one with no quiet block no longer called still.

    The quiet set is the still regimes' blocks that pass the quiet test: a still regime
    none of whose blocks does has no sensor level to quote, so the regimes and the quiet
    set agree (docs/algorithms.md §E1 *The still set*). A record of one still level keeps
    it (its level does not vary).
    """
    if all(r.still for r in regimes):
        return regimes
    return tuple(
        r
        if not r.still or quiet[(start >= r.start) & (stop <= r.stop)].any()
        else replace(r, still=False)
        for r in regimes
    )


def gaussian_seed(
    still: NDArray,
    count: NDArray,
    var: NDArray,
    robust: NDArray,
    robust_dof: NDArray,
    eta: float,
    level: float,
) -> NDArray:
    """The quiet set's seed: the still blocks whose mean square Gaussian noise explains.

    Each still block's mean square is tested against the still regimes' pooled robust
    level with the dof of Gaussian noise (``n_b / η``, family-wise): a forward search from
    a clean set (docs/algorithms.md §F1), used where the record has motion. A block with
    handling or a tap in part of it stays out of the seed, so its tails cannot widen the
    rounds' tests; tails spread over the record (heavy-tailed noise) enter through the
    rounds' kurtosis of the set. A record of one still level has no motion to hand on:
    its excess mean squares are the noise's tails, and the seed is the wider one.
    """
    nu = count / eta
    floor = pooled(robust, robust_dof, still)
    return still & (var <= floor * chi2_ppf(level, nu) / nu)


def leave_one_out_dof(
    count: NDArray,
    robust: NDArray,
    tails: tuple[NDArray, NDArray, NDArray],
    members: NDArray,
    eta: float,
    fallback: NDArray,
) -> NDArray:
    """Each block's mean-square dof with the noise kurtosis of the other ``members`` blocks.

    A burst of motion inside one block does not widen its own test; tails spread over the
    record (heavy-tailed noise) stay in the other blocks' kurtosis. The kurtosis is taken
    on one scale for the set, not on each block's own level, which a spike raises.
    """
    k2, k4, d = tails
    inside = members.astype(float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # one scale for the set (its levels agree): Σ e² / S and Σ e⁴ / S², S its top level
        w = robust / np.max(robust[members], initial=0.0)
        k2, k4 = k2 * w, k4 * w * w
        n = np.sum(count * inside) - count * inside
        m2 = (np.sum(k2 * inside) - k2 * inside) / n
        m4 = (np.sum(k4 * inside) - k4 * inside) / n
        u = d / np.sqrt(np.dot(d, d))
        # κ_v = 3 + (κ_e - 3) / Σ u⁴   (as kurtosis_from_moments)
        kurt = np.maximum(3.0 + (m4 / m2**2 - 3.0) / np.sum(u**4), 1.0)
        # ν = n_b / (η + (κ - 3) / 2)   (docs/algorithms.md §E1)
        dof = count / (eta + np.maximum(kurt - 3.0, 0.0) / 2.0)
    return np.where(np.isfinite(dof) & (m2 > 0), dof, fallback)


def quiet_set(still: NDArray, var: NDArray, dof: NDArray, var_q: NDArray, seed: NDArray) -> NDArray:
    """The still regimes' blocks whose mean square is consistent with their pooled level.

    A block with motion in part of it keeps a low median (so it sits in a still regime)
    but not a low mean square: it leaves the set when its mean square is above a high
    quantile (``var_q``: each block's ``χ²(ν)/ν`` quantile, family-wise) of the set's
    pooled mean square. Rounds from ``seed`` until the set stays the same (at most
    :data:`QUIET_ROUNDS`); no order of blocks enters, so time runs either way.
    """
    quiet = seed.copy()
    for _ in range(QUIET_ROUNDS):
        again = still & (var <= pooled(var, dof, quiet) * var_q)
        if np.array_equal(again, quiet) or not again.any():
            break
        quiet = again
    return quiet


def pooled(x: NDArray, nu: NDArray, members: NDArray) -> float:
    """The dof-weighted level of the ``members`` blocks; 0 when there is none.

    Running sums of the levels over the largest (no overflow of huge levels), added one
    block after another in block order (a running sum from 0: the additions a loop over
    the blocks makes, at once).
    """
    top = float(np.max(x, initial=0.0))
    scale = top if np.isfinite(top) and top > 0 else 1.0
    idx = np.flatnonzero(members)
    w = np.asarray(nu, dtype=float)[idx]
    sx = float(np.cumsum(np.r_[0.0, w * (x / scale)[idx]])[-1])
    sw = float(np.cumsum(np.r_[0.0, w])[-1])
    return sx / sw * scale if sw > 0 else 0.0
