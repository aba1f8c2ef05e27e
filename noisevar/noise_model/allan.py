"""Allan deviation with intervals and noise identification (docs/algorithms.md §E4).

The deviations, the lag-1 autocorrelation noise identification and the equivalent
degrees of freedom are allantools' (Riley 2004, Greenhall 2004); this module chooses
the averaging factors, checks the input, and gathers the results.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import allantools
import numpy as np
from allantools import ci
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import check_exact_ints
from noisevar.errors import NoisevarError
from noisevar.estimators import scale_back, scale_exponent
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes, longest_still_stretch
from noisevar.estimators.results import VarianceEstimate
from noisevar.noise_model.allan_gaps import StampGrid, gap_grid, gapped_adev
from noisevar.numeric.noise_id import noise_id

#: One-sigma confidence (Stable32's default error bars).
ONE_SIGMA = 0.6826894921370859
#: Decimated points used by the noise identification at each tau (its estimate of the
#: lag-1 autocorrelation has a standard error of about ``1/sqrt(points)``).
NOISE_ID_POINTS = 1000
#: Fewest decimated points allantools' noise identification accepts.
NOISE_ID_MIN = 30
#: Power-law noise exponent alpha (S_y(f) ~ f^alpha) -> Stable32's abbreviation.
NOISE_TYPES = {
    2: "WPM",
    1: "FPM",
    0: "WFM",
    -1: "FFM",
    -2: "RWFM",
    -3: "FWFM",
    -4: "RRFM",
}
DATA_KINDS = ("phase", "rate")


def default_data(unit: str | None) -> str:
    """What the samples are when nobody said: ``"phase"`` for a time (a clock's time error
    in ``s``, ``ns``) or an angle (``rad``, ``deg``: the integral of a rate), else
    ``"rate"`` (a gyro's rate, a specific force, a fractional frequency, and a record with
    no unit: what IMU and GNSS users hold).

    The one default of the command line's ``--data`` and the Noise model page's choice.
    """
    from noisevar.units import parse_unit

    try:
        parsed = parse_unit(unit)
    except NoisevarError:
        parsed = None
    return "phase" if parsed is not None and parsed.si in ("second", "radian") else "rate"


#: Terms per block when a deviation is summed block by block (the blocks stay in cache).
BLOCK = 2**16


@dataclass(frozen=True)
class _Kind:
    """A deviation: allantools' function (or per-tau kernel) and Greenhall's edf parameters."""

    function: Callable[..., Any]
    kernel: Callable[..., Any] | None  # allantools' calc_*_phase(phase, rate, m, stride)
    d: int  # order of differencing of the phase (2 Allan, 3 Hadamard)
    modified: bool
    span: int  # phase samples spanned by one term, in units of m


KINDS = {
    "oadev": _Kind(allantools.oadev, allantools.allantools.calc_adev_phase, 2, False, 2),
    "mdev": _Kind(allantools.mdev, None, 2, True, 3),
    "hdev": _Kind(allantools.ohdev, allantools.allantools.calc_hdev_phase, 3, False, 3),
}


@dataclass(frozen=True, eq=False)
class AllanResult:
    """Allan-type deviations of one record, one entry per averaging time.

    Attributes
    ----------
    kind : {"oadev", "mdev", "hdev"}
        Overlapping Allan, modified Allan or overlapping Hadamard deviation.
    data : {"phase", "rate"}
        What the samples were.
    rate : float
        Sample rate (Hz).
    taus : ndarray
        Averaging times (s).
    deviation : ndarray
        The deviation at each tau (units of the rate data: phase units per second).
    interval : tuple of ndarray
        ``(lo, hi)`` confidence interval of the deviation at level ``ci``.
    ci : float
        Confidence level of ``interval``.
    alpha : ndarray
        Identified power-law exponent (``S_y(f) ~ f^alpha``); NaN where fewer than three
        averages remain at that tau.
    noise_type : tuple of str or None
        The noise type per tau (``"WPM"``, ``"FPM"``, ``"WFM"``, ``"FFM"``, ``"RWFM"``...).
    edf : ndarray
        Equivalent degrees of freedom behind each interval.
    slope : ndarray
        Local log-log slope ``d log(deviation) / d log(tau)``.
    n : ndarray
        Number of terms averaged at each tau.
    n_samples : int
        Length of the record (of its still stretch with ``regimes="still"``).
    regimes : {"all", "still"}
        The record's regimes used (:mod:`noisevar.estimators.regimes`).
    notes : tuple of str
        Which stretch a ``regimes="still"`` deviation was computed on.
    """

    kind: str
    data: str
    rate: float
    taus: NDArray
    deviation: NDArray
    interval: tuple[NDArray, NDArray]
    ci: float
    alpha: NDArray
    noise_type: tuple[str | None, ...]
    edf: NDArray
    slope: NDArray
    n: NDArray
    n_samples: int
    regimes: str = DEFAULT_REGIMES
    notes: tuple[str, ...] = ()

    @property
    def variance(self) -> NDArray:
        """The deviation squared (Allan variance)."""
        return self.deviation**2

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary (NaN becomes None)."""
        return {
            "kind": self.kind,
            "data": self.data,
            "rate": float(self.rate),
            "ci": float(self.ci),
            "n_samples": int(self.n_samples),
            "taus": _json(self.taus),
            "deviation": _json(self.deviation),
            "interval_lo": _json(self.interval[0]),
            "interval_hi": _json(self.interval[1]),
            "alpha": _json(self.alpha),
            "noise_type": list(self.noise_type),
            "edf": _json(self.edf),
            "slope": _json(self.slope),
            "n": [int(v) for v in self.n],
            "regimes": self.regimes,
            "notes": list(self.notes),
        }


def _json(a: NDArray) -> list[float | None]:
    return [float(v) if np.isfinite(v) else None for v in np.asarray(a, dtype=float)]


def rescale_allan(res: AllanResult, rate: float, e: int, k: int) -> AllanResult:
    """An Allan result computed on ``z 2**e`` at ``rate 2**k``, in the record's units.

    Taus are ``m / rate``: times ``2**k``. A deviation is ``Δx / tau``: phase data are
    the record (``2**-(e + k)``); rate data are integrated with ``1 / rate``
    (``2**-e``). Noise types, edf, slopes and counts do not change.
    """
    shift = -e - k if res.data == "phase" else -e
    return replace(
        res,
        rate=float(rate),
        taus=scale_back(res.taus, k, "averaging times"),
        deviation=scale_back(res.deviation, shift, "Allan deviation"),
        interval=tuple(scale_back(v, shift, "Allan deviation") for v in res.interval),
    )


def to_phase(z: ArrayLike, rate: float, data: str) -> NDArray:
    """The record as phase: rate data integrated once (mean removed), phase data as is.

    Parameters
    ----------
    z : array_like
        1-D record.
    rate : float
        Sample rate (Hz).
    data : {"phase", "rate"}
        What ``z`` holds.

    Returns
    -------
    ndarray
        Phase samples (one more than ``z`` for rate data).
    """
    if data not in DATA_KINDS:
        raise NoisevarError(f"data must be 'phase' or 'rate', not {data!r}.")
    if rate is None or not np.isfinite(rate) or rate <= 0:
        raise NoisevarError(f"The sample rate must be a positive number of Hz, not {rate}.")
    check_exact_ints(z, "The record")
    y = np.asarray(z, dtype=float)
    if y.ndim != 1:
        raise NoisevarError(f"The record must be one-dimensional; it has shape {y.shape}.")
    if not np.all(np.isfinite(y)):
        raise NoisevarError("The record holds NaN or infinite values: remove or fill them first.")
    if data == "phase":
        return y
    # x_k = tau0 * sum_{j<k} (y_j - mean y),  x_0 = 0
    x = np.empty(y.size + 1)
    x[0] = 0.0
    np.cumsum(y - y.mean(), out=x[1:])
    x[1:] /= rate
    return x


def still_record(
    z: ArrayLike, data: str, need: int, purpose: str, est: VarianceEstimate | None = None
) -> tuple[NDArray, str]:
    """The longest still stretch of a record of phase or rate data, and what to say of it.

    Parameters
    ----------
    z : array_like, shape (n,)
        The record.
    data : {"phase", "rate"}
        What ``z`` holds: the regimes of phase data are those of its rate (its first
        differences).
    need : int
        Fewest rate samples ``purpose`` needs.
    purpose : str
        What the stretch is for (for the error message).
    est : VarianceEstimate, optional
        :func:`noisevar.estimate` of the rate data (``z``, or its first differences for
        phase data), when it was made already.

    Returns
    -------
    ndarray, str
        The stretch's samples and its note
        (:func:`~noisevar.estimators.regimes.longest_still_stretch`).
    """
    y = np.asarray(z, dtype=float)
    if data == "phase":
        s = longest_still_stretch(np.diff(y), need, purpose, est)
        return y[s.start : s.stop + 1], s.note
    s = longest_still_stretch(y, need, purpose, est)
    return s.take(y), s.note


def regime_warning(z: ArrayLike, est: VarianceEstimate | None = None) -> list[str]:
    """The regime warning of a fit of a whole record whose noise level varies.

    Parameters
    ----------
    z : array_like, shape (n,)
        The record (rate data).
    est : VarianceEstimate, optional
        :func:`noisevar.estimate` of ``z``, when it was made already (not made again).

    Returns
    -------
    list of str
        One note when :func:`noisevar.estimate`'s diagnostics say the level varies
        (regimes of motion and stillness): the record's regime warning and
        ``regimes='still'``; none otherwise, or when the regimes cannot be found.

    Notes
    -----
    The diagnostics are the estimate's own (``level_changes``; one home), as
    ``regimes='still'`` finds its stretch with (:func:`still_record`).
    """
    from noisevar.estimators import estimate
    from noisevar.estimators.answer import REGIME_WARNING

    try:
        est = estimate(np.asarray(z, dtype=float)) if est is None else est
    except NoisevarError:
        return []
    diag = est.diagnostics
    if diag is None or not diag.level_changes:
        return []
    return [
        f"regimes='all': {REGIME_WARNING}; this fit is of the whole record, motion "
        "included, not the sensor's noise: fit the still regimes only (regimes='still'; "
        "CLI --regimes still; dashboard: use the still regimes only)"
    ]


def averaging_factors(n_phase: int, rate: float, taus: str | ArrayLike, kind: str) -> NDArray:
    """The averaging factors m (tau = m / rate) that ``kind`` can use on ``n_phase`` samples.

    Parameters
    ----------
    n_phase : int
        Phase samples.
    rate : float
        Sample rate (Hz).
    taus : "octave", "all" or array_like
        Octave factors 1, 2, 4, ...; every factor; or averaging times in seconds.
    kind : str
        A key of :data:`KINDS`.

    Returns
    -------
    ndarray of int
    """
    if kind not in KINDS:
        raise NoisevarError(f"kind must be one of {', '.join(KINDS)}, not {kind!r}.")
    span = KINDS[kind].span
    # at least two terms at every tau: n_phase - span*m >= 2 (hdev, oadev); mdev one fewer
    m_max = (n_phase - 2) // span
    if m_max < 1:
        raise NoisevarError(
            f"The record is too short for {kind}: {n_phase} phase samples, need at least "
            f"{span + 2}."
        )
    if isinstance(taus, str):
        if taus == "octave":
            return 2 ** np.arange(int(np.log2(m_max)) + 1)
        if taus == "all":
            return np.arange(1, m_max + 1)
        raise NoisevarError(f"taus must be 'octave', 'all' or an array of seconds, not {taus!r}.")
    t = np.atleast_1d(np.asarray(taus, dtype=float))
    m = np.round(t * rate).astype(np.int64)
    if t.size == 0 or np.any(~np.isfinite(t)) or np.any(m < 1):
        raise NoisevarError(
            f"Every tau must be at least one sample period ({1 / rate:g} s); got {taus!r}."
        )
    if np.any(m > m_max):
        raise NoisevarError(
            f"The record is too short for tau = {t[m > m_max].max():g} s: {kind} at that tau "
            f"needs {span * int(m.max()) + 2} phase samples, the record has {n_phase}."
        )
    return np.unique(m)


def allan(
    z: ArrayLike,
    rate: float = 1.0,
    data: str = "phase",
    kind: str = "oadev",
    taus: str | ArrayLike = "octave",
    ci: float = ONE_SIGMA,
    regimes: str = DEFAULT_REGIMES,
    t: ArrayLike | None = None,
) -> AllanResult:
    """Overlapping Allan (or modified Allan, overlapping Hadamard) deviation of a record.

    Parameters
    ----------
    z : array_like
        1-D record: phase (e.g. time error in s, angle) or rate (fractional frequency,
        angular rate, acceleration).
    rate : float
        Sample rate (Hz).
    data : {"phase", "rate"}
        What ``z`` holds.
    kind : {"oadev", "mdev", "hdev"}
        Overlapping Allan, modified Allan, or overlapping Hadamard deviation.
    taus : "octave", "all" or array_like
        Averaging times: octave factors, every factor, or given times (s).
    ci : float
        Confidence level of the intervals (default one sigma).
    regimes : {"all", "still"}
        The whole record, or its longest still stretch only (:func:`still_record`;
        said in ``notes``).
    t : array_like, optional
        Sample times (s) of rate data: when they are whole multiples of one period with
        samples missing (:func:`~noisevar.noise_model.allan_gaps.stamp_grid`), the
        overlapping Allan deviation is taken on that grid, at its rate (:func:`gapped`).

    Returns
    -------
    AllanResult

    Notes
    -----
    docs/algorithms.md §E4. Per tau, the noise type is identified by the lag-1
    autocorrelation of the decimated record (on at most :data:`NOISE_ID_POINTS` points;
    below 30 points by the B1 and R(n) ratios, as Stable32); the interval is the
    chi-square interval with Greenhall's edf for that noise type.
    """
    if not 0 < ci < 1:
        raise NoisevarError(f"ci must be between 0 and 1, not {ci}.")
    with np.errstate(over="ignore", under="ignore"):  # checks z; scaled below if out of range
        x = to_phase(z, rate, data)
    e, k = (scale_exponent(np.asarray(v, dtype=float)) for v in (z, [rate]))
    if e or k:  # scale-safe: the record by 2**e, the rate by 2**k (exact), results back
        given = taus if isinstance(taus, str) else np.ldexp(np.asarray(taus, dtype=float), -k)
        t = None if t is None else np.ldexp(np.asarray(t, dtype=float), -k)
        res = allan(np.ldexp(np.asarray(z, dtype=float), e), np.ldexp(rate, k), data, kind,
                    given, ci, regimes, t)  # fmt: skip
        return rescale_allan(res, rate, e, k)
    if check_regimes(regimes) == "still":
        need = KINDS[kind].span + 2 if kind in KINDS else 0
        z, note = still_record(z, data, need, f"the {kind}")
        res = allan(z, rate, data, kind, taus, ci)
        return replace(res, regimes=regimes, notes=(note,))
    if t is not None and np.asarray(t).shape != np.asarray(z).shape:
        raise NoisevarError("t must hold one time per sample of the record.")
    grid = gap_grid(t, data, kind)
    if grid is not None:
        return gapped(z, grid, taus, ci)
    m = averaging_factors(x.size, rate, taus, kind)
    spec = KINDS[kind]
    # the checks above keep allantools off its printing paths (no redirect: not thread-safe)
    t, dev, n = _deviations(x, rate, m, spec)
    if not np.any(dev > 0):
        raise NoisevarError(
            "The record does not vary (its Allan deviation is zero at every tau): nothing to fit."
        )
    m_used = np.round(t * rate).astype(np.int64)
    alpha = np.array([_noise_id(x, int(k), spec.d) for k in m_used], dtype=float)
    edf = _edfs(alpha, spec, m_used, x.size, default=2 if data == "phase" else 0)
    lo, hi = np.empty_like(dev), np.empty_like(dev)
    for i in range(dev.size):
        lo[i], hi[i] = allantools.confidence_interval(dev[i], edf[i], ci)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.gradient(np.log(dev), np.log(t)) if t.size > 1 else np.full(t.size, np.nan)
    names = tuple(None if np.isnan(a) else NOISE_TYPES.get(int(a)) for a in alpha)
    return AllanResult(
        kind=kind,
        data=data,
        rate=float(rate),
        taus=t,
        deviation=dev,
        interval=(lo, hi),
        ci=float(ci),
        alpha=alpha,
        noise_type=names,
        edf=edf,
        slope=slope,
        n=n.astype(np.int64),
        n_samples=int(np.asarray(z).size),
    )


def gapped(z: ArrayLike, grid: StampGrid, taus: str | ArrayLike, ci: float) -> AllanResult:
    """The overlapping Allan deviation of rate data ``z`` on ``grid`` (dropped samples).

    Parameters
    ----------
    z : array_like, shape (n,)
        Rate samples, one per stamp of ``grid``.
    grid : StampGrid
        :func:`~noisevar.noise_model.allan_gaps.stamp_grid` of their times.
    taus : "octave", "all" or array_like
        As :func:`allan`'s, at the grid's rate.
    ci : float
        Confidence level.

    Returns
    -------
    AllanResult
        At the grid's rate; a tau where too few windows hold enough samples is left out.

    Notes
    -----
    docs/algorithms.md §E4 (gaps): the deviation of
    :func:`~noisevar.noise_model.allan_gaps.gapped_adev`; the noise type per tau that
    of the samples present at the factor spanning as many of them; Greenhall's edf for
    the full grid times the share of its terms present and ``(avar / raw)^2`` (the
    removed excess leaves its spread).
    """
    y = np.asarray(z, dtype=float)
    if y.size != grid.slot.size:
        raise NoisevarError(f"{y.size} samples but {grid.slot.size} times: one time per sample.")
    rate = 1.0 / grid.period
    g = gapped_adev(y, grid, averaging_factors(grid.size + 1, rate, taus, "oadev"))
    keep = np.isfinite(g.deviation) & (g.n >= 2)
    if np.count_nonzero(keep) < 1:
        raise NoisevarError("Too few samples are present for an Allan deviation at any tau.")
    m, dev, n, full = g.m[keep], g.deviation[keep], g.n[keep], g.full[keep]
    t = m / rate
    # the noise type of the samples present, at the factor spanning as many of them
    x, share_kept = to_phase(y, rate, "rate"), y.size / grid.size
    alpha = np.array([_noise_id(x, max(1, round(k * share_kept)), 2) for k in m], dtype=float)
    share = n / full * (dev**2 / g.raw[keep]) ** 2  # terms present; the excess's spread
    edf = np.maximum(_edfs(alpha, KINDS["oadev"], m, grid.size + 1, default=0) * share, 1.0)
    lo, hi = np.empty_like(dev), np.empty_like(dev)
    for i in range(dev.size):
        lo[i], hi[i] = allantools.confidence_interval(dev[i], edf[i], ci)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.gradient(np.log(dev), np.log(t)) if t.size > 1 else np.full(t.size, np.nan)
    note = (
        f"{grid.dropped} of {grid.size} samples dropped (the times are whole multiples of "
        f"{grid.period:.6g} s): the deviation is of the samples on that grid, each window's "
        "mean of the samples it holds (at least half), its excess white noise removed; "
        "taus are in the record's seconds"
    )
    return AllanResult(
        kind="oadev", data="rate", rate=rate, taus=t, deviation=dev, interval=(lo, hi),
        ci=float(ci), alpha=alpha,
        noise_type=tuple(None if np.isnan(a) else NOISE_TYPES.get(int(a)) for a in alpha),
        edf=edf, slope=slope, n=n.astype(np.int64), n_samples=int(y.size), notes=(note,),
    )  # fmt: skip


def _deviations(
    x: NDArray, rate: float, m: NDArray, spec: _Kind
) -> tuple[NDArray, NDArray, NDArray]:
    """taus, deviations and term counts; overlapping kinds summed over blocks of terms.

    The overlapping estimators are means of squared terms, so allantools' kernel on
    consecutive blocks (each with its ``span * m`` samples of overlap) gives the same
    deviation as one call, and the blocks fit in the cache.
    """
    if spec.kernel is None:
        t, dev, _, n = spec.function(x, rate, "phase", m / rate)
        return t, dev, n
    dev = np.empty(m.size)
    n = np.zeros(m.size, dtype=np.int64)
    for i, k in enumerate(int(v) for v in m):
        tail = spec.span * k
        step = max(BLOCK, tail)
        total = 0.0
        for a in range(0, x.size - tail, step):
            d_blk, _, n_blk = spec.kernel(x[a : a + step + tail], rate, k, 1)
            # dev^2 is a mean over the block's n terms: pool the sums
            total += d_blk**2 * n_blk
            n[i] += n_blk
        dev[i] = np.sqrt(total / n[i])
    return m / rate, dev, n


def _b1_noise_id(x: NDArray, m: int) -> float:
    """Stable32's noise type where the autocorrelation has too few points (B1 and R(n)).

    The Barnes B1 ratio (standard over Allan variance) picks the nearest power law on a
    log scale (allantools' ``b1_boundary``: geometric means); white and flicker phase
    share B1 and are told apart by R(n) (modified over Allan variance).
    """
    n_avg = (x.size - 1) // m
    if n_avg < 3:
        return np.nan
    with np.errstate(invalid="ignore", divide="ignore"):
        # B1 at factor m is B1 of the phase decimated by m at factor 1 (same averages and
        # non-overlapping Allan terms), without copying the whole record
        ratio = ci.b1(x[::m], 1, 1.0)
    if not np.isfinite(ratio):
        return np.nan
    alpha = 2
    # b1_boundary(b, n) separates phase exponents b - 1 and b (alpha = b + 2)
    for b_hi in (-1, -2, -3):
        if ratio > ci.b1_boundary(b_hi, n_avg):
            alpha = b_hi + 1  # white, flicker, random-walk frequency
    if alpha == 2:
        with np.errstate(invalid="ignore", divide="ignore"):
            rn = ci.rn(x, m, 1.0)
        if np.isfinite(rn) and rn > ci.rn_boundary(m, 0):
            alpha = 1
    return float(alpha)


def _noise_id(x: NDArray, m: int, d: int) -> float:
    """The lag-1 autocorrelation noise exponent at factor ``m`` (B1 when too short)."""
    if x.size // m < NOISE_ID_MIN:
        return _b1_noise_id(x, m)
    head = x[: NOISE_ID_POINTS * m + 1]
    try:
        alpha_int = noise_id(head, m, dmax=d)
    except (NoisevarError, ValueError, np.linalg.LinAlgError):
        return np.nan
    # the power-law types the d-th difference can tell apart: 2 - 2d .. 2
    return float(min(2, max(alpha_int, 2 - 2 * d)))


def _edfs(alpha: NDArray, spec: _Kind, m: NDArray, n_phase: int, default: int) -> NDArray:
    """Greenhall's edf per tau; an unidentified tau takes the last identified noise type."""
    out = np.empty(alpha.size)
    last = float(default)
    for i, a in enumerate(alpha):
        last = last if np.isnan(a) else a
        a_int = int(last)
        try:
            edf = allantools.edf_greenhall(
                a_int, spec.d, int(m[i]), n_phase, overlapping=True, modified=spec.modified
            )
        except (NotImplementedError, AssertionError, ZeroDivisionError, ValueError):
            # Stein's simple formulas know alpha = -2 .. 2 only
            edf = allantools.edf_simple(n_phase, int(m[i]), min(2, max(a_int, -2)))
        out[i] = edf if np.isfinite(edf) and edf > 0 else 1.0
    return out
