"""Quantised records at low noise: the rounding error ``auto``'s residual misses (§E3).

On a grid of step ``Δ`` with noise ``σ`` below about ``Δ/2``, the mean rounding error
``b(c)`` follows the clean signal ``c``; where the signal moves slowly against ``Δ``
the residual filter removes it with the signal. :func:`quantisation_correction` looks
the rounding error's mean and variance up at the record's own offsets within a step
(from a local polynomial estimate of the signal), solves for ``σ`` the residual's mean
square and reports the error variance (docs/algorithms.md §E3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy import optimize, signal, special

from noisevar.diagnostics.quantisation import LSB_TOL
from noisevar.estimators.results import VarianceEstimate
from noisevar.numeric.fir import centred_fir, residual_sequence

#: Corrected only below this noise standard deviation, in steps: above it the mean
#: rounding error ``b`` is under 1e-4 of the error variance.
QUANT_MAX_SIGMA = 0.45
#: Degree of the local polynomial fit that estimates the clean signal, and its span
#: (samples): a first fit over :data:`SMOOTH_SPAN` measures how far the signal travels;
#: the fit then spans about :data:`SMOOTH_STEPS` steps of it on average, within
#: :data:`SMOOTH_LIMITS` and a quarter of the record.
SMOOTH_ORDER = 3
SMOOTH_SPAN = 201
SMOOTH_STEPS = 4.0
SMOOTH_LIMITS = (101, 8191)
#: Rounds of taking the mean rounding error out of ``ĉ`` and solving again for ``σ``.
ROUNDS = 3
#: Offsets within a step at which ``b`` and ``V`` are tabulated.
TABLE = 1024
#: At most this many positions enter the model (in :data:`PIECES` evenly spread runs).
MAX_POSITIONS = 1 << 16
PIECES = 32
#: Corrected only when the signal crosses on average at least this many steps per
#: span of the fit: slower, ``ĉ`` cannot tell the signal from the mean rounding error
#: ``b`` that follows it (a bias, not noise: a note says so).
MIN_STEPS_PER_SPAN = 1.5
#: A level jump (not rounding): means over :data:`JUMP_WINDOW` samples either side of a
#: sample differ, ``ĉ``'s change taken out, by more than this many steps (rounding and
#: noise under half a step move them by at most about one).
JUMP_STEPS = 1.5
JUMP_WINDOW = 40
#: Smallest noise, in steps, the solver tries (the tables need ``σ > 0``).
_SIGMA_FLOOR = 1e-3
_U = np.arange(TABLE + 1) / TABLE


@dataclass(frozen=True)
class QuantCorrection:
    """What the correction found.

    Attributes
    ----------
    sigma : float
        The noise standard deviation before rounding, in grid steps.
    factor : float
        The error variance over what the residual saw (1 when not applied).
    travel : float
        Steps the signal travels over the record.
    per_span : float
        Steps it travels per span of the fit, on average.
    fit : int
        The span of the fit that estimates the clean signal.
    """

    sigma: float
    factor: float
    travel: float
    per_span: float
    fit: int

    @property
    def applied(self) -> bool:
        """The signal moves fast enough for the model (:data:`MIN_STEPS_PER_SPAN`)."""
        return self.per_span >= MIN_STEPS_PER_SPAN


def rounding_tables(s: float) -> tuple[NDArray, NDArray]:
    """``b(u) = E[Q(u + n)] - u`` and ``V(u) = Var[Q(u + n)]`` at offsets ``u`` in [0, 1].

    Parameters
    ----------
    s : float
        The noise standard deviation in steps (> 0).

    Returns
    -------
    b, V : ndarray, shape (TABLE + 1,)
    """
    k = int(np.ceil(8.0 * s)) + 1
    j = np.arange(-k, k + 2, dtype=float)  # grid points within 8 σ of every u
    # P(Q = j) = Φ((j + 1/2 - u)/σ) - Φ((j - 1/2 - u)/σ)
    p = special.ndtr((j + 0.5 - _U[:, None]) / s) - special.ndtr((j - 0.5 - _U[:, None]) / s)
    mean = p @ j
    return mean - _U, p @ (j * j) - mean * mean


def _pieces(n: int, span: int, fit: int) -> list[tuple[int, int, int, int]]:
    """The model's pieces ``(lo, a, b, hi)``: positions ``[a, b)`` read as ``[lo, hi)``.

    Positions are at least ``span // 2`` from an end (the residual's reach); each piece
    is read with ``fit // 2`` times ``ROUNDS + 1`` more samples on either side
    (the record's ends clip it), so that its smoothing is that of the whole record.
    """
    h = span // 2
    pad = h + (ROUNDS + 1) * (fit // 2)
    inner = n - 2 * h
    if inner <= MAX_POSITIONS:
        return [(0, h, n - h, n)]
    size = MAX_POSITIONS // PIECES
    step = (inner - size) // (PIECES - 1)
    starts = [h + i * step for i in range(PIECES)]
    return [(max(a - pad, 0), a, a + size, min(a + size + pad, n)) for a in starts]


@lru_cache(maxsize=4)
def _edge_rows(span: int, order: int) -> tuple[NDArray, NDArray, NDArray]:
    """The fit's centred coefficients and its rows for the first and last ``span // 2``."""
    r = span // 2
    # P = Q Q': the hat matrix of a polynomial fit over the window (savgol_filter's edges)
    q, _ = np.linalg.qr(np.vander((np.arange(span, dtype=float) - r) / r, order + 1))
    hat = q @ q.T
    return hat[r].copy(), hat[:r].copy(), hat[span - r :].copy()


def _smooth(x: NDArray, fit: int) -> NDArray:
    """The centred local polynomial fit of ``x`` over ``fit`` samples (:data:`SMOOTH_ORDER`).

    The first and last ``fit // 2`` samples take the fit over the first (last) ``fit``
    samples: ``scipy.signal.savgol_filter(mode="interp")``'s numbers (tested), with an
    FFT convolution and cached edge rows, since its direct convolution costs ``n`` times
    ``fit`` (up to 8191) for every round of :meth:`Offsets.debias`.
    """
    w, head, tail = _edge_rows(fit, SMOOTH_ORDER)
    return np.concatenate([head @ x[:fit], signal.oaconvolve(x, w, mode="valid"), tail @ x[-fit:]])


@dataclass
class Offsets:
    """The record, in steps, as the model reads it: per piece, ``z`` and ``ĉ``.

    Attributes
    ----------
    z : list of ndarray
        Per piece, the samples read (in steps).
    c : list of ndarray
        Per piece, the estimate ``ĉ`` of the clean signal over the same samples.
    keep : list of (int, int)
        Per piece, the positions ``[a, b)`` within the samples read.
    use : list of ndarray of bool, optional
        Per piece, over ``[a - h, b + h)`` (``h`` half the residual's span): the samples
        clear of level jumps (default: all).
    cuts : list of ndarray, optional
        Per piece, where level jumps split it (``ĉ`` is fitted between them).
    fit : int
        The span of the fit.
    """

    z: list[NDArray]
    c: list[NDArray]
    keep: list[tuple[int, int]]
    use: list[NDArray] | None = None
    cuts: list[NDArray] | None = None
    fit: int = SMOOTH_SPAN

    def debias(self, s: float) -> None:
        """``ĉ ← smooth(z - b(ĉ))`` with noise ``s``: the mean rounding error taken out."""
        b_tab, _ = rounding_tables(s)
        cuts = self.cuts or [np.zeros(0, dtype=int)] * len(self.z)
        parts = zip(self.z, self.c, cuts, strict=True)
        self.c = [
            _smooth_between(z - np.interp(c % 1.0, _U, b_tab), k, self.fit) for z, c, k in parts
        ]

    def travel(self, n: int) -> float:
        """Steps ``ĉ`` travels over the record (scaled from the positions).

        Measured over a quarter span of the fit, so that its noise adds little: the mean
        of ``|ĉ[i + step] - ĉ[i]|`` over every ``i`` (every phase of the subsample), not
        one phase's, which moved with the samples dropped before it (traffic's A320
        pitch: 24.6 steps, 35.0 with its first sample dropped, and the correction x3.5
        was made or not: issue 26).
        """
        moved = count = 0.0
        for c, (a, b) in zip(self.c, self.keep, strict=True):
            step = max(1, min(self.fit // 4, (b - a) // 8))
            if b - a <= step:
                continue
            moved += float(np.nansum(np.abs(c[a + step : b] - c[a : b - step]))) / step
            count += b - a - step
        return moved * (n - 1) / max(count, 1.0)


def record_offsets(
    read: Callable[[int, int], NDArray], n: int, lsb: float, span: int
) -> Offsets | None:
    """``ĉ``, a centred local polynomial fit of ``z / lsb``, over the model's pieces.

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b`` of the record.
    n : int
        Samples in the record.
    lsb : float
        The grid step.
    span : int
        The residual sequence's span (``ĉ`` reaches ``span // 2`` past each position).

    Returns
    -------
    Offsets or None
        None when the record is too short.
    """
    lo, hi = SMOOTH_LIMITS
    first = min(SMOOTH_SPAN, n // 4 // 2 * 2 + 1)
    off = None if first < lo else _offsets_at(read, n, lsb, span, first)
    if off is None:
        return None
    travel = off.travel(n)
    # the fit spans about SMOOTH_STEPS steps of the signal on average
    want = SMOOTH_STEPS * (n - 1) / travel if travel > 0 else np.inf
    fit = int(min(max(want, lo), hi, n // 4)) // 2 * 2 + 1
    return off if fit == first else _offsets_at(read, n, lsb, span, fit)


def _offsets_at(
    read: Callable[[int, int], NDArray], n: int, lsb: float, span: int, fit: int
) -> Offsets | None:
    """:func:`record_offsets` with a fit of ``fit`` samples."""
    h = span // 2
    zs, keep = [], []
    for lo, a, b, hi in _pieces(n, span, fit):
        x = read(lo, hi)
        zs.append(undrifted((x - x[0]) / lsb))  # from a grid point: it may be offset from 0
        keep.append((a - lo, b - lo))
    cuts = [_level_jumps(z, _smooth(z, fit)) for z in zs]
    cs = [_smooth_between(z, k, fit) for z, k in zip(zs, cuts, strict=True)]
    use = [_clear_of(k, c, a - h, b + h, h) for k, c, (a, b) in zip(cuts, cs, keep, strict=True)]
    if sum(int(u[h : u.size - h].sum()) for u in use) < fit:
        return None
    return Offsets(zs, cs, keep, use, cuts, fit)


def undrifted(u: NDArray) -> NDArray:
    """``u`` (in grid steps, from a grid point) less the drift of a grid that moves.

    A linear trend added to a quantised record moves its grid by a fixed fraction ``a`` of
    a step per sample: every first difference is then ``a`` plus a whole number of steps
    (its second differences stay on the grid, ``diagnostics.lsb``). The rounding error
    is the record's own offset from the moved grid, ``u - a k``; ``u`` itself when its
    first differences are not so, each within :data:`LSB_TOL` of a step (``a`` = 0 on a
    grid that does not move). The trend's whole steps per sample go too (the median first
    difference less ``a``, rounded): they leave the offsets as they are, but the signal's
    travel, and so the fit's span, read them (a trend moved a 64 ft/min vertical rate's
    R x0.68: issue 26).
    """
    if u.size < 2:
        return u
    d = np.diff(u)
    a = float(d[0] - np.rint(d[0]))
    r = d - a
    if not float(np.max(np.abs(r - np.rint(r)))) < LSB_TOL:
        return u
    # and the whole steps of the drift: the median first difference's (rounded)
    drift = a + float(np.rint(np.median(r)))
    return u if drift == 0.0 else u - drift * np.arange(u.size)


def _smooth_between(x: NDArray, cuts: NDArray, fit: int) -> NDArray:
    """:func:`_smooth` of each stretch of ``x`` between ``cuts`` (NaN where too short)."""
    out = np.full(x.size, np.nan)
    edges = [0, *cuts.tolist(), x.size]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        if b - a >= fit:
            out[a:b] = _smooth(x[a:b], fit)
    return out


def _clear_of(cuts: NDArray, c: NDArray, a: int, b: int, h: int) -> NDArray:
    """Samples ``[a, b)`` with ``ĉ`` fitted and no jump within the residual's or test's reach."""
    ok = np.isfinite(c[a:b])
    if cuts.size:
        reach = h + JUMP_WINDOW
        p = np.arange(a, b)
        i = np.minimum(np.searchsorted(cuts, p - reach), cuts.size - 1)
        ok &= ~((cuts[i] >= p - reach) & (cuts[i] <= p + reach))
    return ok


def _level_jumps(z: NDArray, c: NDArray) -> NDArray:
    """Where the record jumps by more than rounding can (:data:`JUMP_STEPS`), one per jump.

    ``c`` is a smooth fit of ``z``; the test is the difference of the means of ``z - c``
    over :data:`JUMP_WINDOW` samples after and before each sample.
    """
    m = JUMP_WINDOW
    s = np.concatenate([[0.0], np.cumsum(z - c)])
    k = np.arange(m, z.size - m + 1)
    d = np.abs(s[k + m] - 2.0 * s[k] + s[k - m]) / m
    big = np.flatnonzero(d > JUMP_STEPS)
    if not big.size:
        return np.zeros(0, dtype=int)
    # each run of samples over the threshold is one jump, where the difference peaks
    runs = np.split(big, np.flatnonzero(np.diff(big) > m) + 1)
    return np.asarray([k[r[np.argmax(d[r])]] for r in runs], dtype=int)


def rounding_model(off: Offsets, s: float, span: int, order: int) -> tuple[float, float]:
    """What the residual sees and the error variance, in steps², with noise ``s`` steps.

    Parameters
    ----------
    off : Offsets
    s : float
        Noise standard deviation before rounding, in steps.
    span, order : int
        The residual sequence (:func:`noisevar.estimators.auto.residual_sequence`).

    Returns
    -------
    seen, truth : float
    """
    b_tab, v_tab = rounding_tables(s)
    u = _unit(span, order)
    h = span // 2
    seen = truth = 0.0
    seen_count = truth_count = 0
    for c, (a, b), use in zip(off.c, off.keep, _uses(off, h), strict=True):
        f = c[a - h : b + h] % 1.0
        bias = np.interp(f, _U, b_tab)
        v = np.interp(f, _U, v_tab)
        at = use[h : use.size - h]
        # seen = mean V + mean (u ⋆ b)² over the positions        (E3.4)
        seen_k = v[h : v.size - h] + np.convolve(bias, u, mode="valid") ** 2
        seen += float(seen_k[at].sum())
        # truth = mean (b² + V), the positions and the residual's reach   (E3.3)
        truth += float(np.sum((bias * bias + v)[use]))
        seen_count += int(at.sum())
        truth_count += int(use.sum())
    return seen / seen_count, truth / truth_count


def _uses(off: Offsets, h: int) -> list[NDArray]:
    """``off.use``, or every sample of ``[a - h, b + h)`` in each piece."""
    if off.use is not None:
        return off.use
    return [np.ones(b - a + 2 * h, dtype=bool) for a, b in off.keep]


def own_seen(off: Offsets, span: int, order: int) -> float:
    """The residual's mean square over the model's positions, in steps²."""
    u = _unit(span, order)
    h = span // 2
    total = count = 0.0
    for z, (a, b), use in zip(off.z, off.keep, _uses(off, h), strict=True):
        at = use[h : use.size - h]
        total += float(np.sum(centred_fir(z[a - h : b + h], u, square=True)[at]))
        count += int(at.sum())
    return total / count


@lru_cache(maxsize=16)
def _unit(span: int, order: int) -> NDArray:
    """The residual sequence of unit norm (symmetric)."""
    d = residual_sequence(span, order)
    return d / np.sqrt(np.sum(d * d))


def solve_sigma(off: Offsets, seen: float, span: int, order: int) -> float:
    """``σ`` (in steps) such that the model's ``seen(σ)`` is ``seen`` (steps²)."""

    def f(s: float) -> float:
        return rounding_model(off, s, span, order)[0] - seen

    if f(_SIGMA_FLOOR) >= 0.0:
        return _SIGMA_FLOOR
    hi = np.sqrt(max(seen, 1.0 / 12.0)) + 1.0
    return float(optimize.brentq(f, _SIGMA_FLOOR, hi, xtol=1e-10, rtol=1e-10))


def small_against_step(variance: float, lsb: float) -> bool:
    """An error variance under that of noise of :data:`QUANT_MAX_SIGMA` steps, rounded."""
    x = variance / lsb**2
    # σ² + Δ²/12 with σ below QUANT_MAX_SIGMA steps
    return bool(np.isfinite(x) and 0.0 < x < QUANT_MAX_SIGMA**2 + 1.0 / 12.0)


def quantisation_correction(
    read: Callable[[int, int], NDArray],
    n: int,
    lsb: float,
    seen: float,
    span: int,
    order: int,
) -> QuantCorrection | None:
    """The correction for a quantised record whose residual saw ``seen`` (§E3).

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b``.
    n : int
        Samples in the record.
    lsb : float
        The grid step found in the record.
    seen : float
        The variance the residual measured.
    span, order : int
        The residual sequence used.

    Returns
    -------
    QuantCorrection or None
        None when the noise is above :data:`QUANT_MAX_SIGMA` steps (nothing to correct)
        or the record is too short.

    Notes
    -----
    ``b`` and ``V`` are looked up at the record's own offsets ``ĉ mod 1`` (E3.3); ``σ``
    solves ``seen(σ) = seen`` (E3.4) and the factor is ``truth(σ) / seen``.
    """
    x = seen / lsb**2
    if not small_against_step(seen, lsb):
        return None
    off = record_offsets(read, n, lsb, span)
    if off is None:
        return None
    own = own_seen(off, span, order)
    s = solve_sigma(off, own, span, order)
    for _ in range(ROUNDS):
        off.debias(s)
        s = solve_sigma(off, own, span, order)
    truth = rounding_model(off, s, span, order)[1]
    travel = off.travel(n)
    corr = QuantCorrection(s, 1.0, travel, travel * off.fit / n, off.fit)
    # the error variance over what auto's residual saw
    return replace(corr, factor=truth / x) if corr.applied else corr


def apply_correction(
    result: VarianceEstimate, corr: QuantCorrection, other: QuantCorrection | None = None
) -> VarianceEstimate:
    """``result`` with the variance, its interval and the core scaled, and a note.

    ``other``: the correction read through the shortest span (:func:`correct`); the
    interval then runs from the lower factor's bottom to the higher's top.
    The note speaks in grid steps (the record may have been scaled by a power of two).
    """
    if not corr.applied:
        note = (
            f"the noise is small against the grid step (about {corr.sigma:.2f} of a step) and "
            f"the signal crosses only {corr.travel:.1f} steps ({corr.per_span:.2f} per "
            f"{corr.fit} samples): too slow to tell from the mean rounding error, a bias "
            "that follows the signal, which the variance leaves out; not corrected "
            "(docs/algorithms.md §E3)"
        )
        return replace(result, notes=[*result.notes, note])
    k = corr.factor
    core = None if result.core_variance is None else result.core_variance * k
    note = (
        f"the noise is small against the grid step (about {corr.sigma:.2f} of a step): the "
        "rounding error partly follows the signal and the residual misses that part, so the "
        f"variance was multiplied by {k:.4f} (docs/algorithms.md §E3)"
    )
    lo, hi = result.ci95
    ks = (k,) if other is None or not other.applied else (k, other.factor)
    if len(ks) > 1:
        note += (
            f"; through the shortest span the factor is {ks[1]:.4f} (rounding error and "
            "white noise read the same through any span, signal leaking through does not), "
            "and the interval carries both"
        )
    return replace(
        result,
        variance=result.variance * k,
        ci95=(lo * min(ks), hi * max(ks)),
        core_variance=core,
        notes=[*result.notes, note],
    )


def correct(
    result: VarianceEstimate,
    lsb: float,
    record: Callable[[int, int], NDArray] | None,
    span: int,
    order: int,
    shortest: int | None = None,
) -> VarianceEstimate:
    """``result`` corrected for the rounding error its residual misses (§E3).

    Parameters
    ----------
    result : VarianceEstimate
        ``auto``'s estimate on a record on a grid of step ``lsb``.
    lsb : float
    record : callable or None
        ``record(a, b)`` gives samples ``a .. b`` of the record in one uniform segment;
        None for a record in several (gaps): it is not corrected, and a note says so
        when it would be.
    span, order : int
        The residual sequence the correction reads (``auto``'s longest span).
    shortest : int, optional
        ``auto``'s shortest span: the correction is read through it too, and R's interval
        carries both factors (docs/algorithms.md §E3 *The factor's own spread*).

    Returns
    -------
    VarianceEstimate
    """
    if record is None:
        if not small_against_step(result.variance, lsb):
            return result
        note = (
            "the noise is small against the grid step and the record has gaps: the "
            "correction for the rounding error that follows the signal is made on one "
            "uniform record only, so the variance may be low (docs/algorithms.md §E3)"
        )
        return replace(result, notes=[*result.notes, note])
    corr = quantisation_correction(record, result.n_total, lsb, result.variance, span, order)
    if corr is None or not corr.applied or shortest is None or shortest == span:
        return result if corr is None else apply_correction(result, corr)
    other = quantisation_correction(record, result.n_total, lsb, result.variance, shortest, order)
    return apply_correction(result, corr, other)
