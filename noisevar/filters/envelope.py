"""Envelope-based noise amplitude (docs/algorithms.md §A3) and the h-range scan (§A4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.filters.abg import abg_filter, check_h, settling_samples, stable_h_limit

#: The paper's band for the smoothed-over-raw noise amplitude ratio, eq. [14].
RATIO_BAND = (1.0 / 20.0, 1.0 / 10.0)


def detrend_windows(x: ArrayLike, window: int) -> NDArray:
    """Subtract each window's least-squares line (windows of ``window`` samples).

    The record is cut into ``n // window`` whole windows (a trailing partial
    window is dropped). Vectorised over windows.

    Parameters
    ----------
    x : array_like, shape (n,)
        Samples.
    window : int
        Window length ``m``.

    Returns
    -------
    ndarray, shape (n_windows, window)
        Deviations of each window from its own fitted line.
    """
    x = np.asarray(x, dtype=float)
    n_win = x.shape[-1] // window
    w = x[..., : n_win * window].reshape(*x.shape[:-1], n_win, window)
    i = np.arange(1, window + 1, dtype=float)
    ic = i - i.mean()
    mean = w.mean(axis=-1, keepdims=True)
    slope = (w * ic).sum(axis=-1, keepdims=True) / (ic**2).sum()
    return w - mean - slope * ic


def envelopes(x: ArrayLike) -> tuple[NDArray, NDArray]:
    """Upper and lower envelopes through the local maxima and minima (docs/algorithms.md §A3).

    Parameters
    ----------
    x : array_like, shape (n,)
        Samples.

    Returns
    -------
    upper, lower : ndarray, shape (n,)
        Linear interpolation of the local maxima (minima) onto every sample;
        the first and last samples count as extrema so both ends are defined.
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    if n < 3:
        return x.copy(), x.copy()
    mid = x[1:-1]
    is_max = np.concatenate([[True], (mid > x[:-2]) & (mid >= x[2:]), [True]])
    is_min = np.concatenate([[True], (mid < x[:-2]) & (mid <= x[2:]), [True]])
    idx = np.arange(n)
    upper = np.interp(idx, idx[is_max], x[is_max])
    lower = np.interp(idx, idx[is_min], x[is_min])
    return upper, lower


@dataclass
class WindowAmplitude:
    """Envelope noise amplitude per window (eq. [13]).

    Attributes
    ----------
    window : int
        Window length ``m``.
    upper, lower : ndarray, shape (n_windows * m,)
        Envelopes of the window-detrended samples.
    amplitude : ndarray, shape (n_windows,)
        ``|V| = sum(U_k - L_k) / (2 m)`` in each window.
    """

    window: int
    upper: NDArray
    lower: NDArray
    amplitude: NDArray

    @property
    def mean_amplitude(self) -> float:
        """Mean ``|V|`` over all windows."""
        return float(np.mean(self.amplitude)) if self.amplitude.size else float("nan")


def noise_amplitude(x: ArrayLike, window: int = 40) -> WindowAmplitude:
    """Envelope noise amplitude of eq. [13] in windows of ``window`` samples.

    Each window is first detrended by its least-squares line (our choice: the
    paper applies [13] to the raw samples, where a trend or curvature
    inflates ``U - L``), then the envelopes of the detrended record are taken.

    Parameters
    ----------
    x : array_like, shape (n,)
        Samples.
    window : int
        Window length ``m`` (at least 4).

    Returns
    -------
    WindowAmplitude
    """
    if int(window) < 4:
        raise NoisevarError(f"window must be at least 4 samples, got {window}")
    window = int(window)
    dev = detrend_windows(x, window)
    if dev.shape[0] == 0:
        raise NoisevarError(
            f"the signal has fewer samples than one window ({window}): "
            "give a longer signal or a smaller window"
        )
    flat = dev.ravel()
    upper, lower = envelopes(flat)
    amp = (upper - lower).reshape(dev.shape).sum(axis=-1) / (2.0 * window)
    return WindowAmplitude(window=window, upper=upper, lower=lower, amplitude=amp)


@dataclass
class HScan:
    """Result of the h-range scan of eq. [14].

    Attributes
    ----------
    h : ndarray
        The log-spaced grid of ``h``.
    ratio : ndarray
        ``|V1| / |V2|``: envelope amplitude of the smoothed signal over that
        of the raw signal, for each ``h``.
    band : tuple of float
        ``(1/20, 1/10)``.
    h_min, h_max : float
        Range of ``h`` whose ratio lies in the band (NaN if none).
    h_chosen : float
        The grid ``h`` whose ratio is closest (in log) to the band's
        geometric centre; the default ``h_smooth``.
    """

    h: NDArray
    ratio: NDArray
    band: tuple[float, float]
    h_min: float
    h_max: float
    h_chosen: float

    def to_dict(self) -> dict:
        """JSON-ready form."""
        return {
            "h": self.h.tolist(),
            "ratio": self.ratio.tolist(),
            "band": list(self.band),
            "h_min": self.h_min,
            "h_max": self.h_max,
            "h_chosen": self.h_chosen,
        }


def scan_h(
    z: ArrayLike,
    window: int = 40,
    h_grid: ArrayLike | None = None,
    band: tuple[float, float] = RATIO_BAND,
) -> HScan:
    """Scan the smoothing ``h`` and find the range of eq. [14].

    For every ``h`` of the grid the signal is smoothed (one ``lfilter`` pass
    each), the start-up transient is dropped, and the envelope amplitude of
    the smoothed signal is divided by that of the raw signal over the same
    samples.

    Parameters
    ----------
    z : array_like, shape (n,)
        Samples.
    window : int
        Window length used by the envelope amplitude.
    h_grid : array_like, optional
        Grid of ``h`` (default 41 points from 1e-9 to 1e-1, log-spaced).
    band : (float, float)
        Ratio band, default ``(1/20, 1/10)``.

    Returns
    -------
    HScan
    """
    z = np.asarray(z, dtype=float)
    if h_grid is None:
        h_grid = np.logspace(-9, -1, 41)
    h_grid = np.asarray([check_h(h) for h in np.atleast_1d(h_grid)])
    if h_grid.max() >= stable_h_limit():  # pragma: no cover - check_h refuses first
        raise NoisevarError("h grid reaches the unstable range")
    ratio = np.full(h_grid.shape, np.nan)
    if z.size < 2 * window:
        raise NoisevarError(
            f"the signal has fewer samples ({z.size}) than two windows ({2 * window}): "
            "give a longer signal or a smaller window"
        )
    # window amplitudes of the raw record once; each h averages the windows after its transient
    raw_amp = noise_amplitude(z, window).amplitude
    starts = np.arange(raw_amp.size) * window
    for j, h in enumerate(h_grid):
        after = starts >= min(settling_samples(h), z.size // 2)
        if not after.any() or raw_amp[after].mean() <= 0:
            continue
        smooth_amp = noise_amplitude(abg_filter(z, h), window).amplitude
        ratio[j] = smooth_amp[after].mean() / raw_amp[after].mean()
    inside = (ratio >= band[0]) & (ratio <= band[1])
    if np.any(inside):
        h_min, h_max = float(h_grid[inside].min()), float(h_grid[inside].max())
    else:
        h_min = h_max = float("nan")
    centre = np.sqrt(band[0] * band[1])
    finite = np.isfinite(ratio) & (ratio > 0)
    if not np.any(finite):
        raise NoisevarError("the h scan found no usable ratio: the signal is too short or constant")
    dist = np.where(finite, np.abs(np.log(np.where(finite, ratio, 1.0) / centre)), np.inf)
    h_chosen = float(h_grid[int(np.argmin(dist))])
    return HScan(h=h_grid, ratio=ratio, band=band, h_min=h_min, h_max=h_max, h_chosen=h_chosen)
