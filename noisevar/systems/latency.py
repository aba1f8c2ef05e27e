"""GPS latency: the delay between two records of the same motion.

Spec C, seed ``gps-latency-avionics.txt``. A GPS speed (or heading) reaches the
avionics late. The paper splits the total delay into a part the system can
measure (timestamps and scheduler intervals, eqs. (7)-(10)) and an unknown part
(transport from the receiver to the server), eq. (11)::

    delay = delay_measurable + delay_unknown                            (11)

and estimates it in three steps:

1. **coarse delay by least squares over shifts** (section 2.1): shift the GPS
   sequence against the inertial (AHRS) sequence and keep the shift that
   minimises the sum of squared differences. We refine the minimum below one
   sample with a parabola through the costs at the best shift and its two
   neighbours (spec C);
2. **unknown part** ``z = coarse - measurable`` (section 2.2.2);
3. **random-constant Kalman filter** over successive segments of the record,
   ``x[n+1] = x[n] + w``, ``z[n] = x[n] + v`` (section 2.2.2); the total delay
   is the measurable part plus the filtered unknown part.

Choices the paper leaves open, stated here:

* The cost at each shift is the mean squared difference over one *fixed* set
  of reference samples (so every shift is compared on the same data), with the
  mean of the difference removed by default (``remove_bias=True``): a constant
  offset between the two sensors (an AHRS speed bias) then does not move the
  minimum. ``remove_bias=False`` is the paper-literal sum of squares.
* Shifts run from ``-max_shift`` to ``+max_shift``: a positive delay means the
  second record lags the first; a negative one means it leads.
* The Kalman filter's observation variance for each segment is not a constant
  but the Gauss-Newton variance of the segment's shift estimate,
  ``T^2 c_min / (m a)`` (``c_min`` the cost at the minimum, ``a`` the curvature
  of the cost parabola per sample^2, ``m`` the number of compared samples). A
  segment in which the speed hardly changes carries almost no information about
  the delay; this variance says so and the filter all but ignores it. Pass
  ``observation_std_s`` for the paper's constant ``R``.
* Scenario (paper section 3): speed changing between 110 and 170 kn for 550 s,
  sampled at 10 Hz, total delay 300 ms on average. We make the measurable part
  change from segment to segment (scheduler phase, ``measurable_jitter_s``), so
  that a single fixed compensation cannot be perfect while the
  measurable-plus-filtered one can; with ``measurable_jitter_s=0`` the delay is
  the paper's fixed 300 ms.
* "Fixed compensation" (the paper's second case) is one constant for the whole
  record: our whole-record least-squares delay. "Filtered compensation" is the
  measurable part of each segment plus the causal Kalman estimate of the
  unknown part at that segment.

Entry points: :func:`simulate_latency` (a seeded scenario), :func:`estimate_delay`
(the least-squares delay between any two records, also for the two-sensor
tools), :func:`align_signals`, :func:`segment_delays`,
:func:`random_constant_kalman` and :func:`run_latency` (the whole method).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

#: One knot in metres per second.
KNOT_MS = 0.514444

#: Fewest reference samples a shift may be compared on.
MIN_OVERLAP = 16

#: Half-width (in shifts) of the least-squares parabola whose curvature gives
#: the variance of a delay estimate (see :func:`_refine`).
CURVATURE_HALFWIDTH = 5


# ---------------------------------------------------------------------------
# Scenario
# ---------------------------------------------------------------------------
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


# ---------------------------------------------------------------------------
# Least-squares delay
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class DelayEstimate:
    """The least-squares delay between two records (section 2.1, spec C).

    Attributes
    ----------
    delay_s : float
        Estimated delay of the second record behind the first (s), refined
        below one sample. Positive: the second record lags.
    integer_shift : int
        Best whole-sample shift.
    shifts : ndarray of int
        The shifts searched (samples).
    costs : ndarray
        Mean squared difference at each shift (the curve of the paper's
        Figs. 5, 7, 9).
    variance_s2 : float
        Gauss-Newton variance of ``delay_s`` (s^2): ``T^2 c_min / (m a)``;
        ``inf`` when the cost has no curvature (the records do not change).
    n_compared : int
        Number of reference samples compared at every shift.
    sample_period : float
        ``T`` (s).
    """

    delay_s: float
    integer_shift: int
    shifts: NDArray[np.int64]
    costs: NDArray[np.float64]
    variance_s2: float
    n_compared: int
    sample_period: float

    @property
    def std_s(self) -> float:
        """Standard deviation of ``delay_s`` (s)."""
        return float(np.sqrt(self.variance_s2))


def _as_record(x: ArrayLike, name: str) -> NDArray[np.float64]:
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 1:
        raise NoisevarError(f"{name} must be a 1-D record; got shape {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise NoisevarError(f"{name} contains NaN or infinite samples; remove or fill them.")
    return arr


def _max_shift(max_delay: float | None, sample_period: float, n: int) -> int:
    if not sample_period > 0:
        raise NoisevarError(f"sample_period={sample_period} must be positive (seconds).")
    limit = (n - MIN_OVERLAP) // 2
    if max_delay is None:
        return max(1, min(limit, n // 10))
    if not max_delay > 0:
        raise NoisevarError(f"max_delay={max_delay} must be positive (seconds).")
    shift = int(np.ceil(max_delay / sample_period - 1e-9))
    if shift > limit:
        raise NoisevarError(
            f"max_delay={max_delay:g} s is {shift} samples, longer than this record of {n} "
            f"samples allows (at most {limit * sample_period:g} s, which still leaves "
            f"{MIN_OVERLAP} samples to compare); shorten max_delay or give a longer record."
        )
    return max(1, shift)


def _costs_at_shifts(
    reference: NDArray[np.float64],
    delayed: NDArray[np.float64],
    lo: NDArray[np.int64],
    hi: NDArray[np.int64],
    max_shift: int,
    remove_bias: bool,
) -> NDArray[np.float64]:
    """Mean squared difference for every block and shift, in one array operation.

    Block ``j`` compares the late samples ``delayed[lo_j : hi_j]`` with
    ``reference[lo_j - k : hi_j - k]`` for every shift
    ``k in [-max_shift, max_shift]`` (callers keep ``lo_j >= max_shift`` and
    ``hi_j <= n - max_shift``). The late record is the fixed side because its
    samples carry the delay: a block of late samples shares one measurable
    delay. Blocks of different lengths are handled with a mask. Returns shape
    ``(len(lo), 2*max_shift+1)``.
    """
    shifts = np.arange(-max_shift, max_shift + 1)
    width = int(np.max(hi - lo))
    inner = np.arange(width)
    mask = inner[None, :] < (hi - lo)[:, None]  # (b, m)
    idx = np.where(mask, lo[:, None] + inner[None, :], lo[:, None])
    late = delayed[idx]
    diff = late[:, None, :] - reference[idx[:, None, :] - shifts[None, :, None]]  # (b, s, m)
    weights = mask[:, None, :] / mask.sum(axis=-1)[:, None, None]
    if remove_bias:
        diff = diff - np.sum(weights * diff, axis=-1, keepdims=True)
    return np.sum(weights * diff * diff, axis=-1)


def _refine(
    costs: NDArray[np.float64],
    max_shift: int,
    n_compared: NDArray[np.int64],
    sample_period: float,
    curvature_halfwidth: int = CURVATURE_HALFWIDTH,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """Sub-sample minimum and its variance, for every row of ``costs``.

    The vertex: a parabola through the costs at the best shift ``s0`` and its
    two neighbours, ``s* = s0 + (c- - c+) / (4 a3)`` with
    ``a3 = (c- - 2 c0 + c+) / 2`` (spec C).

    The variance: with ``c(s) ≈ a (s - s*)^2 + c_min`` the Gauss-Newton
    variance of the delay is ``T^2 c_min / (m a)``. Two corrections make it
    honest (we checked it against Monte Carlo errors): the curvature ``a`` is
    fitted by least squares over ``s0 ± curvature_halfwidth`` shifts rather
    than taken from the three-point parabola (on a segment where the signal
    hardly changes the three-point curvature is mostly noise), and the scatter
    ``s_c^2`` of the costs about that fitted parabola adds
    ``T^2 s_c^2 / (8 a^2)``: each integer shift pairs the late samples with
    other noise samples of the reference, so the three costs the vertex is
    read from are not on one smooth curve.

    Returns the refined delay (s), the integer shift, and the variance (s^2,
    ``inf`` where the minimum is at the search edge or the fitted curvature is
    not positive).
    """
    n_rows, n_shifts = costs.shape
    best = np.argmin(costs, axis=-1)
    rows = np.arange(n_rows)
    at_edge = (best == 0) | (best == n_shifts - 1)
    centre = np.clip(best, 1, n_shifts - 2)
    c_minus = costs[rows, centre - 1]
    c_zero = costs[rows, centre]
    c_plus = costs[rows, centre + 1]
    curvature3 = 0.5 * (c_minus - 2.0 * c_zero + c_plus)
    convex = (curvature3 > 0) & ~at_edge
    safe3 = np.where(convex, curvature3, 1.0)
    offset = np.clip(np.where(convex, (c_minus - c_plus) / (4.0 * safe3), 0.0), -0.5, 0.5)
    # A zero cost is a perfect fit at a whole-sample shift: keep it (the
    # parabola would move it by the O(1/m) asymmetry of the record's ends).
    perfect = c_zero <= 1e-14 * (c_minus + c_plus)
    offset = np.where(perfect, 0.0, offset)
    c_min = np.maximum(c_zero - safe3 * offset**2, 0.0)

    # Least-squares parabola a j^2 + b j + c over the wider window.
    j = np.arange(-curvature_halfwidth, curvature_halfwidth + 1)
    idx = centre[:, None] + j[None, :]
    valid = (idx >= 0) & (idx < n_shifts)
    y = np.where(valid, costs[rows[:, None], np.clip(idx, 0, n_shifts - 1)], 0.0)
    basis = np.stack([j**2, j, np.ones_like(j)], axis=-1).astype(float)  # (w, 3)
    weighted = valid[:, :, None] * basis[None, :, :]  # (b, w, 3)
    normal = np.einsum("bwi,wj->bij", weighted, basis)
    rhs = np.einsum("bwi,bw->bi", weighted, y)
    solvable = valid.sum(axis=-1) >= 3
    normal[~solvable] = np.eye(3)
    coefficients = np.linalg.solve(normal, rhs[..., None])[..., 0]  # (b, 3)
    curvature = coefficients[:, 0]
    fitted = coefficients @ basis.T  # (b, w)
    dof = np.maximum(valid.sum(axis=-1) - 3, 1)
    cost_noise_var = np.sum(valid * (y - fitted) ** 2, axis=-1) / dof
    informative = convex & solvable & (curvature > 0)
    safe = np.where(informative, curvature, 1.0)

    integer_shift = best - max_shift
    delay = (integer_shift + offset) * sample_period
    # Gauss-Newton term plus the scatter of the three costs the vertex is read
    # from (each shift pairs other noise samples): var(c- - c+) / (16 a^2).
    shift_var = c_min / (n_compared * safe) + cost_noise_var / (8.0 * safe**2)
    variance = np.where(informative, sample_period**2 * shift_var, np.inf)
    return delay, integer_shift, variance


def estimate_delay(
    reference: ArrayLike,
    delayed: ArrayLike,
    sample_period: float = 1.0,
    max_delay: float | None = None,
    remove_bias: bool = True,
) -> DelayEstimate:
    """Delay of ``delayed`` behind ``reference`` by least squares over shifts.

    Section 2.1 of the paper ("flight data comparison", "speed difference
    detection"): the shift minimising the sum of squared differences, refined
    below one sample with a parabola through the costs at the best shift and
    its two neighbours (spec C).

    Parameters
    ----------
    reference : array_like, shape (n,)
        The on-time record (e.g. the AHRS speed).
    delayed : array_like, shape (n,)
        The same quantity, late (e.g. the GPS speed), sampled at the same times.
    sample_period : float
        ``T`` in seconds (1 gives the delay in samples).
    max_delay : float, optional
        Largest delay searched, either sign (s). Default: a tenth of the record.
    remove_bias : bool
        Remove the mean of the difference at each shift (robust to a constant
        offset between the sensors). False: the paper-literal sum of squares.

    Returns
    -------
    DelayEstimate

    Raises
    ------
    NoisevarError
        When the records differ in length, are too short, contain NaN, when
        ``max_delay`` is longer than the record allows, or when the minimum
        lies at the edge of the searched shifts.
    """
    ref = _as_record(reference, "reference")
    lag = _as_record(delayed, "delayed")
    if ref.shape != lag.shape:
        raise NoisevarError(
            f"reference has {ref.size} samples and delayed {lag.size}; resample both onto "
            "the same times first."
        )
    n = ref.size
    if n < 2 * MIN_OVERLAP + 2:
        raise NoisevarError(
            f"{n} samples is too short to estimate a delay; give at least "
            f"{2 * MIN_OVERLAP + 2} samples."
        )
    max_shift = _max_shift(max_delay, sample_period, n)
    length = n - 2 * max_shift
    costs = _costs_at_shifts(
        ref, lag, np.array([max_shift]), np.array([n - max_shift]), max_shift, remove_bias
    )
    delay, integer_shift, variance = _refine(costs, max_shift, np.array([length]), sample_period)
    best = int(np.argmin(costs[0]))
    if best in (0, costs.shape[-1] - 1):
        raise NoisevarError(
            f"the least-squares minimum lies at the edge of the searched shifts "
            f"(±{max_shift * sample_period:g} s): the delay may be longer; increase "
            "max_delay."
        )
    return DelayEstimate(
        delay_s=float(delay[0]),
        integer_shift=int(integer_shift[0]),
        shifts=np.arange(-max_shift, max_shift + 1),
        costs=costs[0],
        variance_s2=float(variance[0]),
        n_compared=length,
        sample_period=float(sample_period),
    )


def align_signals(
    reference: ArrayLike, delayed: ArrayLike, delay_s: float, sample_period: float = 1.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Advance ``delayed`` by ``delay_s`` and crop both records to their overlap.

    The late record is read at ``t + delay`` by linear interpolation, so a
    sub-sample delay is removed as well; use this before differencing two
    sensors (the two-sensor SOMD, spec A1).

    Parameters
    ----------
    reference, delayed : array_like, shape (n,)
        Records on the same sample times.
    delay_s : float
        Delay of ``delayed`` behind ``reference`` (s), e.g.
        :attr:`DelayEstimate.delay_s`.
    sample_period : float
        ``T`` (s).

    Returns
    -------
    reference_aligned, delayed_aligned : ndarray
        Equal-length records, sample ``k`` of both describing the same instant.
    """
    ref = _as_record(reference, "reference")
    lag = _as_record(delayed, "delayed")
    if ref.shape != lag.shape:
        raise NoisevarError("reference and delayed must have the same number of samples.")
    shift = delay_s / sample_period
    n = ref.size
    k = np.arange(n)
    positions = k + shift
    keep = (positions >= 0) & (positions <= n - 1)
    if keep.sum() < 2:
        raise NoisevarError(
            f"a delay of {delay_s:g} s leaves no overlap in a record of {n} samples."
        )
    aligned = np.interp(positions[keep], k, lag)
    return ref[keep], aligned


# ---------------------------------------------------------------------------
# Segments and the random-constant Kalman filter
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class SegmentDelays:
    """Coarse least-squares delay of each segment of a record.

    Attributes
    ----------
    start_index : ndarray of int, shape (s,)
        First reference sample of each segment.
    delay_s : ndarray, shape (s,)
        Coarse delay of each segment (s).
    variance_s2 : ndarray, shape (s,)
        Gauss-Newton variance of each; ``inf`` for a segment without
        information (flat signal, minimum at the search edge, a segment too
        short to compare once the shifts are cut off); its delay is NaN when
        it is too short.
    costs : ndarray, shape (s, 2*max_shift+1)
        Cost curve of each segment.
    """

    start_index: NDArray[np.int64]
    delay_s: NDArray[np.float64]
    variance_s2: NDArray[np.float64]
    costs: NDArray[np.float64]


def segment_delays(
    reference: ArrayLike,
    delayed: ArrayLike,
    segment_length: int,
    sample_period: float = 1.0,
    max_delay: float | None = None,
    remove_bias: bool = True,
) -> SegmentDelays:
    """Coarse least-squares delay in each successive segment of the records.

    Segment ``j`` compares ``reference[j L : (j+1) L]`` (clipped to where all
    shifts fit) with the shifted ``delayed``; all segments and shifts are
    evaluated in one array operation.

    Parameters
    ----------
    reference, delayed : array_like, shape (n,)
        The two records.
    segment_length : int
        Samples per segment ``L``.
    sample_period : float
        ``T`` (s).
    max_delay : float, optional
        Largest delay searched (s); default a tenth of the record.
    remove_bias : bool
        As in :func:`estimate_delay`.

    Returns
    -------
    SegmentDelays
    """
    ref = _as_record(reference, "reference")
    lag = _as_record(delayed, "delayed")
    if ref.shape != lag.shape:
        raise NoisevarError("reference and delayed must have the same number of samples.")
    n = ref.size
    if not isinstance(segment_length, int | np.integer) or segment_length < MIN_OVERLAP:
        raise NoisevarError(
            f"segment_length={segment_length} must be an integer of at least {MIN_OVERLAP} samples."
        )
    max_shift = _max_shift(max_delay, sample_period, n)
    first = np.arange(0, n, segment_length)
    lo = np.maximum(first, max_shift)
    hi = np.minimum(first + segment_length, n - max_shift)
    n_compared = np.maximum(hi - lo, 0)
    if not np.any(n_compared >= MIN_OVERLAP):
        raise NoisevarError(
            f"no segment of {segment_length} samples leaves {MIN_OVERLAP} samples to compare "
            f"at shifts of ±{max_shift}; use longer segments or a shorter max_delay."
        )
    hi = np.maximum(hi, lo + 1)  # an empty edge segment: compute on one sample, then drop
    costs = _costs_at_shifts(ref, lag, lo, hi, max_shift, remove_bias)
    delay, _, variance = _refine(costs, max_shift, np.maximum(n_compared, 1), sample_period)
    too_short = n_compared < MIN_OVERLAP
    variance = np.where(too_short, np.inf, variance)
    delay = np.where(too_short, np.nan, delay)
    return SegmentDelays(
        start_index=first.astype(np.int64),
        delay_s=delay,
        variance_s2=variance,
        costs=costs,
    )


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
    x = np.full(z.shape[:-1], float(initial_estimate))
    p = np.full(z.shape[:-1], float(initial_variance))
    estimates = np.empty_like(z)
    variances = np.empty_like(z)
    for j in range(z.shape[-1]):  # the filter's time loop is inherent
        p = p + process_variance
        rj = r[..., j]
        finite = np.isfinite(rj) & np.isfinite(z[..., j])
        gain = np.where(finite, p / (p + np.where(finite, rj, 1.0)), 0.0)
        x = x + gain * np.where(finite, z[..., j] - x, 0.0)
        p = (1.0 - gain) * p
        estimates[..., j] = x
        variances[..., j] = p
    return estimates, variances


# ---------------------------------------------------------------------------
# The whole method
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class LatencyResult:
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
