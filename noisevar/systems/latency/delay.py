"""Least-squares delay between two records, and per-segment delays (docs/algorithms.md §C)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.systems.latency.scenario import MIN_OVERLAP

#: Half-width (in shifts) of the least-squares parabola whose curvature gives
#: the variance of a delay estimate (see :func:`_refine`).
CURVATURE_HALFWIDTH = 5


@dataclass(frozen=True)
class DelayEstimate:
    """The least-squares delay between two records (section 2.1, docs/algorithms.md §C).

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

    def is_significant(self, sample_period: float) -> bool:
        """Whether the delay is worth removing: over half a sample and over twice its std."""
        return abs(self.delay_s) > 0.5 * sample_period and abs(self.delay_s) > 2.0 * self.std_s


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

    Returns
    -------
    delay : ndarray
        Refined delay (s): the vertex of the parabola through the best shift
        and its two neighbours.
    shift : ndarray of int
        The integer shift of the minimum.
    variance : ndarray
        Gauss-Newton variance ``T² c_min / (m a)`` (s²) with ``a`` fitted over
        ``±curvature_halfwidth`` shifts, plus the scatter term; ``inf`` at the
        search edge or for a non-positive curvature.

    Notes
    -----
    Equations in docs/algorithms.md §C.
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
    its two neighbours (docs/algorithms.md §C).

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
    sensors (the two-sensor SOMD, docs/algorithms.md §A1).

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
