"""The latency method: coarse delay, segments, random-constant filter (docs/algorithms.md §C)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import steps
from noisevar.systems.base import BatchResult
from noisevar.systems.latency.delay import (
    DelayEstimate,
    SegmentDelays,
    estimate_delay,
    segment_delays,
)
from noisevar.systems.latency.scenario import LatencyRecord


def random_constant_kalman(
    observations: ArrayLike,
    observation_variance: ArrayLike,
    process_variance: float = 1e-8,
    initial_variance: float = 1.0,
    initial_estimate: float = 0.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Scalar Kalman filter of a random constant (section 2.2.2).

    ``x[n+1] = x[n] + w`` (``var w = process_variance``),
    ``z[n] = x[n] + v`` (``var v = observation_variance[n]``). An observation
    with infinite variance leaves the estimate unchanged. Works on the last
    axis, so a batch of Monte Carlo runs is filtered at once.

    Parameters
    ----------
    observations : array_like, shape (..., s)
        ``z[n]`` = coarse delay minus measurable delay, one per segment.
    observation_variance : array_like, broadcastable to ``observations``
        ``var v[n]``.
    process_variance : float
        ``var w``; small for a constant that may drift slowly.
    initial_variance, initial_estimate : float
        Prior of the unknown delay.

    Returns
    -------
    estimate, variance : ndarray, shape (..., s)
        Filtered estimate after each observation and its variance.
    """
    z = np.asarray(observations, dtype=float)
    r = np.broadcast_to(np.asarray(observation_variance, dtype=float), z.shape)
    if process_variance < 0 or not initial_variance > 0:
        raise NoisevarError(
            "process_variance must be >= 0 and initial_variance > 0 for the random-constant filter."
        )
    if np.any(r < 0) or np.any(np.isnan(r)):
        raise NoisevarError("observation variances must be >= 0 (inf to skip a segment).")
    B, s = int(np.prod(z.shape[:-1])), z.shape[-1]
    one = np.ones((1, 1))  # F = H = 1
    q = np.full((1, 1), float(process_variance))
    x = np.full((B, 1), float(initial_estimate))
    p = np.full((B, 1, 1), float(initial_variance))
    estimates = np.empty((B, s))
    variances = np.empty((B, s))
    zs = z.reshape(B, s)
    rs = r.reshape(B, s)
    for j in range(s):  # the filter's time loop is inherent
        x, p = steps.predict(x, p, one, q)
        # an observation with infinite variance (or none) adds nothing: K = 0
        finite = (np.isfinite(rs[:, j]) & np.isfinite(zs[:, j]))[:, None]
        R = np.where(finite, rs[:, j : j + 1], 1.0)[:, :, None]
        _, _, _, K = steps.gain(p, one, R)
        K = np.where(finite[:, :, None], K, 0.0)
        d = np.where(finite, steps.innovation(zs[:, j : j + 1], x), 0.0)
        # the short form P = (1 - K) P of the scalar filter
        x, p = steps.update(x, p, d, K, one, R, joseph=False)
        estimates[:, j] = x[:, 0]
        variances[:, j] = p[:, 0, 0]
    return estimates.reshape(z.shape), variances.reshape(z.shape)


@dataclass(frozen=True)
class LatencyResult(BatchResult):
    """Every step of the latency method on one record, with what a figure needs.

    Attributes
    ----------
    record : LatencyRecord
        The input records (and the truth).
    coarse : DelayEstimate
        Whole-record least-squares delay: the "fixed compensation".
    segments : SegmentDelays
        Coarse delay of each segment.
    segment_time : ndarray, shape (s,)
        Start time of each segment (s).
    segment_measurable_s : ndarray, shape (s,)
        Measurable part of each segment (s), known.
    segment_true_delay_s : ndarray, shape (s,)
        True total delay of each segment (s), for scoring.
    unknown_observed_s : ndarray, shape (s,)
        ``coarse - measurable`` per segment: the filter's observations.
    unknown_filtered_s, unknown_filtered_var : ndarray, shape (s,)
        Random-constant Kalman estimate of the unknown part and its variance.
    total_filtered_s : ndarray, shape (s,)
        Measurable part plus filtered unknown part: the final delay, eq. (11).
    estimated_delay_s : float
        Final estimate of the mean total delay: the last filtered unknown part
        plus the mean measurable part.
    true_delay_s : float
        Mean true total delay.
    residual_none_s, residual_fixed_s, residual_filtered_s, residual_coarse_s : float
        RMS over segments of the delay left after no compensation, a fixed
        compensation (``coarse.delay_s``), the filtered compensation, and the
        per-segment coarse estimate without filtering.
    """

    record: LatencyRecord
    coarse: DelayEstimate
    segments: SegmentDelays
    segment_time: NDArray[np.float64]
    segment_measurable_s: NDArray[np.float64]
    segment_true_delay_s: NDArray[np.float64]
    unknown_observed_s: NDArray[np.float64]
    unknown_filtered_s: NDArray[np.float64]
    unknown_filtered_var: NDArray[np.float64]
    total_filtered_s: NDArray[np.float64]
    estimated_delay_s: float
    true_delay_s: float
    residual_none_s: float
    residual_fixed_s: float
    residual_filtered_s: float
    residual_coarse_s: float
    settings: dict = field(default_factory=dict)

    @property
    def runs(self) -> int:
        """Number of runs: one record."""
        return 1

    @property
    def label(self) -> str:
        """``"latency"``."""
        return "latency"


def _rms(x: NDArray[np.float64]) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def run_latency(
    record: LatencyRecord,
    max_delay_s: float = 2.0,
    process_noise_std_s: float = 1e-4,
    observation_std_s: float | None = None,
    remove_bias: bool = True,
) -> LatencyResult:
    """Run the paper's method on a record: coarse, split, filter (eqs. (11), 2.2.2).

    Parameters
    ----------
    record : LatencyRecord
        From :func:`simulate_latency` (or built from real data with the same
        fields; ``true_delay`` is used only for scoring).
    max_delay_s : float
        Largest delay searched (s).
    process_noise_std_s : float
        Standard deviation of the random-constant filter's drift per segment.
    observation_std_s : float, optional
        Constant observation standard deviation (the paper's fixed ``R``).
        Default: each segment's own Gauss-Newton variance.
    remove_bias : bool
        As in :func:`estimate_delay`.

    Returns
    -------
    LatencyResult
    """
    if process_noise_std_s < 0:
        raise NoisevarError(f"process_noise_std_s={process_noise_std_s} must be >= 0.")
    if observation_std_s is not None and not observation_std_s > 0:
        raise NoisevarError(f"observation_std_s={observation_std_s} must be positive.")
    period = record.sample_period
    coarse = estimate_delay(record.reference, record.delayed, period, max_delay_s, remove_bias)
    segments = segment_delays(
        record.reference, record.delayed, record.segment_length, period, max_delay_s, remove_bias
    )
    starts = segments.start_index
    n = record.reference.size
    ends = np.minimum(starts + record.segment_length, n)
    sums = np.add.reduceat(record.measurable_delay, starts)
    measurable = sums / (ends - starts)
    true_delay = np.add.reduceat(record.true_delay, starts) / (ends - starts)
    observed = segments.delay_s - measurable
    variance = (
        segments.variance_s2
        if observation_std_s is None
        else np.where(np.isfinite(segments.variance_s2), observation_std_s**2, np.inf)
    )
    # A diffuse, causal prior (1 s^2 around 0): the first informative segment
    # takes over, as in the paper, which starts from the first observation.
    unknown, unknown_var = random_constant_kalman(
        observed,
        variance,
        process_variance=process_noise_std_s**2,
        initial_variance=1.0,
        initial_estimate=0.0,
    )
    total = measurable + unknown
    finite = np.isfinite(segments.variance_s2)
    coarse_residual = (
        _rms(true_delay[finite] - segments.delay_s[finite]) if finite.any() else float("nan")
    )
    return LatencyResult(
        record=record,
        coarse=coarse,
        segments=segments,
        segment_time=record.time[starts],
        segment_measurable_s=measurable,
        segment_true_delay_s=true_delay,
        unknown_observed_s=observed,
        unknown_filtered_s=unknown,
        unknown_filtered_var=unknown_var,
        total_filtered_s=total,
        estimated_delay_s=float(unknown[-1] + np.mean(record.measurable_delay)),
        true_delay_s=float(np.mean(record.true_delay)),
        residual_none_s=_rms(true_delay),
        residual_fixed_s=_rms(true_delay - coarse.delay_s),
        residual_filtered_s=_rms(true_delay - total),
        residual_coarse_s=coarse_residual,
        settings={
            "max_delay_s": max_delay_s,
            "process_noise_std_s": process_noise_std_s,
            "observation_std_s": observation_std_s,
            "remove_bias": remove_bias,
        },
    )
