"""GPS latency: the delay between two records of the same motion (docs/algorithms.md §C).

A GPS speed reaches the avionics late. The total delay is a measurable part
plus an unknown part (eq. (11)); the method takes a coarse least-squares
delay over shifts (refined below one sample), the unknown part per segment,
and a random-constant Kalman filter over the segments.

Submodules: :mod:`~noisevar.systems.latency.scenario` (:func:`simulate_latency`),
:mod:`~noisevar.systems.latency.delay` (:func:`estimate_delay`,
:func:`align_signals`, :func:`segment_delays`),
:mod:`~noisevar.systems.latency.run` (:func:`random_constant_kalman`,
:func:`run_latency`).

Notes
-----
A positive delay means the second record lags the first. The cost removes the
mean difference by default (``remove_bias=True``); the filter's observation
variance is each segment's Gauss-Newton variance unless ``observation_std_s``
is given.
"""

from noisevar.systems.latency.delay import (
    CURVATURE_HALFWIDTH,
    MIN_OVERLAP,
    DelayEstimate,
    SegmentDelays,
    align_signals,
    estimate_delay,
    segment_delays,
)
from noisevar.systems.latency.run import LatencyResult, random_constant_kalman, run_latency
from noisevar.systems.latency.scenario import (
    KNOT_MS,
    LatencyRecord,
    LatencyScenario,
    evaluate_speed,
    simulate_latency,
    speed_profile,
)

__all__ = [
    "CURVATURE_HALFWIDTH",
    "KNOT_MS",
    "MIN_OVERLAP",
    "DelayEstimate",
    "LatencyRecord",
    "LatencyResult",
    "LatencyScenario",
    "SegmentDelays",
    "align_signals",
    "estimate_delay",
    "evaluate_speed",
    "random_constant_kalman",
    "run_latency",
    "segment_delays",
    "simulate_latency",
    "speed_profile",
]
