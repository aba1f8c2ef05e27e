"""Our SOMD estimator as an R-adaptation strategy (docs/algorithms.md §A7, §A8)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.strategies.base import RStrategy, check_window, diag_matrix

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter
    from noisevar.kalman.model import StateSpaceModel


class SomdOnlineR(RStrategy):
    """Our SOMD estimator over a trailing window of each channel (docs/algorithms.md §A7, §A8).

    Every ``every`` steps the variance of each measured channel is estimated
    from its last ``window`` raw samples (the current one included) with
    :func:`noisevar.estimate` (``method``, ``h_smooth`` per channel,
    ``select=False``), independently of the filter's state, so a lagging
    filter cannot corrupt it (the point of the 2016 paper). Until a channel
    has enough samples for its smoothing filter to settle, its nominal ``R``
    is kept.

    Channels listed in the model's ``angle_measurements`` are unwrapped
    before estimating (a heading that turns through ±π is a continuous
    signal to the estimator).

    :func:`~noisevar.kalman.run_filter` gives the whole record to
    :meth:`prepare`, which computes the same estimates for every run and
    re-estimation step at once (one ``lfilter`` call per channel), instead
    of ``B · m`` separate calls per re-estimation; the two paths agree to
    rounding (tested).

    Parameters
    ----------
    h_smooth : float or sequence of float
        Smoothing ``h`` per channel (one value for all).
    window : int, optional
        Trailing window length (default: all samples so far).
    every : int
        Re-estimation interval ``N`` in steps.
    method : {"somd", "somd-paper"}
        Bias-corrected SOMD (default) or the paper's factor 1/2.
    """

    name = "somd-online"

    def __init__(
        self,
        h_smooth: float | ArrayLike = 9e-4,
        window: int | None = None,
        every: int = 100,
        method: str = "somd",
    ) -> None:
        if method not in ("somd", "somd-paper"):
            raise NoisevarError(f"method must be 'somd' or 'somd-paper', got {method!r}")
        self.method = method
        self.h_smooth = np.atleast_1d(np.asarray(h_smooth, dtype=float))
        self.window = None if window is None else check_window(window)
        self.every = check_window(every, "every")
        self._schedule: NDArray | None = None
        if method == "somd-paper":
            self.name = "somd-paper-online"

    def _h(self, m: int) -> NDArray:
        if self.h_smooth.size == 1:
            return np.repeat(self.h_smooth, m)
        if self.h_smooth.size != m:
            raise NoisevarError(
                f"h_smooth has {self.h_smooth.size} values but the model measures {m} channels"
            )
        return self.h_smooth

    def _bounds(self, k: int) -> tuple[int, int]:
        start = 0 if self.window is None else max(0, k + 1 - self.window)
        return start, k + 1

    def prepare(self, z: NDArray, model: StateSpaceModel) -> None:
        from noisevar.estimators.somd import somd_variance_windows

        B, N, m = z.shape
        hs = self._h(m)
        zc = _unwrap_channels(z, model.angle_measurements, axis=1)
        steps = np.arange(self.every - 1, N, self.every)
        est = np.full((B, steps.size, m), np.nan)
        for j in range(m):
            bounds = [self._bounds(int(k)) for k in steps]
            est[:, :, j] = somd_variance_windows(
                zc[:, :, j], bounds, float(hs[j]), paper=self.method == "somd-paper"
            )
        self._schedule_steps = steps
        self._schedule = est
        self._prepared_shape = (B, N, m)

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        B, m = filt.batch_size, filt.m
        self._hs = self._h(m)
        self._var = np.repeat(np.diag(filt.model.R)[None], B, axis=0)
        self._Rmat = diag_matrix(self._var)
        self._angles = list(filt.model.angle_measurements)
        # a schedule from prepare() serves the one filter that run_filter starts next
        self._active = (
            self._schedule
            if self._schedule is not None and (self._prepared_shape[0] == B)
            else None
        )
        self._schedule = None
        self._history: list[NDArray] = []
        self._n_est = 0

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        k = filt.k
        if self._active is None:
            self._history.append(np.array(filt.z))
        if (k + 1) % self.every == 0:
            if self._active is not None:
                new = self._active[:, self._n_est]
            else:
                new = self._estimate_from_history(k)
            self._n_est += 1
            ok = np.isfinite(new) & (new > 0)
            if ok.any():
                self._var = np.where(ok, new, self._var)
                self._Rmat = diag_matrix(self._var)
        return self._guard_dead(self._Rmat)

    def _estimate_from_history(self, k: int) -> NDArray:
        from noisevar.estimators import estimate

        start, stop = self._bounds(k)
        zw = np.stack(self._history[start:stop], axis=1)  # (B, L, m)
        zw = _unwrap_channels(zw, self._angles, axis=1)
        B, _, m = zw.shape
        out = np.full((B, m), np.nan)
        for b in range(B):
            for j in range(m):
                try:
                    out[b, j] = estimate(
                        zw[b, :, j], method=self.method, h_smooth=float(self._hs[j]), select=False
                    ).variance
                except NoisevarError:
                    pass  # too few samples for this channel's filter to settle yet
        return out


def _unwrap_channels(z: NDArray, channels: Any, axis: int) -> NDArray:
    channels = list(channels)
    if not channels:
        return z
    z = np.array(z)
    z[..., channels] = np.unwrap(z[..., channels], axis=axis)
    return z
