"""Noise-variance estimators: SOMD (paper and corrected), redundant sensors, peers, ``auto``.

Every estimator takes one signal ``z`` (1-D) and keyword parameters and
returns a :class:`~noisevar.estimators.results.VarianceEstimate`. Use
:func:`estimate` (``noisevar.estimate``) with a method name from
:func:`methods`.

Difference estimators share one mechanism: a finite sequence ``d`` is
convolved with ``z`` and ``mean((d * z)²) / sum(d²)`` estimates the noise
variance; its effective degrees of freedom are ``n / sum_k ρ_k²`` where ``ρ``
is the normalised autocorrelation of ``d`` (1 for independent squares, the
Cramér-Rao case). A new difference estimator is one new sequence.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal, stats
from scipy.ndimage import maximum_filter1d

from noisevar.errors import NoisevarError, NoWindowKept
from noisevar.estimators.results import (
    RedundantEstimate,
    SomdDetails,
    VarianceEstimate,
    chi2_interval,
)
from noisevar.filters.abg import (  # noqa: PLC2701 - shared internals
    _impulse,
    _transfer_function_cached,
    abg_filter,
    check_h,
    settling_samples,
    somd_bias_factor,
)
from noisevar.filters.selection import ANGLES, select_windows

try:  # compiled residual filters of ``auto`` (numba); np.convolve below is the reference
    from noisevar.filters import _fir
except ImportError:  # pragma: no cover - numba not installed
    _fir = None

#: ``auto`` filters with the compiled kernel of :mod:`noisevar.filters._fir` while this
#: is true (and numba is installed); false selects ``np.convolve`` (the same
#: filter, equal to rounding, about 4 times slower).
USE_COMPILED: bool = _fir is not None

MAD_TO_SIGMA = 1.0 / 0.6744897501960817
#: Asymptotic efficiency of the MAD scale estimator at the Gaussian (relative to the SD).
MAD_EFFICIENCY = 0.3675

# Parameters every method accepts (irrelevant ones are ignored); anything else is a typo.
KNOWN_PARAMS = {
    "h_smooth",
    "h_track",
    "track_ratio",
    "window",
    "gamma_amp",
    "gamma_ang",
    "angle",
    "select",
    "reference",
    "reference_variance",
    "drop_nonfinite",
    "wavelet",
    "trim",
    "order",
    "span",
}

PAPER_H_SMOOTH = 1.5e-5
PAPER_WINDOW = 40


# ----------------------------------------------------------------------------- input
def as_signal(z: ArrayLike, drop_nonfinite: bool = False) -> tuple[NDArray, list[str]]:
    """Validate one signal: numeric, 1-D, finite (or drop non-finite samples), not constant.

    Parameters
    ----------
    z : array_like
        Samples.
    drop_nonfinite : bool
        Drop NaN/Inf samples (and say how many) instead of refusing them.

    Returns
    -------
    z : ndarray of float, shape (n,)
    notes : list of str
    """
    try:
        arr = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError("the signal is not numeric: give an array of numbers") from None
    arr = np.squeeze(arr) if arr.ndim > 1 and 1 in arr.shape else arr
    if arr.ndim != 1:
        raise NoisevarError(
            f"expected one signal (a 1-D array), got shape {arr.shape}: pick one column"
        )
    notes: list[str] = []
    bad = ~np.isfinite(arr)
    if bad.any():
        first = int(np.argmax(bad))
        if not drop_nonfinite:
            raise NoisevarError(
                f"the signal has {int(bad.sum())} non-finite values (NaN or Inf), the first at "
                f"sample {first}: clean them, or drop them with drop_nonfinite=True "
                "(CLI: --drop-nonfinite)"
            )
        arr = arr[~bad]
        notes.append(f"dropped {int(bad.sum())} non-finite samples (first at sample {first})")
    if arr.size == 0:
        raise NoisevarError("the signal is empty: give at least a few hundred samples")
    if arr.size < 8:
        raise NoisevarError(f"the signal has only {arr.size} samples: give at least 100")
    if not arr.flags.writeable:  # e.g. a memory-mapped file; PyWavelets needs writable input
        arr = arr.copy()
    if np.ptp(arr) == 0:
        raise NoisevarError(
            "the signal is constant: its noise variance is 0 and there is nothing to estimate"
        )
    return arr, notes


def _check_window(window: Any, n: int, need: int = 1) -> int:
    try:
        m = int(window)
    except (TypeError, ValueError):
        raise NoisevarError(f"window must be an integer, got {window!r}") from None
    if m != window or m < 8:
        raise NoisevarError(f"window must be an integer of at least 8 samples, got {window}")
    if n < need * m:
        raise NoisevarError(
            f"too few samples for the window: {n} samples, window {m} "
            f"(need at least {need * m}); use a smaller window or a longer record"
        )
    return m


def _check_range(name: str, value: Any, lo: float, hi: float, unit: str = "") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be a number, got {value!r}") from None
    if not (lo < v <= hi):
        raise NoisevarError(f"{name}={value} is out of range: it must be in ({lo}, {hi}]{unit}")
    return v


# ------------------------------------------------------------------ difference estimators
def sequence_efficiency(d: ArrayLike) -> float:
    """``sum_k ρ_k²`` of a difference sequence: variance inflation over the Cramér-Rao floor.

    Parameters
    ----------
    d : array_like
        The sequence.

    Returns
    -------
    float
        1 for a delta (independent squares); 1.5 for Rice's ``[1, -1]``.
    """
    d = np.asarray(d, dtype=float)
    ac = np.correlate(d, d, mode="full") / np.sum(d**2)
    return float(np.sum(ac**2))


def difference_estimate(
    z: NDArray, d: ArrayLike, method: str, params: dict, notes: list[str]
) -> VarianceEstimate:
    """Variance ``mean((d * z)²) / sum(d²)`` over the valid part of the convolution.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    d : array_like
        Difference sequence (``sum(d) = 0``).
    method, params, notes
        Recorded in the result.

    Returns
    -------
    VarianceEstimate
    """
    d = np.asarray(d, dtype=float)
    e = np.convolve(z, d[::-1], mode="valid")
    var = float(np.mean(e**2) / np.sum(d**2))
    dof = e.size / sequence_efficiency(d)
    return VarianceEstimate(
        method, var, chi2_interval(var, dof), e.size, z.size, dof, params, notes
    )


def _zero_sum_unit(d: list[float]) -> NDArray:
    """Project a published (4-decimal) sequence onto sum 0, sum of squares 1.

    The printed order-3 values sum to 1e-4, which would leak an offset ``c``
    into the estimate as ``(1e-4 c)²``: ruinous for, say, UTM coordinates.
    """
    a = np.asarray(d, dtype=float)
    a = a - a.mean()
    return a / np.sqrt(np.sum(a**2))


#: Hall-Kay-Titterington (1990) optimal difference sequences, orders 1-3.
HKT_SEQUENCES = {
    1: _zero_sum_unit([0.7071, -0.7071]),
    2: _zero_sum_unit([0.8090, -0.5000, -0.3090]),
    3: _zero_sum_unit([0.1942, 0.2809, 0.3832, -0.8582]),
}


def _mad_variance(x: NDArray) -> float:
    med = np.median(x)
    return float((np.median(np.abs(x - med)) * MAD_TO_SIGMA) ** 2)


# ------------------------------------------------------------------------------ SOMD
@lru_cache(maxsize=256)
def _somd_efficiency(h: float) -> float:
    b, a = _transfer_function_cached(h, "predicted")
    g = _impulse(b, a)
    dg = g.copy()
    dg[0] -= 1.0
    seq = np.diff(np.concatenate([[0.0], dg]))
    seq = seq[: max(8, int(np.argmax(np.cumsum(seq**2) > (1 - 1e-10) * np.sum(seq**2))) + 1)]
    return sequence_efficiency(seq)


def _as_h_tuple(h_smooth: Any) -> tuple[float, ...]:
    if h_smooth is None:
        return (PAPER_H_SMOOTH,)
    if isinstance(h_smooth, (int, float, np.floating)):
        return (check_h(h_smooth, "h_smooth"),)
    hs = tuple(check_h(h, "h_smooth") for h in h_smooth)
    if not hs:
        raise NoisevarError("h_smooth is empty: give at least one smoothing h")
    return hs


def somd_estimate(
    z: NDArray,
    *,
    paper: bool,
    h_smooth: Any = None,
    h_track: float | None = None,
    track_ratio: float = 30.0,
    window: int = PAPER_WINDOW,
    gamma_amp: float = 0.5,
    gamma_ang: float = 10.0,
    angle: str | None = None,
    select: bool = True,
    notes: list[str] | None = None,
) -> VarianceEstimate:
    """SOMD with an alpha-beta-gamma virtual redundant sensor (spec A5-A8).

    The virtual sensor ``Z1`` is the one-step prediction of the smoothing
    filter (``h_S``), ``Z2`` the raw samples; over the samples of the kept
    windows

        var = E[(ΔZ1 - ΔZ2)²] / c                                       [8]

    with ``c = 2`` as printed (``paper=True``) or the exact ``c(h)`` of spec
    A8 (``paper=False``), which removes the paper's bias. Windows are kept by
    the tests of eq. [19] (:func:`noisevar.filters.selection.select_windows`); with
    several ``h_S`` a window counts when any passes (section 2.4) and its
    estimate is the mean over the passing ones.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    paper : bool
        Paper-literal factor 1/2, angle convention and amplitude test (the
        printed chain of ratios); otherwise ``c(h)`` and the symmetric
        amplitude test, which makes the estimate invariant to the signal's
        sign (:mod:`noisevar.filters.selection`).
    h_smooth : float or sequence of float
        Smoothing ``h_S`` (default 1.5e-5, the paper's).
    h_track : float, optional
        Tracking ``h_T`` (default ``track_ratio * min(h_S)``).
    track_ratio : float
        ``h_T / h_S`` when ``h_track`` is not given (paper: 10 to 100).
    window : int
        Window length ``m`` (paper: 40).
    gamma_amp, gamma_ang : float
        Thresholds of eq. [19] (``gamma_ang`` in degrees).
    angle : {"scaled", "paper"}, optional
        Slope convention (default "paper" when ``paper`` else "scaled").
    select : bool
        Apply window selection (off for signals known to be smooth).
    notes : list of str, optional
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
        With :class:`~noisevar.estimators.results.SomdDetails`.
    """
    notes = list(notes or [])
    n = z.size
    hs = _as_h_tuple(h_smooth)
    if h_track is None:
        ratio = _check_range("track_ratio", track_ratio, 1.0, 1e4)
        h_track = min(hs) * ratio
    ht = check_h(h_track, "h_track")
    m = _check_window(window, n)
    gamma_amp = _check_range("gamma_amp", gamma_amp, 0.0, 1.0)
    gamma_ang = _check_range("gamma_ang", gamma_ang, 0.0, 90.0, " degrees")
    angle = angle or ("paper" if paper else "scaled")
    amplitude = "paper" if paper else "symmetric"  # somd is invariant to the signal's sign
    if angle not in ANGLES:
        raise NoisevarError(f"angle must be one of {ANGLES}, got {angle!r}")
    skip = max(settling_samples(h) for h in (*hs, ht))
    if n - skip < 2 * m:
        raise NoisevarError(
            f"too few samples: the filters need {skip} samples to settle (h_smooth={min(hs):g}) "
            f"and then at least two windows of {m}; give more than {skip + 2 * m} samples "
            "or a larger h_smooth"
        )
    smooth = np.stack([abg_filter(z, h) for h in hs])
    track = abg_filter(z, ht)
    factors = tuple(2.0 if paper else somd_bias_factor(h) for h in hs)
    mutual = np.diff(smooth, axis=1) - np.diff(z)  # ΔZ1 - ΔZ2, shape (n_h, n-1)
    sq = np.concatenate([mutual**2, np.zeros((len(hs), 1))], axis=1)  # align with samples
    n_win = n // m
    win_sq = sq[:, : n_win * m].reshape(len(hs), n_win, m)
    counts = np.full(n_win, m, dtype=float)
    if n_win * m == n:
        counts[-1] -= 1  # last sample has no forward difference
    per_h = win_sq.sum(axis=2) / counts / np.asarray(factors)[:, None]
    starts = np.arange(n_win) * m
    in_record = starts >= skip
    params = {
        "h_smooth": list(hs) if len(hs) > 1 else hs[0],
        "h_track": ht,
        "window": m,
        "gamma_amp": gamma_amp,
        "gamma_ang": gamma_ang,
        "angle": angle,
        "select": bool(select),
    }
    selection = None
    if select:
        sels = [
            select_windows(
                z, s, track, m, gamma_amp, gamma_ang, angle, skip=skip, amplitude=amplitude
            )
            for s in smooth
        ]
        selection = sels[0]
        passing = np.stack([s.kept for s in sels])
        kept = passing.any(axis=0)
        if not kept.any():
            summ = selection.rejection_summary()
            details = SomdDetails(
                h_smooth=hs,
                h_track=ht,
                smooth_output=smooth,
                track_output=track,
                selection=selection,
                kept_windows=kept,
                window_variance=np.full(n_win, np.nan),
                sample_mask=np.zeros(n, dtype=bool),
                bias_factor=factors,
                skip=skip,
            )
            diagnosis = VarianceEstimate(
                "somd-paper" if paper else "somd",
                float("nan"),
                (float("nan"), float("nan")),
                0,
                n,
                0.0,
                params,
                notes,
                details,
            )
            raise NoWindowKept(
                f"no window kept: of {summ['windows']} windows, {summ['failed_amplitude']} failed "
                f"the amplitude test (gamma_amp={gamma_amp:g}) and {summ['failed_angle']} the "
                f"angle test (gamma_ang={gamma_ang:g} deg); relax gamma_amp towards 1 or "
                "gamma_ang, use a longer window, or turn selection off",
                summ,
                diagnosis,
            )
        with np.errstate(invalid="ignore"):
            window_var = np.where(
                kept, np.sum(per_h * passing, axis=0) / np.maximum(passing.sum(axis=0), 1), np.nan
            )
        variance = float(np.nanmean(window_var))
        sample_mask = np.repeat(kept, m)
        sample_mask = np.concatenate([sample_mask, np.zeros(n - sample_mask.size, dtype=bool)])
        n_used = int(counts[kept].sum())
    else:
        kept = in_record
        window_var = np.where(in_record, per_h.mean(axis=0), np.nan)
        tail = sq[:, skip : n - 1]
        variance = float(np.mean(tail.mean(axis=1) / np.asarray(factors)))
        sample_mask = np.zeros(n, dtype=bool)
        sample_mask[skip : n - 1] = True
        n_used = n - 1 - skip
    eff = float(np.mean([_somd_efficiency(h) for h in hs]))
    dof = n_used / eff
    details = SomdDetails(
        h_smooth=hs,
        h_track=ht,
        smooth_output=smooth,
        track_output=track,
        selection=selection,
        kept_windows=kept,
        window_variance=window_var,
        sample_mask=sample_mask,
        bias_factor=factors,
        skip=skip,
    )
    method = "somd-paper" if paper else "somd"
    return VarianceEstimate(
        method, variance, chi2_interval(variance, dof), n_used, n, dof, params, notes, details
    )


def redundant_estimate(
    z: NDArray,
    reference: ArrayLike,
    reference_variance: float = 0.0,
    notes: list[str] | None = None,
) -> VarianceEstimate:
    """SOMD with a real redundant sensor, eq. [8]: ``var(V2) = E[(ΔZ1 - ΔZ2)²]/2 - var(V1)``.

    Parameters
    ----------
    z : ndarray
        The sensor whose noise is wanted (``Z2``).
    reference : array_like
        A second sensor of the same quantity (``Z1``), same length.
    reference_variance : float
        Known noise variance of the reference (0: the paper's assumption
        ``var(V1) << var(V2)``; otherwise it is subtracted exactly).
    notes : list of str, optional
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
    """
    ref, _ = as_signal(reference)
    if ref.size != z.size:
        raise NoisevarError(
            f"the reference sensor has {ref.size} samples and the signal {z.size}: "
            "give two records of the same length (align them first)"
        )
    dd = np.diff(ref) - np.diff(z)
    pair = float(np.mean(dd**2) / 2.0)
    var = pair - float(reference_variance)
    dof = dd.size / 1.5
    lo, hi = chi2_interval(pair, dof)
    return VarianceEstimate(
        "somd-redundant",
        var,
        (lo - reference_variance, hi - reference_variance),
        dd.size,
        z.size,
        dof,
        {"reference_variance": float(reference_variance)},
        list(notes or []),
    )


def estimate_redundant(sensors: ArrayLike) -> RedundantEstimate:
    """Each sensor's noise variance from two or more real sensors (spec A1).

    For every pair ``1/2 E[(ΔZi - ΔZj)²] = var_i + var_j`` (eq. [8] with both
    noises kept, systematic errors slowly varying). With three or more sensors
    the pair sums are solved for each variance by least squares (the
    three-cornered hat); with two, only the sum is identifiable and each
    sensor is given the sum as an upper bound.

    Parameters
    ----------
    sensors : array_like, shape (n, k)
        One column per sensor, same sampling instants.

    Returns
    -------
    RedundantEstimate
    """
    Z = np.asarray(sensors, dtype=float)
    if Z.ndim != 2 or Z.shape[1] < 2:
        raise NoisevarError(
            f"give two or more sensors as columns of an (n, k) array, got shape {Z.shape}"
        )
    if not np.all(np.isfinite(Z)):
        raise NoisevarError("the sensor records contain NaN or Inf: clean them first")
    n, k = Z.shape
    if n < 8:
        raise NoisevarError(f"only {n} samples per sensor: give at least 100")
    D = np.diff(Z, axis=0)
    i, j = np.triu_indices(k, 1)
    sums = np.mean((D[:, i] - D[:, j]) ** 2, axis=0) / 2.0
    pair = np.zeros((k, k))
    pair[i, j] = pair[j, i] = sums
    notes: list[str] = []
    dof_pair = (n - 1) / 1.5
    if k == 2:
        variances = np.array([sums[0], sums[0]])
        notes.append(
            "two sensors give only the sum var1 + var2; each value is that sum (an upper bound)"
        )
        ci = np.array([chi2_interval(sums[0], dof_pair)] * 2)
        return RedundantEstimate(variances, ci, pair, n, notes)
    A = np.zeros((i.size, k))
    A[np.arange(i.size), i] = 1.0
    A[np.arange(i.size), j] = 1.0
    variances, *_ = np.linalg.lstsq(A, sums, rcond=None)
    if np.any(variances < 0):
        notes.append("a negative variance was clipped to 0: that sensor's noise is below detection")
        variances = np.maximum(variances, 0.0)
    # approximate CI: propagate independent pair-sum errors through the solve
    pinv = np.linalg.pinv(A)
    sd_pairs = sums * np.sqrt(2.0 / dof_pair)
    sd = np.sqrt((pinv**2) @ (sd_pairs**2))
    ci = np.column_stack([np.maximum(variances - 1.96 * sd, 0.0), variances + 1.96 * sd])
    return RedundantEstimate(variances, ci, pair, n, notes)


# ------------------------------------------------------------------------------- MLE
def mle_estimate(z: NDArray, trend: bool, notes: list[str]) -> VarianceEstimate:
    """Irregular variance of a statsmodels ``UnobservedComponents`` model, by ML.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    trend : bool
        Local linear trend (True) or local level (False).
    notes : list of str
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
        CI from the Hessian-based standard error, on the log-variance scale.
    """
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    scale = float(np.std(np.diff(z))) or 1.0
    y = (z - z.mean()) / scale
    level = "local linear trend" if trend else "local level"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = UnobservedComponents(y, level=level)
        res = model.fit(disp=False, maxiter=200)
    retvals = getattr(res, "mle_retvals", None) or {}
    if not retvals.get("converged", True):
        notes.append(
            "the likelihood optimiser stopped without converging "
            f"(after {retvals.get('iterations', '?')} iterations): this estimate may be far off"
        )
    names = list(model.param_names)
    idx = names.index("sigma2.irregular")
    var_scaled = float(res.params[idx])
    var = var_scaled * scale**2
    try:
        se = float(res.bse[idx]) * scale**2
    except Exception:  # noqa: BLE001 - statsmodels may fail to invert the Hessian
        se = float("nan")
    if np.isfinite(se) and var > 0:
        rel = se / var
        # log-normal interval; a fit that barely identifies the noise (rel of hundreds)
        # gives (0, inf) instead of an overflow warning
        with np.errstate(over="ignore"):
            ci = (var * float(np.exp(-1.96 * rel)), var * float(np.exp(1.96 * rel)))
        dof = 2.0 / rel**2
    else:
        ci, dof = (float("nan"), float("nan")), float("nan")
    method = "mle-trend" if trend else "mle-level"
    return VarianceEstimate(method, var, ci, z.size, z.size, dof, {}, notes)


# ------------------------------------------------------------------------------- auto
AUTO_SPANS = (11, 21, 41, 81)
#: Trimmed samples are widened by half of this span (or of the longest span below it).
AUTO_MASK_SPAN = 41
AUTO_ORDER = 3
AUTO_TRIM = 5.0
AUTO_BLOCK = 256
AUTO_LEAK_SE = 3.5


@lru_cache(maxsize=64)
def residual_sequence(span: int, order: int) -> NDArray:
    """Difference sequence ``δ - w`` of a centred local-polynomial (Savitzky-Golay) fit.

    Parameters
    ----------
    span : int
        Odd number of samples of each local fit.
    order : int
        Polynomial degree; the residual is blind to polynomials up to it.

    Returns
    -------
    ndarray, shape (span,)
    """
    w = signal.savgol_coeffs(span, order)
    d = -0.5 * (w + w[::-1])  # exactly symmetric (savgol_coeffs is to about 1e-14)
    d[span // 2] += 1.0
    d.setflags(write=False)
    return d


@lru_cache(maxsize=64)
def _difference_variance_factor(span_a: int, span_b: int, order: int) -> float:
    """``sum_k (ρ_aa² + ρ_bb² - 2 ρ_ab²)``: n·var(v_a - v_b)/(2σ⁴) for two residual estimators."""
    da = residual_sequence(span_a, order)
    db = residual_sequence(span_b, order)
    da = da / np.sqrt(np.sum(da**2))
    db = db / np.sqrt(np.sum(db**2))
    raa = np.correlate(da, da, mode="full")
    rbb = np.correlate(db, db, mode="full")
    rab = np.correlate(da, db, mode="full")
    return float(np.sum(raa**2) + np.sum(rbb**2) - 2.0 * np.sum(rab**2))


@lru_cache(maxsize=64)
def _edge_residual_rows(span: int, order: int) -> tuple[NDArray, NDArray]:
    """Rows of ``I - P`` for the first and last ``span // 2`` samples of a ``span`` window.

    ``P`` is the hat matrix of a polynomial fit of degree ``order`` over the
    window; row ``h = span // 2`` is the interior sequence ``d``. The edge rows
    let the estimator use every sample, not only those a centred span fits.
    """
    h = span // 2
    i = np.arange(span, dtype=float) - h
    v = np.vander(i / max(h, 1), order + 1)
    q, _ = np.linalg.qr(v)
    resid = np.eye(span) - q @ q.T
    head, tail = resid[:h].copy(), resid[span - h :].copy()
    head.setflags(write=False)
    tail.setflags(write=False)
    return head, tail


def _residual_squares(z: NDArray, span: int, order: int, out: NDArray | None = None) -> NDArray:
    """Normalised squared residuals ``e_k² / (I - P)_kk`` of a local polynomial, every sample.

    Interior samples use the centred sequence ``d`` (``d / |d|``, symmetric:
    the compiled kernel of :mod:`noisevar.filters._fir` when :data:`USE_COMPILED`,
    else one ``np.convolve``, squared straight into ``out``); the first and last
    ``span // 2`` use the one-sided fit over the first (last) ``span``
    samples, so each square has expectation ``σ_k²`` for noise whose variance
    is locally constant.
    """
    n = z.size
    d = residual_sequence(span, order)
    h = span // 2
    out = np.empty(n) if out is None else out
    unit = d / np.sqrt(np.sum(d**2))
    if USE_COMPILED and _fir is not None:
        _fir.symmetric_fir_squares(np.ascontiguousarray(z), unit[h:].copy(), out[h : n - h])
    else:
        e = np.convolve(z, unit[::-1], mode="valid")
        np.multiply(e, e, out=out[h : n - h])
    head, tail = _edge_residual_rows(span, order)
    out[:h] = (head @ z[:span]) ** 2 / np.diag(head[:, :h])
    out[n - h :] = (tail @ z[n - span :]) ** 2 / np.diag(tail[:, span - h :])
    return out


def _truncated_second_moment(kappa: float) -> float:
    """``E[Z² ; |Z| < κ] / P(|Z| < κ)`` for a standard normal ``Z``."""
    p = 2.0 * stats.norm.cdf(kappa) - 1.0
    return float((p - 2.0 * kappa * stats.norm.pdf(kappa)) / p)


def _block_sums(x: NDArray, block: int, nb: int) -> NDArray:
    """Sums over ``nb`` consecutive blocks of ``block`` samples (the rest joins the last)."""
    sums = x[: nb * block].reshape(nb, block).sum(axis=1, dtype=float)
    sums[-1] += x[nb * block :].sum()
    return sums


def _block_square_sums(x: NDArray, block: int, nb: int) -> NDArray:
    """Sums of ``x²`` over the blocks of :func:`_block_sums`, without a squared copy of ``x``."""
    head = x[: nb * block].reshape(nb, block)
    sums = np.einsum("ij,ij->i", head, head)
    tail = x[nb * block :]
    sums[-1] += tail @ tail
    return sums


def _block_medians(x: NDArray, block: int, nb: int, stride: int) -> NDArray:
    """Median of every ``stride``-th sample of each of the first ``nb`` blocks.

    A row-wise sort of the small ``(nb, block / stride)`` array: several
    times faster than ``np.median(..., axis=1)`` on it, with the same values.
    """
    y = np.sort(x[: nb * block].reshape(nb, block)[:, ::stride], axis=1)
    k = y.shape[1]
    return y[:, k // 2] if k % 2 else 0.5 * (y[:, k // 2 - 1] + y[:, k // 2])


STEP_WINDOW = 6
STEP_THRESHOLD = 6.0
#: Above this fraction of flagged samples the step detector is ignored: what it sees is a
#: fast signal (a sinusoid of a few tens of samples per period), not jumps.
STEP_MAX_FRACTION = 0.2


def _step_mask(
    z: NDArray, above: Callable[[NDArray], NDArray], scale: float = 1.0, w: int = STEP_WINDOW
) -> NDArray:
    """Samples next to a jump, found by a step detector blind to parabolas.

    With ``M[i] = mean(z[i:i+w])``, ``D3[k] = M[k+w] - 3 M[k] + 3 M[k-w] -
    M[k-2w]`` is the third difference of four adjacent window means: zero on
    any parabola (a ramp, a turn), while a jump ``J`` gives ``|D3|`` up to
    ``2 J`` against a noise standard deviation ``σ sqrt(20 / w)``. At
    ``w = 6`` a jump of 6 σ stands 6.6 standard deviations out, where the
    cubic residual shows it only at about 2.5 (a local cubic absorbs most of
    a jump). A fast signal (a sinusoid of 30 samples per period, say) also
    trips it; :func:`_outlier_mask` then ignores it.

    ``above(x)`` tells where ``x`` exceeds ``scale`` times the local noise
    variance (:func:`_above_local`); returns the samples where ``|D3|``
    exceeds :data:`STEP_THRESHOLD` standard deviations. (The scale is folded
    into the window means, so the test costs no pass of its own: two work
    arrays, the third differences written in place.)
    """
    n = z.size
    if n < 4 * w:
        return np.zeros(n, dtype=bool)
    # mm[i] = mean(z[i:i+w]), pre-scaled so that D3² compares with threshold_var directly
    gain = np.sqrt(scale / (STEP_THRESHOLD**2 * 20.0 / w)) / w
    mm = np.convolve(z, np.full(w, gain), mode="valid")  # n - w + 1
    work = np.empty(n)
    d1 = work[: n - 2 * w + 1]
    np.subtract(mm[w:], mm[:-w], out=d1)  # third difference at lag w, as three first ones
    d2 = mm[: n - 3 * w + 1]
    np.subtract(d1[w:], d1[:-w], out=d2)
    d3 = work[2 * w : n - 2 * w + 1]  # D3 at k = 2w .. n - 2w, aligned with the samples
    np.subtract(d2[w:], d2[:-w], out=d3)
    np.multiply(d3, d3, out=d3)
    work[: 2 * w] = 0.0  # D3 is not defined there: no jump can be seen
    work[n - 2 * w + 1 :] = 0.0
    return above(work)


def _dilate(mask: NDArray, half: int) -> NDArray:
    """``mask`` widened by ``half`` samples on each side (cheap when few are set)."""
    idx = np.flatnonzero(mask)
    if idx.size > mask.size // 64:
        return maximum_filter1d(mask.view(np.uint8), 2 * half + 1).view(bool)
    out = np.zeros_like(mask)
    span = (idx[:, None] + np.arange(-half, half + 1)).ravel()
    out[span[(span >= 0) & (span < mask.size)]] = True
    return out


def _flagged_per_block(idx: NDArray, block: int, nb: int) -> NDArray:
    """How many of the sample indices ``idx`` fall in each block of :func:`_block_sums`."""
    return np.bincount(np.minimum(idx // block, nb - 1), minlength=nb).astype(float)


def _block_counts(block: int, nb: int, n: int) -> NDArray:
    """Samples per block of :func:`_block_sums` (the rest joins the last)."""
    counts = np.full(nb, float(block))
    counts[-1] += n - nb * block
    return counts


def _kept_block_sums(x: NDArray, idx: NDArray, block: int, nb: int) -> NDArray:
    """:func:`_block_sums` of ``x`` with the samples ``idx`` counted as zero; ``x`` untouched.

    Only the blocks that hold a flagged sample are summed again, from a copy
    of those blocks alone (exactly: subtracting the flagged values instead
    would let a huge outlier swamp its block's sum).
    """
    sums = _block_sums(x, block, nb)
    body = x[: nb * block].reshape(nb, block)
    inside = idx[idx < nb * block]
    rows_of = inside // block
    blocks = np.unique(rows_of)
    last = body[-1].sum()
    if blocks.size:
        rows = body[blocks]  # a copy of the flagged blocks only
        rows[np.searchsorted(blocks, rows_of), inside % block] = 0.0
        sums[blocks] = rows.sum(axis=1)
        if blocks[-1] == nb - 1:
            last = sums[-1]
    rest = x[nb * block :]
    tail = idx[idx >= nb * block]
    if tail.size:
        rest = rest.copy()
        rest[tail - nb * block] = 0.0
    if rest.size and (tail.size or (blocks.size and blocks[-1] == nb - 1)):
        sums[-1] = last + rest.sum()  # the rest of the record joins the last block
    return sums


def _above_local(x: NDArray, local: NDArray, block: int) -> NDArray:
    """``x`` above the larger local level of the two block centres around each sample.

    Block ``j``'s level holds at its centre ``(j + 1/2) block``; a sample is
    compared with the larger of the levels of the two centres around it (the
    rest of the record after the last block with the last level). Near a
    change of noise level the threshold is the higher side's: a linear
    interpolation there put the threshold for the louder samples just after a
    noise step of x3 at 3.5 of their standard deviations, and trimmed genuine
    noise in one record of ten. One blockwise comparison with the block's own
    level (a lower bound) finds the few candidates; only those are compared
    with the bracketing level (no per-sample threshold array).
    """
    n, nb = x.size, local.size
    hit = np.empty(n, dtype=bool)
    np.greater(
        x[: nb * block].reshape(nb, block), local[:, None], out=hit[: nb * block].reshape(nb, block)
    )
    np.greater(x[nb * block :], local[-1], out=hit[nb * block :])
    idx = np.flatnonzero(hit)
    if idx.size and nb > 1:
        own = np.minimum(idx // block, nb - 1)
        side = np.where(idx - own * block < block // 2, own - 1, own + 1)
        side = np.clip(side, 0, nb - 1)  # the rest of the record: the last block's level
        hit[idx[x[idx] <= np.maximum(local[own], local[side])]] = False
    return hit


def _outlier_mask(
    sq: NDArray,
    kappa: float,
    block: int,
    dilate: int,
    steps: Callable[[Callable[[NDArray], NDArray], float], NDArray] | None,
) -> NDArray | None:
    """Squared residuals that are jumps or outliers (the caller widens the mask).

    Pass 1 takes a robust local scale from block medians of ``e²`` (every
    fourth sample: plenty for a scale whose only use is a generous
    threshold); pass 2 refines it with the mean of each block's kept squares,
    so that a noise level changing along the record is followed (a noise step
    is not mistaken for outliers). Residuals beyond ``κ`` local standard
    deviations are flagged, and so are samples next to a jump found by
    ``steps(above, κ²)`` (:func:`_step_mask`). Pass 1 leaves ``dilate``
    neighbours on each side of what it flags out of the scale (a jump spreads
    over the whole span of the residual sequence); the returned mask is not
    widened, so that the caller can widen it by each span's half. Returns
    None when nothing is flagged (the common case, which then costs no
    masking).
    """
    n = sq.size
    nb = max(1, n // block)
    scale = kappa**2 / 0.4549364231195724  # the median of χ²₁ is 0.4549
    threshold = _block_medians(sq, block, nb, 4) * scale
    first = np.empty(n, dtype=bool)
    np.greater(
        sq[: nb * block].reshape(nb, block),
        threshold[:, None],
        out=first[: nb * block].reshape(nb, block),
    )
    np.greater(sq[nb * block :], threshold[-1], out=first[nb * block :])
    tau = _truncated_second_moment(kappa)
    kept_n = _block_counts(block, nb, n)
    if first.any():
        if dilate > 0:  # leave the whole neighbourhood of a jump out of the scale
            first = _dilate(first, dilate)
        idx = np.flatnonzero(first)
        kept_sum = _kept_block_sums(sq, idx, block, nb)
        kept_n -= _flagged_per_block(idx, block, nb)
    else:
        kept_sum = _block_sums(sq, block, nb)
    # κ² times the local variance of each block (held at its centre; see _above_local)
    threshold = kappa**2 * kept_sum / np.maximum(kept_n, 1.0) / tau

    def above(x: NDArray) -> NDArray:
        return _above_local(x, threshold, block)

    outlier = above(sq)
    if steps is not None:
        jumps = steps(above, kappa**2)
        if np.count_nonzero(jumps) <= STEP_MAX_FRACTION * n:  # else the signal is too fast
            outlier |= jumps
    if not outlier.any():
        return None
    return outlier


def _near_flagged(
    flagged: NDArray, idx: NDArray, spans: tuple[int, ...], half: int, sq: NDArray
) -> tuple[NDArray, NDArray, NDArray] | None:
    """Samples of the common mask ``idx`` that a shorter span can still use.

    The common mask widens flagged samples by ``half``; the residual of a
    span ``s`` at sample ``k`` reaches ``s // 2`` samples either way, so a
    sample more than ``s // 2`` from every flagged one has a clean residual
    for that span. Returns the indices of such samples, the longest usable
    span index of each, and their squared residuals for the spans up to it
    (before the caller zeroes the masked ones), or None.
    """
    usable = np.full(idx.size, -1)
    for j, s in enumerate(spans):
        if s // 2 >= half:
            break
        usable[~_dilate(flagged, s // 2)[idx]] = j
    keep = usable >= 0
    if not keep.any():
        return None
    near = idx[keep]
    return near, usable[keep], sq[: int(usable.max()) + 1, near].copy()


def auto_estimate(
    z: NDArray,
    *,
    span: int | None = None,
    order: int = AUTO_ORDER,
    trim: float = AUTO_TRIM,
    notes: list[str] | None = None,
) -> VarianceEstimate:
    """Our default: a zero-lag polynomial virtual sensor, exact normalisation, local span, trimming.

    Design (each step measured in ``benchmarks/accuracy.py``):

    1. Virtual redundant sensor. SOMD compares the raw samples with a
       smoothed copy of themselves. The causal alpha-beta-gamma filter lags
       on manoeuvres and its differenced comparison ``Δ(g - δ)`` wastes
       efficiency (``sum ρ²`` about 1.5, like Rice's estimator). We use
       instead a centred local polynomial of degree ``order`` (cubic) over
       ``span`` samples (a Savitzky-Golay smoother): no lag, blind to every
       polynomial up to that degree (ramps, parabolas, constant-jerk
       stretches: the slowly varying systematic error of SOMD's eq. [6]),
       and the residual ``e = z - Z1 = d * z``, ``d = δ - w``, has nearly
       independent squares (``sum ρ²`` 1.18 for a span of 21, 1.08 for 41,
       against 1.17 for the best third-order Hall-Kay-Titterington sequence
       and 1.94 for the second difference).
    2. Exact normalisation: the noise part of ``e`` has variance
       ``σ² sum(d²)``; dividing by ``sum(d²)`` is the analogue of our
       ``c(h)`` correction of the paper's factor 1/2.
    3. Robust trimming (the paper's window selection, made local):
       residuals of the shortest span beyond ``trim`` (5) local standard
       deviations are flagged with their neighbours over the longest span
       (up to 41) and left out of every span's choice. In the estimate, a
       sample of that neighbourhood still counts with the longest span (at
       most its block's) whose residual reaches no flagged sample: a spike
       or a jump costs 20 to 35 samples instead of 50 to 65 (steps-ramps,
       n = 1000: RMSE 5.74 -> 5.21 %, bias -0.62 -> -0.40 %, 200 runs). The
       local scale follows a noise level that changes along the record
       (near a change of level, the higher of the two neighbouring blocks'
       levels: genuine noise just after a x3 noise step was trimmed in one
       record of ten, -0.10 % bias and RMSE 2.47 % against 2.42 % on
       noise-step at n = 6000).
    4. Local span (again window selection, but measured): a longer span
       is more efficient but lets more of a fast signal through, and
       leakage only ever adds variance. In each block of 256 samples the
       span is lengthened (11, 21, 41, 81) while each step's mean square
       does not exceed the previous span's by more than 3.5 standard errors
       of their exact difference (consecutive spans are strongly
       correlated, so the test is sharp: 0.14 against 0.37 for 41 against
       11). Smooth stretches get span 81, manoeuvres a short span. (At 2.5
       standard errors, chance rejections on pure noise cost a -0.25 %
       selection bias; 3.5 keeps every family of the benchmark within about
       0.4 %. The difference of two spans' mean squares is right-skewed,
       so 3.5 Gaussian standard errors are exceeded by chance more often
       than nominal, 0.2 to 0.4 % of tests on white noise; a threshold from
       a χ² matched to its first three cumulants, at a level of equal
       power on fast-slow, changed no family's RMSE by more than 1 %, and
       was left out.) Span 81 is worth 5 to 7 % of RMSE on smooth records of
       1000 samples (random-jerk 4.71 to 4.40 %, noise-ramp 5.74 to 5.39 %,
       200 paired runs), where the state-space MLE was level with or ahead
       of a span of at most 41. Its residuals reach 40 samples into the
       next blocks, so a block takes it only where both neighbours reached
       41 as well (a fast burst next door otherwise leaks into the first
       samples of the block, too few for the block's test: +1.4 % bias on
       fast-slow at n = 1000 without this rule, +0.6 % with it, +0.4 % with
       spans up to 41), and only where its wider neighbourhood of trimmed
       samples (flagged samples are widened by 20, half of 41) leaves the
       block alone.
    5. Jumps the cubic absorbs (a local cubic hides most of a jump of a
       few σ) are found by a third difference of window means, blind to
       parabolas (:func:`_step_mask`), and left out like outliers; the
       first and last ``span // 2`` samples use one-sided fits, so every
       sample counts and a noise level that drifts along the record is
       weighted as it should be.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    span : int, optional
        Fix one span instead of choosing per block (odd, > order + 1).
    order : int
        Polynomial degree of the virtual sensor (1 to 6).
    trim : float
        Trimming threshold in local standard deviations (``inf``: none).
    notes : list of str, optional
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
        ``params["span"]`` is the requested span (None: chosen per block, and
        a note gives the sample-weighted mean span used), so that
        ``estimate(z, **params)`` reproduces the estimate.
    """
    notes = list(notes or [])
    order = int(order)
    if not 1 <= order <= 6:
        raise NoisevarError(f"order must be between 1 and 6, got {order}")
    trim = float(trim)
    if not trim > 1.0:
        raise NoisevarError(f"trim must be above 1 (standard deviations), got {trim}")
    if span is not None:
        span = int(span)
        if span % 2 == 0 or span <= order + 1:
            raise NoisevarError(f"span must be odd and larger than order + 1, got {span}")
        spans: tuple[int, ...] = (span,)
    else:
        spans = tuple(s for s in AUTO_SPANS if s > order + 1)
        spans = tuple(s for s in spans if 4 * s <= z.size) or spans[:1]
    n = z.size
    if n < 2 * max(spans):
        raise NoisevarError(
            f"too few samples ({n}) for the auto estimator: give at least {2 * max(spans)}"
        )
    m = n
    sq = np.empty((len(spans), m))
    for j, s in enumerate(spans):
        _residual_squares(z, s, order, out=sq[j])
    block = AUTO_BLOCK if m >= 2 * AUTO_BLOCK else max(m // 2, 16)
    nb = max(1, m // block)
    # flagged samples are widened by half the longest span up to AUTO_MASK_SPAN; a
    # longer span is used only in blocks that its wider neighbourhood leaves alone
    half = max(s for s in spans if s <= max(AUTO_MASK_SPAN, spans[0])) // 2
    flagged = (
        _outlier_mask(sq[0], trim, block, half, lambda var, sc: _step_mask(z, var, sc))
        if np.isfinite(trim)
        else None
    )
    tau = _truncated_second_moment(trim) if np.isfinite(trim) else 1.0
    kept_count = _block_counts(block, nb, m)
    recover = None
    clean_for = np.ones((len(spans), nb), dtype=bool)  # span j's residuals untouched here
    if flagged is not None:
        idx = np.flatnonzero(_dilate(flagged, half) if half > 0 else flagged)
        if idx.size == m:
            raise NoisevarError(
                "every residual was trimmed as an outlier: the signal is not usable"
            )
        per_block = _flagged_per_block(idx, block, nb)
        kept_count -= per_block
        recover = _near_flagged(flagged, idx, spans, half, sq)
        sq[:, idx] = 0.0  # sq is ours: trimmed residuals count as zero
        for j, s in enumerate(spans):
            if s // 2 > half:
                wide = _flagged_per_block(np.flatnonzero(_dilate(flagged, s // 2)), block, nb)
                clean_for[j] = wide == per_block
    block_sum = np.stack([_block_sums(q, block, nb) for q in sq])
    fourth = _block_square_sums(sq[0], block, nb)
    with np.errstate(invalid="ignore", divide="ignore"):
        block_mean = block_sum / kept_count
        rms4 = np.sqrt(fourth / kept_count / 3.0)  # = σ² for Gaussian noise
    choice = np.zeros(nb, dtype=int)
    open_ = np.ones(nb, dtype=bool)  # still lengthening the span in this block
    for j in range(1, len(spans)):
        with np.errstate(invalid="ignore", divide="ignore"):  # a block may be all trimmed
            se = rms4 * np.sqrt(
                2.0 * _difference_variance_factor(spans[j - 1], spans[j], order) / kept_count
            )
        ok = open_ & clean_for[j] & (block_mean[j] - block_mean[j - 1] <= AUTO_LEAK_SE * se)
        if spans[j] > AUTO_MASK_SPAN and nb > 1:
            # a long span reaches into the neighbouring blocks: only where they are smooth
            # too (a fast burst next door leaks into the first samples of this block)
            smooth = choice >= j - 1
            ok[1:] &= smooth[:-1]
            ok[:-1] &= smooth[1:]
        choice[ok] = j
        open_ &= ok
    chosen_sum = block_sum[choice, np.arange(nb)]
    if recover is not None:
        # samples the common mask left out whose shorter-span residual reaches no flagged
        # sample count with that span (at most the block's own)
        near, usable, values = recover
        rows = np.minimum(near // block, nb - 1)
        use = np.minimum(choice[rows], usable)
        chosen_sum = chosen_sum + np.bincount(
            rows, weights=values[use, np.arange(near.size)], minlength=nb
        )
        kept_count = kept_count + np.bincount(rows, minlength=nb)
    n_kept = int(kept_count.sum())
    var = float(chosen_sum.sum() / (n_kept * tau))
    span_used = np.asarray(spans)[choice]
    eff = np.asarray([sequence_efficiency(residual_sequence(s, order)) for s in spans])[choice]
    dof = float(np.sum(kept_count / eff)) * (0.98 if np.isfinite(trim) else 1.0)
    trimmed = m - n_kept
    if trimmed > 0.01 * n:
        notes.append(f"{trimmed} residuals ({trimmed / n:.1%}) left out as jumps or outliers")
    short = float(np.sum(kept_count[choice < len(spans) - 1]) / max(n_kept, 1))
    if len(spans) > 1 and short > 0.05:
        notes.append(f"{short:.0%} of the record needed a shorter span (fast signal there)")
    if len(spans) > 1:
        mean_span = float(np.sum(span_used * kept_count) / max(n_kept, 1))
        notes.append(f"span chosen per block of {block} samples: mean {mean_span:.1f}")
    # params are the config form (estimate(z, **params) reproduces this result):
    # the requested span, None when it is chosen per block.
    params = {"span": span, "order": order, "trim": trim}
    return VarianceEstimate("auto", var, chi2_interval(var, dof), n_kept, n, dof, params, notes)


# --------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class Method:
    """A registered estimator: its name, a one-line description and its function."""

    name: str
    description: str
    kind: str
    func: Callable[..., VarianceEstimate]


def _rice(z, notes, **_):
    return difference_estimate(z, [1.0, -1.0], "rice", {}, notes)


def _diff2(z, notes, **_):
    return difference_estimate(z, [1.0, -2.0, 1.0], "diff2", {}, notes)


def _hkt(order):
    def f(z, notes, **_):
        return difference_estimate(z, HKT_SEQUENCES[order], f"hkt{order}", {}, notes)

    return f


def _mad_diff(z, notes, **_):
    dz = np.diff(z)
    var = _mad_variance(dz) / 2.0
    dof = dz.size * MAD_EFFICIENCY / 1.5
    return VarianceEstimate(
        "mad-diff", var, chi2_interval(var, dof), dz.size, z.size, dof, {}, notes
    )


def _wavelet_mad(z, notes, wavelet="db4", **_):
    import pywt

    try:
        wav = pywt.Wavelet(wavelet)
    except ValueError:
        raise NoisevarError(f"unknown wavelet {wavelet!r}: try 'db4' or 'sym8'") from None
    _, detail = pywt.dwt(z, wav, mode="periodization")
    sigma = np.median(np.abs(detail)) * MAD_TO_SIGMA
    var = float(sigma**2)
    dof = detail.size * MAD_EFFICIENCY
    params = {"wavelet": wavelet}
    return VarianceEstimate(
        "wavelet-mad", var, chi2_interval(var, dof), z.size, z.size, dof, params, notes
    )


def _somd_paper(z, notes, **p):
    p.setdefault("gamma_ang", 5.0)
    return somd_estimate(z, paper=True, notes=notes, **p)


def _somd(z, notes, **p):
    return somd_estimate(z, paper=False, notes=notes, **p)


def _somd_redundant(z, notes, reference=None, reference_variance=0.0, **_):
    if reference is None:
        raise NoisevarError(
            "somd-redundant needs a second sensor: pass reference=<array> (CLI: --reference-column)"
        )
    return redundant_estimate(z, reference, reference_variance, notes)


def _auto(z, notes, span=None, order=AUTO_ORDER, trim=AUTO_TRIM, **_):
    return auto_estimate(z, span=span, order=order, trim=trim, notes=notes)


_SOMD_KEYS = (
    "h_smooth",
    "h_track",
    "track_ratio",
    "window",
    "gamma_amp",
    "gamma_ang",
    "angle",
    "select",
)

METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method("auto", "robust zero-lag polynomial virtual sensor (our default)", "ours", _auto),
        Method(
            "somd", "SOMD, alpha-beta-gamma virtual sensor, exact c(h) correction", "somd", _somd
        ),
        Method("somd-paper", "SOMD exactly as printed (factor 1/2)", "somd", _somd_paper),
        Method("somd-redundant", "SOMD with a real second sensor, eq. 8", "somd", _somd_redundant),
        Method("rice", "Rice first difference mean(Δz²)/2", "peer", _rice),
        Method("diff2", "second difference mean((Δ²z)²)/6", "peer", _diff2),
        Method("hkt1", "Hall-Kay-Titterington optimal difference, order 1", "peer", _hkt(1)),
        Method("hkt2", "Hall-Kay-Titterington optimal difference, order 2", "peer", _hkt(2)),
        Method("hkt3", "Hall-Kay-Titterington optimal difference, order 3", "peer", _hkt(3)),
        Method("mad-diff", "median absolute deviation of first differences", "peer", _mad_diff),
        Method(
            "wavelet-mad", "Donoho-Johnstone MAD of finest wavelet details", "peer", _wavelet_mad
        ),
        Method(
            "mle-level",
            "state-space ML, local level (statsmodels)",
            "peer",
            lambda z, notes, **_: mle_estimate(z, False, notes),
        ),
        Method(
            "mle-trend",
            "state-space ML, local linear trend (statsmodels)",
            "peer",
            lambda z, notes, **_: mle_estimate(z, True, notes),
        ),
    ]
}

_METHOD_KEYS = {
    "somd": _SOMD_KEYS,
    "somd-paper": _SOMD_KEYS,
    "somd-redundant": ("reference", "reference_variance"),
    "auto": ("span", "order", "trim"),
    "wavelet-mad": ("wavelet",),
}


def methods(kind: str | None = None) -> list[str]:
    """Names of the available estimators.

    Parameters
    ----------
    kind : {"ours", "somd", "peer"}, optional
        Only methods of this kind.

    Returns
    -------
    list of str
    """
    return [m.name for m in METHODS.values() if kind is None or m.kind == kind]


def describe_methods() -> dict[str, str]:
    """Method name to one-line description."""
    return {m.name: m.description for m in METHODS.values()}


def estimate(z: ArrayLike, method: str = "auto", **params: Any) -> VarianceEstimate:
    """Estimate the measurement-noise variance of one signal.

    Parameters
    ----------
    z : array_like, shape (n,)
        Samples, uniformly spaced.
    method : str
        One of :func:`methods`; default ``"auto"``.
    **params
        Method parameters: ``h_smooth``, ``h_track``, ``track_ratio``,
        ``window``, ``gamma_amp``, ``gamma_ang`` (degrees), ``angle``,
        ``select`` (SOMD methods); ``reference``, ``reference_variance``
        (``somd-redundant``); ``span``, ``order``, ``trim`` (``auto``);
        ``wavelet`` (``wavelet-mad``); ``drop_nonfinite`` (all). Parameters
        that a method does not use are ignored; unknown names are refused.

    Returns
    -------
    VarianceEstimate
        ``.variance``, ``.std``, ``.ci95``, ``.n_used``, ``.params`` and, for
        SOMD methods, ``.details`` with the arrays the dashboard draws.

    Raises
    ------
    NoisevarError
        Bad input or parameters, with a message that says what to do.

    Examples
    --------
    >>> import numpy as np, noisevar
    >>> z = np.sin(np.arange(5000) / 200) * 50 + np.random.default_rng(0).normal(0, 2, 5000)
    >>> round(noisevar.estimate(z).std, 1)
    2.0
    """
    if method not in METHODS:
        raise NoisevarError(f"unknown method {method!r}; choose one of: {', '.join(methods())}")
    unknown = set(params) - KNOWN_PARAMS
    if unknown:
        raise NoisevarError(
            f"unknown parameter(s) {', '.join(sorted(unknown))}; "
            f"known: {', '.join(sorted(KNOWN_PARAMS))}"
        )
    drop = bool(params.pop("drop_nonfinite", False))
    z_arr, notes = as_signal(z, drop_nonfinite=drop)
    keys = _METHOD_KEYS.get(method, ())
    used = {k: v for k, v in params.items() if k in keys and v is not None}
    result = METHODS[method].func(z_arr, notes, **used)
    result.params = {"method": method, **result.params}
    return result
