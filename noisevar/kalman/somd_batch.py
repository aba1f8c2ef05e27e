"""SOMD without window selection over many windows and runs at once.

:class:`~noisevar.kalman.strategies.SomdOnlineR` re-estimates every channel
of every Monte Carlo run every ``N`` steps. Calling :func:`noisevar.estimate`
for each (run, channel, window) costs about 1 ms of Python overhead per call;
this module computes the very same numbers (``method="somd"`` or
``"somd-paper"``, ``select=False``) with one ``lfilter`` pass per window
start for all runs, and cumulative sums for all windows that share a start
(a growing window's filter output is a prefix of the longer one's, because
the steady-state initial condition depends only on the first samples). A
test checks it against :func:`noisevar.estimate` to rounding.

The estimate, spec A7/A8 (paper eq. [8]) with the virtual sensor ``Z1`` the
alpha-beta-gamma one-step prediction and ``Z2`` the raw samples::

    var = mean_{k >= skip} (ΔZ1 - ΔZ2)_k² / c

``c = 2`` (paper) or ``c(h)`` (bias-corrected); ``skip`` is the settling
length of the smoothing and the tracking filter (``h_T = 30 h_S``, the
estimator's default), as in :func:`noisevar.estimators.somd_estimate`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from noisevar.filters.abg import abg_filter, check_h, settling_samples, somd_bias_factor

#: The estimator's defaults that decide when a window is long enough.
TRACK_RATIO = 30.0
MIN_WINDOWS = 2
WINDOW = 40


def somd_variance_windows(
    z: NDArray, bounds: Sequence[tuple[int, int]], h: float, paper: bool = False
) -> NDArray:
    """SOMD variance (no selection) of ``z[:, start:stop]`` for every window and run.

    Parameters
    ----------
    z : ndarray, shape (B, N)
        One channel of ``B`` runs.
    bounds : sequence of (start, stop)
        Windows (``stop`` exclusive).
    h : float
        Smoothing ``h_S``.
    paper : bool
        Factor 2 (paper) instead of ``c(h)``.

    Returns
    -------
    ndarray, shape (B, len(bounds))
        Variances; NaN where a window is too short for the filter to settle
        (where :func:`noisevar.estimate` would refuse it).
    """
    h = check_h(h, "h_smooth")
    ht = check_h(h * TRACK_RATIO, "h_track")
    skip = max(settling_samples(h), settling_samples(ht))
    factor = 2.0 if paper else somd_bias_factor(h)
    z = np.asarray(z, dtype=float)
    B = z.shape[0]
    out = np.full((B, len(bounds)), np.nan)
    by_start: dict[int, list[int]] = {}
    for i, (start, stop) in enumerate(bounds):
        if stop - start - skip >= MIN_WINDOWS * WINDOW:
            by_start.setdefault(int(start), []).append(i)
    for start, idx in by_start.items():
        stop_max = max(bounds[i][1] for i in idx)
        seg = z[:, start:stop_max]
        smooth = abg_filter(seg, h, axis=-1)
        sq = (np.diff(smooth, axis=-1) - np.diff(seg, axis=-1)) ** 2
        csum = np.concatenate([np.zeros((B, 1)), np.cumsum(sq, axis=-1)], axis=-1)
        for i in idx:
            n = bounds[i][1] - start
            out[:, i] = (csum[:, n - 1] - csum[:, skip]) / (n - 1 - skip) / factor
    return out


def somd_variance_records(z: NDArray, h: float, paper: bool = False) -> NDArray:
    """SOMD variance (no selection) of every whole record of a batch at once.

    The same number as ``noisevar.estimate(z[b], method="somd" | "somd-paper",
    h_smooth=h, select=False).variance`` for each run ``b`` (the same
    filter, differences and mean, in one ``lfilter`` pass over all runs
    instead of ``B`` calls), e.g. for the paper's Table 1 over 100 Monte
    Carlo runs.

    Parameters
    ----------
    z : ndarray, shape (B, N)
        One channel of ``B`` runs.
    h : float
        Smoothing ``h_S``.
    paper : bool
        Factor 2 (paper) instead of ``c(h)``.

    Returns
    -------
    ndarray, shape (B,)
        Variances; all NaN when the records are too short for the filters
        to settle (where :func:`noisevar.estimate` refuses them: call it for
        its message).
    """
    h = check_h(h, "h_smooth")
    ht = check_h(h * TRACK_RATIO, "h_track")
    skip = max(settling_samples(h), settling_samples(ht))
    factor = 2.0 if paper else somd_bias_factor(h)
    z = np.asarray(z, dtype=float)
    B, n = z.shape
    if n - skip < MIN_WINDOWS * WINDOW or not np.all(np.isfinite(z)):
        return np.full(B, np.nan)
    smooth = abg_filter(z, h, axis=-1)
    mutual = np.diff(smooth, axis=-1) - np.diff(z, axis=-1)  # ΔZ1 - ΔZ2
    # the estimator's mean over the settled samples (one contiguous row per run)
    return (mutual[:, skip:] ** 2).mean(axis=1) / factor
