"""The κ study: paired Huber/EKF RMSE ratios with and without outliers (docs/algorithms.md §B3)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.systems.base import as_list
from noisevar.systems.robust.filters import PAPER_KAPPA, RobustResult, run_robust
from noisevar.systems.robust.scenario import RobustData


def paired_rmse_ratio(
    mse_a: NDArray[np.float64],
    mse_b: NDArray[np.float64],
    n_boot: int = 2000,
    seed: int = 0,
    coverage: float = 0.95,
) -> tuple[float, float, float]:
    """RMSE ratio ``a / b`` of two filters on the same runs, with a paired bootstrap interval.

    ``ratio = sqrt(Σ mse_a / Σ mse_b)``; the interval resamples *runs*
    (the same indices for both filters, so the noise they share cancels).

    Parameters
    ----------
    mse_a, mse_b : ndarray, shape (B,)
        Per-run mean squared errors of the two filters on the same runs.
    n_boot : int
        Bootstrap resamples.
    seed : int
        Seed of the resampling.
    coverage : float
        Probability of the two-sided percentile interval.

    Returns
    -------
    (ratio, low, high) : tuple of float
        With a single run the interval is undefined: ``low = high = nan``.
    """
    a = np.asarray(mse_a, dtype=float)
    b = np.asarray(mse_b, dtype=float)
    if a.shape != b.shape or a.ndim != 1 or a.size < 1:
        raise NoisevarError(
            f"paired_rmse_ratio needs two non-empty per-run MSE vectors of the same length, "
            f"got shapes {a.shape} and {b.shape}."
        )
    if int(n_boot) < 1 or not 0 < coverage < 1:
        raise NoisevarError("n_boot must be >= 1 and coverage in (0, 1).")
    if a.size == 1:
        return float(np.sqrt(a.sum() / b.sum())), float("nan"), float("nan")
    idx = np.random.default_rng(seed).integers(0, a.size, (int(n_boot), a.size))
    boot = np.sqrt(a[idx].sum(axis=1) / b[idx].sum(axis=1))
    tail = 100.0 * (1.0 - coverage) / 2.0
    lo, hi = np.percentile(boot, [tail, 100.0 - tail])
    return float(np.sqrt(a.sum() / b.sum())), float(lo), float(hi)


@dataclass(frozen=True)
class KappaTradeoff:
    """Huber/EKF position-RMSE ratios over ``κ``, with and without outliers.

    Attributes
    ----------
    kappa : ndarray, shape (k,)
    ratio_outliers, ratio_clean : ndarray, shape (k,)
        Huber RMSE / plain-EKF RMSE on the same runs.
    ci_outliers, ci_clean : ndarray, shape (k, 2)
        Paired bootstrap intervals of those ratios.
    rmse_huber_outliers, rmse_huber_clean : ndarray, shape (k,)
        Huber position RMSE (m).
    rmse_ekf_outliers, rmse_ekf_clean : float
        Plain-EKF position RMSE (m).
    magvar_estimate_deg : ndarray, shape (k,)
        Mean over runs of the Huber filter's final ``α`` (with outliers).
    runs : int
        Runs pooled per ratio.
    coverage : float
    """

    kappa: NDArray[np.float64]
    ratio_outliers: NDArray[np.float64]
    ci_outliers: NDArray[np.float64]
    ratio_clean: NDArray[np.float64]
    ci_clean: NDArray[np.float64]
    rmse_huber_outliers: NDArray[np.float64]
    rmse_huber_clean: NDArray[np.float64]
    rmse_ekf_outliers: float
    rmse_ekf_clean: float
    magvar_estimate_deg: NDArray[np.float64]
    runs: int
    coverage: float

    def meets(self, with_outliers: float = 0.7, without: float = 0.01) -> NDArray[np.bool_]:
        """Which ``κ`` meet both targets on the point estimates."""
        return (self.ratio_outliers <= with_outliers) & (np.abs(self.ratio_clean - 1) <= without)

    def meets_with_confidence(
        self, with_outliers: float = 0.7, without: float = 0.01
    ) -> NDArray[np.bool_]:
        """Which ``κ`` meet both targets over their whole intervals."""
        return (self.ci_outliers[:, 1] <= with_outliers) & (
            np.abs(self.ci_clean - 1).max(axis=1) <= without
        )


def kappa_tradeoff(
    noisy: RobustData | Sequence[RobustData],
    clean: RobustData | Sequence[RobustData],
    kappas: Sequence[float] = (PAPER_KAPPA, 1.5, 2.0, 2.5, 3.0),
    iterations: int = 10,
    n_boot: int = 2000,
    seed: int = 0,
    coverage: float = 0.95,
    known: Mapping[float, tuple[RobustResult, RobustResult]] | None = None,
) -> KappaTradeoff:
    """The κ trade-off: Huber/EKF RMSE ratios with and without outliers.

    Every ``κ`` runs on the same records, so the ratios are paired
    (:func:`paired_rmse_ratio`). Several batches (for example several
    seeds) are pooled run by run.

    Parameters
    ----------
    noisy, clean : RobustData or list of RobustData
        Records with outliers and without (same lengths of lists).
    kappas : sequence of float
        Huber thresholds.
    iterations : int
        IRLS iterations.
    n_boot, seed, coverage
        Bootstrap of the intervals.
    known : mapping of float to (RobustResult, RobustResult), optional
        Results already computed for one batch (``noisy`` and ``clean``
        single records), by ``κ``: each pair must hold ``"ekf"`` and
        ``"huber"``; saves re-running them.

    Returns
    -------
    KappaTradeoff
    """
    noisy_l = as_list(noisy, RobustData, "noisy")
    clean_l = as_list(clean, RobustData, "clean")
    if len(noisy_l) != len(clean_l):
        raise NoisevarError("give as many clean records as noisy ones.")
    ks = np.asarray(list(kappas), dtype=float)
    if ks.size == 0 or not np.all(ks > 0):
        raise NoisevarError(f"kappas={list(kappas)}: give positive Huber thresholds.")
    known = dict(known or {})
    if known and len(noisy_l) > 1:
        raise NoisevarError("known results only go with a single noisy/clean batch.")

    ekf_n, ekf_c = [], []
    for nd, cd in zip(noisy_l, clean_l, strict=True):
        if known:
            base_n, base_c = next(iter(known.values()))
        else:
            base_n = run_robust(nd, filters=("ekf",))
            base_c = run_robust(cd, filters=("ekf",))
        ekf_n.append(base_n.position_mse_per_run("ekf"))
        ekf_c.append(base_c.position_mse_per_run("ekf"))
    en, ec = np.concatenate(ekf_n), np.concatenate(ekf_c)
    rows = []
    for k in ks:
        a, b, mv = _huber_mse(float(k), noisy_l, clean_l, iterations, known)
        rows.append(
            (
                paired_rmse_ratio(a, en, n_boot, seed, coverage),
                paired_rmse_ratio(b, ec, n_boot, seed, coverage),
                float(np.sqrt(a.mean())),
                float(np.sqrt(b.mean())),
                mv,
            )
        )
    return KappaTradeoff(
        kappa=ks,
        ratio_outliers=np.array([r[0][0] for r in rows]),
        ci_outliers=np.array([r[0][1:] for r in rows]),
        ratio_clean=np.array([r[1][0] for r in rows]),
        ci_clean=np.array([r[1][1:] for r in rows]),
        rmse_huber_outliers=np.array([r[2] for r in rows]),
        rmse_huber_clean=np.array([r[3] for r in rows]),
        rmse_ekf_outliers=float(np.sqrt(en.mean())),
        rmse_ekf_clean=float(np.sqrt(ec.mean())),
        magvar_estimate_deg=np.array([r[4] for r in rows]),
        runs=int(en.size),
        coverage=float(coverage),
    )


def _huber_mse(
    k: float,
    noisy_l: list[RobustData],
    clean_l: list[RobustData],
    iterations: int,
    known: Mapping[float, tuple[RobustResult, RobustResult]],
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """Per-run Huber MSE with and without outliers, pooled, and the mean final ``α`` (deg)."""
    hn, hc, mv = [], [], []
    for nd, cd in zip(noisy_l, clean_l, strict=True):
        if k in known:
            rn, rc = known[k]
        else:
            rn = run_robust(nd, kappa=k, iterations=iterations, filters=("huber",))
            rc = run_robust(cd, kappa=k, iterations=iterations, filters=("huber",))
        hn.append(rn.position_mse_per_run("huber"))
        hc.append(rc.position_mse_per_run("huber"))
        mv.append(rn.magvar_estimate_deg)
    return np.concatenate(hn), np.concatenate(hc), float(np.mean(np.concatenate(mv)))
