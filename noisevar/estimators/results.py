"""Result types of the variance estimators."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf
from noisevar.filters.selection import WindowSelection

if TYPE_CHECKING:
    import pandas as pd

    from noisevar.diagnostics import NoiseDiagnostics


def chi2_interval(variance: float, dof: float, level: float = 0.95) -> tuple[float, float]:
    """Confidence interval of a variance estimate with ``dof`` effective degrees of freedom.

    ``(ν v / χ²_{1-a/2,ν}, ν v / χ²_{a/2,ν})`` (docs/algorithms.md §F4).

    Parameters
    ----------
    variance : float
        The estimate.
    dof : float
        Effective degrees of freedom (> 0).
    level : float
        Confidence level.

    Returns
    -------
    (low, high) : tuple of float
    """
    if not (dof > 0 and np.isfinite(variance)):
        return (float("nan"), float("nan"))
    a = 1.0 - level
    # (ν v / χ²_{1-a/2,ν}, ν v / χ²_{a/2,ν})
    lo = dof * variance / chi2_ppf(1.0 - a / 2.0, dof)
    hi = dof * variance / chi2_ppf(a / 2.0, dof)
    return (float(lo), float(hi))


@dataclass
class SomdDetails:
    """What the dashboard draws for a SOMD estimate.

    Attributes
    ----------
    h_smooth : tuple of float
        Smoothing filter parameters ``h_S`` (several: docs/algorithms.md §A6).
    h_track : float
        Tracking filter parameter ``h_T``.
    smooth_output : ndarray, shape (n_h, n)
        One-step predictions of each smoothing filter (the virtual sensors).
    track_output : ndarray, shape (n,)
        Tracking filter output.
    selection : WindowSelection or None
        Per-window tests (None when selection is off).
    kept_windows : ndarray of bool, shape (n_windows,)
        Windows used (any smoothing ``h`` passing, §A6).
    window_variance : ndarray, shape (n_windows,)
        Variance estimate of each window (NaN where not kept).
    sample_mask : ndarray of bool, shape (n,)
        Samples whose mutual differences entered the estimate.
    bias_factor : tuple of float
        The divisor used for each ``h`` (2 for the paper, ``c(h)`` otherwise).
    skip : int
        Leading samples discarded as the filters' start-up transient.
    """

    h_smooth: tuple[float, ...]
    h_track: float
    smooth_output: NDArray
    track_output: NDArray
    selection: WindowSelection | None
    kept_windows: NDArray
    window_variance: NDArray
    sample_mask: NDArray
    bias_factor: tuple[float, ...]
    skip: int


@dataclass
class VarianceEstimate:
    """One noise-variance estimate.

    Attributes
    ----------
    method : str
        Method name (see :func:`noisevar.methods`).
    variance : float
        Estimated noise variance (signal units squared).
    ci95 : (float, float)
        95 % confidence interval of the variance.
    n_used : int
        Samples that entered the estimate.
    n_total : int
        Samples given (after any dropped non-finite ones).
    dof : float
        Effective degrees of freedom behind ``ci95``.
    params : dict
        The parameters that define the estimate (the JSON config form).
    notes : list of str
        Plain-language remarks (dropped samples, fallbacks taken).
    details : SomdDetails or None
        Arrays for figures (SOMD methods only).
    core_variance : float or None
        Gaussian-equivalent variance of the bulk, outliers left out (for a robust
        filter); None when the method does not separate them.
    outlier_fraction : float
        Share of samples outside the bulk.
    diagnostics : NoiseDiagnostics or None
        What the record's noise looks like (docs/algorithms.md §E1-§E3), with a
        one-sentence verdict.
    assumptions : dict of str to bool
        What the method assumes of the noise, and whether this record satisfies it.
    jumps : ndarray of bool or None
        Samples left out around persistent level jumps (signal, not noise); None for
        methods that do not look for jumps.
    """

    method: str
    variance: float
    ci95: tuple[float, float]
    n_used: int
    n_total: int
    dof: float
    params: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    details: SomdDetails | None = None
    core_variance: float | None = None
    outlier_fraction: float = 0.0
    diagnostics: NoiseDiagnostics | None = None
    assumptions: dict[str, bool] = field(default_factory=dict)
    jumps: NDArray | None = field(default=None, repr=False)

    @property
    def std(self) -> float:
        """Noise standard deviation, ``sqrt(variance)``."""
        return float(np.sqrt(self.variance)) if self.variance >= 0 else float("nan")

    @property
    def relative_halfwidth(self) -> float:
        """Half the CI width over the estimate (a quick precision figure)."""
        return float((self.ci95[1] - self.ci95[0]) / 2.0 / self.variance)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (no arrays)."""
        return {
            "method": self.method,
            "variance": float(self.variance),
            "std": self.std,
            "ci95": [float(self.ci95[0]), float(self.ci95[1])],
            "n_used": int(self.n_used),
            "n_total": int(self.n_total),
            "dof": float(self.dof),
            "params": dict(self.params),
            "notes": list(self.notes),
            "core_variance": None if self.core_variance is None else float(self.core_variance),
            "outlier_fraction": float(self.outlier_fraction),
            "assumptions": dict(self.assumptions),
            "diagnostics": None if self.diagnostics is None else self.diagnostics.to_dict(),
        }


@dataclass
class RedundantEstimate:
    """Noise variances of several real sensors of the same quantity (docs/algorithms.md §A1).

    Attributes
    ----------
    variances : ndarray, shape (k,)
        Each sensor's noise variance (three-cornered hat for k >= 3).
    ci95 : ndarray, shape (k, 2)
        Approximate 95 % intervals.
    pair_sums : ndarray, shape (k, k)
        ``1/2 E[(ΔZi - ΔZj)²] = var_i + var_j`` for each pair (eq. [8]).
    n_used : int
        Samples per sensor.
    notes : list of str
        Remarks (e.g. a negative solution clipped to zero).
    """

    variances: NDArray
    ci95: NDArray
    pair_sums: NDArray
    n_used: int
    notes: list[str] = field(default_factory=list)

    @property
    def stds(self) -> NDArray:
        """Each sensor's noise standard deviation, ``sqrt(variances)``."""
        return np.sqrt(self.variances)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        return {
            "variances": self.variances.tolist(),
            "ci95": self.ci95.tolist(),
            "pair_sums": self.pair_sums.tolist(),
            "n_used": self.n_used,
            "notes": list(self.notes),
        }


@dataclass
class VarianceEstimates:
    """Noise-variance estimates of many channels (``estimate(Z, axis=...)`` on N-D input).

    Attributes
    ----------
    method : str
        Method name.
    shape : tuple of int
        Channel shape: the input's shape without the sample axis.
    estimates : list of VarianceEstimate
        One per channel, in C order (index with ``result[i, j]`` or iterate).
    params : dict
        The parameters shared by every channel (the config form).
    """

    method: str
    shape: tuple[int, ...]
    estimates: list[VarianceEstimate]
    params: dict[str, Any] = field(default_factory=dict)

    def _array(self, values: list[Any]) -> NDArray:
        arr = np.asarray(values, dtype=float)
        return arr.reshape(self.shape + arr.shape[1:])

    @property
    def variance(self) -> NDArray:
        """Variances, shape ``shape``."""
        return self._array([e.variance for e in self.estimates])

    @property
    def std(self) -> NDArray:
        """Standard deviations, shape ``shape``."""
        return self._array([e.std for e in self.estimates])

    @property
    def ci95(self) -> NDArray:
        """95 % intervals of the variance, shape ``shape + (2,)``."""
        return self._array([e.ci95 for e in self.estimates])

    @property
    def n_used(self) -> NDArray:
        """Samples used per channel, shape ``shape``."""
        return self._array([e.n_used for e in self.estimates]).astype(int)

    def __len__(self) -> int:
        return len(self.estimates)

    def __iter__(self) -> Iterator[VarianceEstimate]:
        return iter(self.estimates)

    def __getitem__(self, index: int | tuple[int, ...]) -> VarianceEstimate:
        """The estimate of one channel (a flat index, or one index per channel axis)."""
        if isinstance(index, tuple):
            index = int(np.ravel_multi_index(index, self.shape))
        return self.estimates[index]

    def to_frame(self) -> pd.DataFrame:
        """One row per channel: variance, std, ci95, counts, dof, core, flags and verdict."""
        import pandas as pd

        idx = list(np.ndindex(*self.shape)) if self.shape else [()]
        rows = [
            {
                "channel": i if len(i) != 1 else i[0],
                "variance": e.variance,
                "std": e.std,
                "ci95_low": e.ci95[0],
                "ci95_high": e.ci95[1],
                "n_used": e.n_used,
                "n_total": e.n_total,
                "dof": e.dof,
                "core_variance": e.core_variance,
                "outlier_fraction": e.outlier_fraction,
                **({} if e.diagnostics is None else e.diagnostics.flags),
                "verdict": None if e.diagnostics is None else e.diagnostics.verdict,
            }
            for i, e in zip(idx, self.estimates, strict=True)
        ]
        return pd.DataFrame(rows)
