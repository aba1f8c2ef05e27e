"""The simulated flight: speed profile, delays and the two records (docs/algorithms.md §C)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

#: One knot in metres per second.
KNOT_MS = 0.514444

#: Fewest reference samples a shift may be compared on.
MIN_OVERLAP = 16


@dataclass(frozen=True)
class LatencyScenario:
    """Parameters of the paper's simulated flight (section 3).

    Parameters
    ----------
    duration_s : float
        Record length (paper: 550 s).
    rate_hz : float
        Sample rate of both records (10 Hz).
    speed_min_kn, speed_max_kn : float
        Ground speed range (paper: 110-170 kn).
    unknown_delay_s : float
        The unknown, constant part of the delay (transport receiver-to-server).
    measurable_delay_s : float
        Mean of the measurable part (timestamp and scheduler intervals).
    measurable_jitter_s : float
        The measurable part is uniform in ``measurable_delay_s ± jitter`` and
        changes once per segment. 0 gives a fixed total delay.
    segment_s : float
        Length of one segment: the measurable part is constant inside it, and
        the estimator makes one coarse delay estimate per segment.
    ahrs_noise_std : float
        White noise on the inertial speed (m/s).
    gps_noise_std : float
        White noise on the GPS speed (m/s).
    ahrs_bias : float
        Constant offset of the inertial speed (m/s).
    level_hold_s : tuple of float
        Range of the time between speed changes (s).
    ramp_s : tuple of float
        Range of the duration of one speed change (s).
    """

    duration_s: float = 550.0
    rate_hz: float = 10.0
    speed_min_kn: float = 110.0
    speed_max_kn: float = 170.0
    unknown_delay_s: float = 0.2
    measurable_delay_s: float = 0.1
    measurable_jitter_s: float = 0.05
    segment_s: float = 30.0
    ahrs_noise_std: float = 0.05
    gps_noise_std: float = 0.1
    ahrs_bias: float = 0.0
    level_hold_s: tuple[float, float] = (10.0, 40.0)
    ramp_s: tuple[float, float] = (8.0, 25.0)

    @property
    def mean_delay_s(self) -> float:
        """Mean total delay, measurable plus unknown (s)."""
        return self.measurable_delay_s + self.unknown_delay_s

    def validate(self) -> None:
        """Raise :class:`NoisevarError` when a parameter is out of range."""
        if not (self.duration_s > 0 and self.rate_hz > 0):
            raise NoisevarError(
                f"duration_s={self.duration_s} and rate_hz={self.rate_hz} must both be "
                "positive; give a record length in seconds and a sample rate in Hz."
            )
        if not 0 < self.speed_min_kn <= self.speed_max_kn:
            raise NoisevarError(
                f"speed range {self.speed_min_kn}-{self.speed_max_kn} kn is invalid; "
                "give 0 < speed_min_kn <= speed_max_kn."
            )
        if self.measurable_jitter_s < 0 or self.measurable_delay_s < self.measurable_jitter_s:
            raise NoisevarError(
                f"measurable part {self.measurable_delay_s} ± {self.measurable_jitter_s} s "
                "would go negative; give 0 <= measurable_jitter_s <= measurable_delay_s."
            )
        if self.unknown_delay_s < 0:
            raise NoisevarError(
                f"unknown_delay_s={self.unknown_delay_s} is negative; a transport delay is >= 0 s."
            )
        longest = self.measurable_delay_s + self.measurable_jitter_s + self.unknown_delay_s
        if longest >= self.duration_s / 4:
            raise NoisevarError(
                f"a delay of up to {longest:g} s is too long for a {self.duration_s:g} s "
                "record (it must be under a quarter of the record); shorten the delay or "
                "lengthen the record."
            )
        if not 0 < self.segment_s <= self.duration_s:
            raise NoisevarError(
                f"segment_s={self.segment_s} must be in (0, duration_s={self.duration_s}]."
            )
        if self.ahrs_noise_std < 0 or self.gps_noise_std < 0:
            raise NoisevarError("noise standard deviations must be >= 0.")
        for name in ("level_hold_s", "ramp_s"):
            lo, hi = getattr(self, name)
            if not 0 < lo <= hi:
                raise NoisevarError(f"{name}={(lo, hi)} must satisfy 0 < low <= high.")


@dataclass(frozen=True)
class LatencyRecord:
    """Two simulated records of one flight's speed, the second one late.

    Attributes
    ----------
    time : ndarray, shape (n,)
        Sample times (s).
    true_speed : ndarray, shape (n,)
        True ground speed at ``time`` (m/s).
    reference : ndarray, shape (n,)
        Inertial (AHRS) speed: on time, noisy.
    delayed : ndarray, shape (n,)
        GPS speed as used by the avionics: ``speed(t - delay) + noise``.
    true_delay : ndarray, shape (n,)
        Total delay of each GPS sample (s).
    measurable_delay : ndarray, shape (n,)
        The measurable part of ``true_delay`` (known to the estimator).
    unknown_delay_s : float
        The constant unknown part.
    sample_period : float
        Sample period ``T`` (s).
    segment_length : int
        Samples per segment of constant measurable delay.
    scenario : LatencyScenario
        The parameters that made this record.
    """

    time: NDArray[np.float64]
    true_speed: NDArray[np.float64]
    reference: NDArray[np.float64]
    delayed: NDArray[np.float64]
    true_delay: NDArray[np.float64]
    measurable_delay: NDArray[np.float64]
    unknown_delay_s: float
    sample_period: float
    segment_length: int
    scenario: LatencyScenario


def _cosine_ramp(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """0 before 0, 1 after 1, a smooth (C1) half-cosine between."""
    xc = np.clip(x, 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * xc))


def speed_profile(
    scenario: LatencyScenario, rng: np.random.Generator
) -> tuple[float, NDArray[np.float64]]:
    """Draw a random piecewise-smooth speed history within the scenario's range.

    The speed holds a level, then ramps (half-cosine, continuous slope) to a
    new level drawn uniformly in ``[speed_min_kn, speed_max_kn]``, and so on.
    Being analytic, it can be evaluated at any time, in particular at
    ``t - delay`` (see :func:`evaluate_speed`).

    Returns
    -------
    start_speed : float
        Initial speed (m/s).
    ramps : ndarray, shape (3, m)
        One column per speed change: start time (s), duration (s), step (m/s).
    """
    lo, hi = scenario.speed_min_kn * KNOT_MS, scenario.speed_max_kn * KNOT_MS
    level = float(rng.uniform(lo, hi))
    start_speed = level
    starts, durations, steps = [], [], []
    t = 0.5 * rng.uniform(*scenario.level_hold_s)
    while t < scenario.duration_s:
        duration = rng.uniform(*scenario.ramp_s)
        new_level = rng.uniform(lo, hi)
        starts.append(t)
        durations.append(duration)
        steps.append(new_level - level)
        level = new_level
        t += duration + rng.uniform(*scenario.level_hold_s)
    ramps = np.array([starts, durations, steps], dtype=float).reshape(3, -1)
    return start_speed, ramps


def evaluate_speed(
    start_speed: float, ramps: NDArray[np.float64], t: ArrayLike
) -> NDArray[np.float64]:
    """Speed of a :func:`speed_profile` history at times ``t`` (any shape)."""
    starts, durations, steps = ramps
    x = (np.asarray(t, dtype=float)[..., None] - starts) / durations
    return start_speed + _cosine_ramp(x) @ steps


def simulate_latency(scenario: LatencyScenario | None = None, seed: int = 0) -> LatencyRecord:
    """Simulate the paper's flight: an on-time AHRS speed and a late GPS speed.

    Parameters
    ----------
    scenario : LatencyScenario, optional
        Parameters; the default is the paper's scenario (section 3).
    seed : int
        Seed of the random generator (speed history, delays, noises).

    Returns
    -------
    LatencyRecord
        Both records, the true and measurable delays per sample.

    Raises
    ------
    NoisevarError
        When a parameter is out of range, e.g. a delay longer than the record.
    """
    scenario = scenario or LatencyScenario()
    scenario.validate()
    rng = np.random.default_rng(seed)
    period = 1.0 / scenario.rate_hz
    n = int(round(scenario.duration_s * scenario.rate_hz))
    segment_length = max(1, int(round(scenario.segment_s * scenario.rate_hz)))
    if n < 4 * MIN_OVERLAP:
        raise NoisevarError(
            f"{n} samples is too short a record; give at least {4 * MIN_OVERLAP} samples "
            "(a longer duration_s or a higher rate_hz)."
        )
    time = np.arange(n) * period
    start_speed, ramps = speed_profile(scenario, rng)
    n_segments = -(-n // segment_length)
    measurable_per_segment = scenario.measurable_delay_s + rng.uniform(
        -scenario.measurable_jitter_s, scenario.measurable_jitter_s, n_segments
    )
    measurable = np.repeat(measurable_per_segment, segment_length)[:n]
    true_delay = measurable + scenario.unknown_delay_s
    true_speed = evaluate_speed(start_speed, ramps, time)
    reference = true_speed + scenario.ahrs_bias + scenario.ahrs_noise_std * rng.standard_normal(n)
    delayed = evaluate_speed(start_speed, ramps, time - true_delay)
    delayed = delayed + scenario.gps_noise_std * rng.standard_normal(n)
    return LatencyRecord(
        time=time,
        true_speed=true_speed,
        reference=reference,
        delayed=delayed,
        true_delay=true_delay,
        measurable_delay=measurable,
        unknown_delay_s=float(scenario.unknown_delay_s),
        sample_period=period,
        segment_length=segment_length,
        scenario=scenario,
    )
