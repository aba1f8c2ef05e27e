"""The Kalman fit's Gaussian assumption checked on its innovations, and its robust interval
(docs/algorithms.md §E6).

The maximum-likelihood fit assumes Gaussian noise. Its point estimate stays consistent when
the noise is not Gaussian (a quasi-likelihood: the innovations' second moments are right),
but the Gaussian information then misstates the estimate's spread. The interval is the
sandwich ``H^-1 J H^-1`` of the observed information ``H`` and the scores' long-run
covariance ``J`` (batch means over blocks), right for any noise with a finite fourth moment,
with bootstrap-t quantiles for the skew a few glitches give; a note says when the
innovations are heavy-tailed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.stats
from numpy.typing import ArrayLike, NDArray

from noisevar.estimators.interval import tail_index, tails_shape, unreliable_tail
from noisevar.noise_model._steady import FilterPass


def innovation_kurtosis(nu: NDArray) -> float:
    """Kurtosis of the standardised innovations ``nu`` (3 for Gaussian noise)."""
    peak = float(np.max(np.abs(nu))) if nu.size else 0.0
    if not peak > 0.0 or not np.isfinite(peak):
        return 3.0
    x = (nu / peak) ** 2  # scale-free: keep the fourth powers in range
    m2 = float(np.mean(x))
    return float(np.mean(x * x) / m2**2) if m2 > 0 else 3.0


#: Step in ln h of the central differences.
STEP = 1e-3
#: Bootstrap resamples of the scores' blocks for the intervals' quantiles.
RESAMPLES = 999
#: The bootstrap's seed: one record, one interval (in Python, the CLI and the page).
SEED = 26
#: Resamples drawn at once (bounds the memory: 8 bytes x this x the number of blocks).
CHUNK = 64
#: Most blocks the scores are summed over (longer blocks beyond).
MAX_BLOCKS = 1000
#: Fewest blocks the bootstrap-t runs on; below, Student-t quantiles on blocks - 1 dof.
MIN_BLOCKS = 50
#: The intervals' tail probabilities (95 %).
TAILS = (0.025, 0.975)


def information_and_scores(fps: list[FilterPass], log_r: float) -> tuple[NDArray, NDArray]:
    """Observed information of ``(ln h, ln r)`` and the per-sample scores.

    Parameters
    ----------
    fps : list of FilterPass
        The unit-r filter at ``ln h - STEP``, ``ln h``, ``ln h + STEP``.
    log_r : float

    Returns
    -------
    info : ndarray (2, 2)
        Central differences in ``ln h``, analytic in ``ln r``.
    scores : ndarray (n, 2)
        ``∂l_k/∂ln h`` (central differences of ``l_k``) and ``∂l_k/∂ln r = (ν_k² - 1)/2``.
    """
    w = np.exp(-log_r)
    # -2 l_k (constants dropped) at ln h - d, ln h, ln h + d
    terms = [np.log(fp.s) + w * fp.innovations**2 / fp.s for fp in fps]
    sums = [float(np.sum(t)) for t in terms]
    g = [w * float(np.sum(fp.innovations**2 / fp.s)) for fp in fps]
    huu = -0.5 * (sums[2] - 2 * sums[1] + sums[0]) / STEP**2
    huv = 0.5 * (g[2] - g[0]) / (2 * STEP)
    info = np.array([[-huu, -huv], [-huv, 0.5 * g[1]]])
    nu2 = w * fps[1].innovations ** 2 / fps[1].s
    return info, np.column_stack([-(terms[2] - terms[0]) / (4 * STEP), 0.5 * (nu2 - 1.0)])


def block_sums(scores: NDArray) -> NDArray:
    """Centred per-sample scores summed over consecutive blocks (rows: blocks).

    Notes
    -----
    Blocks of ``floor(4 (n/100)^(2/9)) + 1`` samples (Newey and West's lag count, plus
    one), longer on a long record so that there are at most :data:`MAX_BLOCKS` (the
    bootstrap's cost stays bounded). A glitch moves the innovations after it too, so the
    squared innovations are correlated over the filter's memory and per-sample (outer
    product) sums would understate the scores' long-run covariance on a fast filter. The
    scores are centred (their sum is 0 at the maximum; elsewhere, for given or ALS
    parameters, their spread is what counts).
    """
    n = scores.shape[0]
    size = max(int(np.floor(4.0 * (n / 100.0) ** (2.0 / 9.0))) + 1, -(-n // MAX_BLOCKS))
    starts = np.arange(0, n, size)
    return np.add.reduceat(scores - scores.mean(axis=0), starts, axis=0)


@dataclass(frozen=True)
class RobustCovariance:
    """Sandwich covariance of a log-parameter estimate, with its bootstrap-t calibration.

    Attributes
    ----------
    cov : ndarray (p, p)
        ``H^-1 J H^-1``, ``J`` the block sums' covariance (batch means).
    theta : ndarray (B, p)
        One-step estimates ``H^-1 sum(blocks*)`` of resampled blocks (none: too few blocks).
    covs : ndarray (B, p, p)
        Each resample's own sandwich.
    dof : float
        Degrees of freedom of the Student-t quantiles used without resamples.
    """

    cov: NDArray
    theta: NDArray
    covs: NDArray
    dof: float = np.inf

    def interval(self, centre: float, c: ArrayLike) -> tuple[float, float]:
        """95 % interval of ``exp(c · θ)`` around ``exp(centre)``: bootstrap-t quantiles of
        ``c · θ*`` over its own standard error, times the record's standard error."""
        c = np.asarray(c, dtype=float)
        var = float(c @ self.cov @ c)
        if not np.isfinite(var) or var <= 0:
            return (float("nan"), float("nan"))
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.theta @ c) / np.sqrt(np.einsum("i,bij,j->b", c, self.covs, c))
        t = t[np.isfinite(t)]
        q_lo, q_hi = np.quantile(t, TAILS) if t.size else scipy.stats.t.ppf(TAILS, self.dof)
        se = np.sqrt(var)
        with np.errstate(over="ignore", under="ignore"):  # an unidentified term: (0, inf)
            return (float(np.exp(centre - q_hi * se)), float(np.exp(centre - q_lo * se)))


def sandwich(info: NDArray, scores: NDArray) -> RobustCovariance:
    """Robust covariance ``H^-1 J H^-1`` of the estimate and its bootstrap-t calibration.

    Parameters
    ----------
    info : ndarray (p, p)
        Observed information ``H`` (minus the log-likelihood's Hessian).
    scores : ndarray (n, p)
        Per-sample derivatives of the log-likelihood.

    Returns
    -------
    RobustCovariance

    Raises
    ------
    numpy.linalg.LinAlgError
        If ``H`` is singular.

    Notes
    -----
    For Gaussian noise ``J ≈ H`` and the covariance is the Gaussian ``H^-1``; with noise of
    kurtosis ``κ`` the variance of ``ln r`` grows about ``(κ - 1) / 2``-fold. A few glitches
    make ``r`` a mean of a few large squares, skewed, whose estimated spread is small
    exactly where few glitches fell: the quantiles of the studentised one-step estimate
    over :data:`RESAMPLES` resamples of the blocks (moving-block bootstrap-t, seeded)
    replace ±1.96. With fewer than :data:`MIN_BLOCKS` blocks (a short record) a resample
    of them is too coarse (its spread can vanish): Student-t quantiles on ``blocks - 1``
    dof, batch means' own.
    """
    inv = np.linalg.inv(info)
    b = block_sums(scores)
    m, p = b.shape
    cov = inv @ (b.T @ b) @ inv
    if m < MIN_BLOCKS:  # batch means: the studentised sum has about m - 1 dof
        return RobustCovariance(cov, np.empty((0, p)), np.empty((0, p, p)), float(m - 1))
    moments = np.hstack([b, (b[:, :, None] * b[:, None, :]).reshape(m, p * p)])
    rng = np.random.default_rng(SEED)
    theta, covs = [], []
    for k in range(0, RESAMPLES, CHUNK):
        size = min(CHUNK, RESAMPLES - k)
        # a resample of the blocks as counts: its sums and outer products in one product
        picks = rng.integers(0, m, (size, m)) + m * np.arange(size)[:, None]
        counts = np.bincount(picks.ravel(), minlength=size * m).reshape(size, m)
        sums = counts.astype(float) @ moments
        total = sums[:, :p]
        spread = sums[:, p:].reshape(-1, p, p) - total[:, :, None] * total[:, None, :] / m
        theta.append(total @ inv.T)
        covs.append(inv @ spread @ inv)
    return RobustCovariance(cov, np.concatenate(theta), np.concatenate(covs))


def tails_note(nu: NDArray) -> tuple[str | None, float, str]:
    """The note on innovations whose tails are not Gaussian (None: Gaussian enough), their
    kurtosis and their shape.

    Parameters
    ----------
    nu : ndarray
        Standardised innovations of the fitted filter.

    Returns
    -------
    note : str or None
    kurtosis : float
    shape : {"gaussian", "heavy", "light"}
        :func:`~noisevar.estimators.interval.tails_shape`, the one rule.

    Notes
    -----
    Heavy tails: the fit's Gaussian intervals would be too narrow (the robust ones are
    given). Light tails (a sine, a square wave, quantised or uniform noise): r's
    Gaussian interval is on the safe side, but the noise is not Gaussian noise.
    """
    kurt = innovation_kurtosis(nu)
    shape = tails_shape(nu.size, kurt)
    if shape == "light":
        return (
            f"the innovations are light-tailed (kurtosis {kurt:.3g} over {nu.size} samples; "
            "Gaussian noise gives 3): the noise is not Gaussian but bounded, like quantisation "
            "(uniform: 1.8) or a periodic disturbance (a sine: 1.5, a square wave: 1); r is "
            "its variance and the intervals are not overconfident, but a periodic part is "
            "signal a filter could model rather than noise"
        ), kurt, shape
    if shape != "heavy":
        return None, kurt, shape
    alpha = tail_index(nu)
    unreliable = (
        f"; their tail index {alpha:.1f} is too low for a finite fourth moment (or a few "
        "glitches of one size): even the robust interval is unreliable"
        if unreliable_tail(alpha)
        else ""
    )
    return (
        f"the innovations are heavy-tailed (kurtosis {kurt:.3g}; Gaussian noise gives 3): the "
        "fit's Gaussian assumption is broken, and r counts the outlying samples (glitches, "
        "bursts) as noise, which may hold most of it; the intervals are the robust (sandwich) "
        f"ones{unreliable}. Check the estimate's core variance, and gate the outliers or use "
        "a robust filter"
    ), kurt, shape
