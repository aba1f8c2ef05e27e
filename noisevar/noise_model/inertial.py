"""Inertial noise terms (IEEE Std 952/1554) fitted to the Allan variance of rate data.

docs/algorithms.md §E4: every term of eq. E4.1 at once, by non-negative weighted least
squares over all taus, with intervals and continuous/discrete forms.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats
from scipy.optimize import nnls

from noisevar import units
from noisevar._arrays import check_exact_ints
from noisevar.errors import NoisevarError
from noisevar.estimators import check_rate, scale_back, scale_exponent
from noisevar.estimators.regimes import DEFAULT_REGIMES, StillStretch, check_regimes
from noisevar.estimators.results import VarianceEstimate
from noisevar.noise_model.allan import (
    KINDS,
    ONE_SIGMA,
    AllanResult,
    _edfs,
    allan,
    regime_warning,
    rescale_allan,
    still_record,
)
from noisevar.noise_model.gmwm.bound import internal_params
from noisevar.noise_model.gmwm.processes import PROCESSES
from noisevar.noise_model.gmwm.wavelet import wv_covariance
from noisevar.noise_model.inertial_axes import per_axis
from noisevar.noise_model.inertial_misfit import misfit_note
from noisevar.noise_model.inertial_resolve import dominant, left_out_note, resolve
from noisevar.noise_model.inertial_white import (
    n_against_white,
    tau0_holders,
    white_level,
)

#: Bootstrap replicates behind each term's interval.
BOOTSTRAP = 200
#: Reweighting passes of the fit (weights from the fitted Allan variance).
PASSES = 3
_FLICKER = 2.0 * math.log(2.0) / math.pi
#: Power-law exponent of the rate noise each term is (S_y(f) ~ f^alpha): Greenhall's edf
#: of a tau is that of the term the fitted model says dominates there.
ALPHA = {"Q": 2, "N": 0, "B": -1, "K": -2, "R": -2}
#: The composite-model process of each term with a spectrum (R, a ramp, has none): the
#: bootstrap's Allan variances are correlated as that model's (:func:`_correlation`).
PROCESS = {"Q": "QN", "N": "WN", "B": "FL", "K": "RW"}


@dataclass(frozen=True)
class TermSpec:
    """A term of eq. E4.1: its coefficient in the Allan variance and its units.

    ``unit``/``discrete_unit`` are templates on the rate data's unit ``{u}``;
    ``discrete`` maps the continuous value and the sample rate to the per-sample value.
    """

    name: str
    symbol: str
    slope: float
    unit: str
    discrete_unit: str
    description: str

    def coefficient(self, taus: NDArray) -> NDArray:
        """d sigma^2 / d (term^2) at each tau (eq. E4.1)."""
        t = np.asarray(taus, dtype=float)
        return {
            "Q": 3.0 / t**2,
            "N": 1.0 / t,
            "B": np.full(t.shape, _FLICKER),
            "K": t / 3.0,
            "R": t**2 / 2.0,
        }[self.symbol]

    def discrete(self, value: float, rate: float) -> float:
        """The per-sample equivalent at ``rate`` Hz (docs/algorithms.md §E4)."""
        form = {
            "Q": lambda v, f: v * math.sqrt(2.0) * f,  # std of (q_k - q_{k-1}) * fs
            "N": units.sigma_at,  # white rate std per sample: N sqrt(fs)
            "B": lambda v, f: v,
            "K": units.walk_step,  # rate increment std per sample: K / sqrt(fs)
            "R": lambda v, f: v / f,  # rate change per sample
        }[self.symbol]
        return float(form(value, rate))


#: The five terms of eq. E4.1, in order of slope.
TERMS = (
    TermSpec("quantization", "Q", -1.0, "{u}·s", "{u}", "white angle noise: rate std per sample"),
    TermSpec("random_walk", "N", -0.5, "{u}/√Hz", "{u}", "white rate noise: std per sample"),
    TermSpec("bias_instability", "B", 0.0, "{u}", "{u}", "flicker rate noise (flat ADEV 0.664 B)"),
    TermSpec("rate_random_walk", "K", 0.5, "{u}/s/√Hz", "{u}", "bias increment std per sample"),
    TermSpec("rate_ramp", "R", 1.0, "{u}/s", "{u}", "rate change per sample"),
)
TERM_NAMES = tuple(t.name for t in TERMS)
#: Each term's label in the notes, e.g. ``"B (bias instability)"``.
TERM_LABELS = tuple(f"{t.symbol} ({t.name.replace('_', ' ')})" for t in TERMS)


def tau0_weights(rate: float) -> NDArray:
    """Each squared term's weight in the white level squared ``W² = sigma²(tau0) tau0``
    (eq. E4.1 at ``tau0 = 1/rate``): ``3 fs``, 1, ``2 ln 2 / (pi fs)``, ``1 / (3 fs²)``,
    ``1 / (2 fs³)``."""
    tau0 = np.array([1.0 / rate])
    return np.array([s.coefficient(tau0)[0] * tau0[0] for s in TERMS])


@dataclass(frozen=True)
class NoiseTerm:
    """One fitted term: continuous-time value, interval, and the discrete equivalent."""

    name: str
    symbol: str
    value: float
    interval: tuple[float, float]
    unit: str
    discrete: float
    discrete_unit: str
    slope: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "name": self.name,
            "symbol": self.symbol,
            "value": float(self.value),
            "interval": [float(self.interval[0]), float(self.interval[1])],
            "unit": self.unit,
            "discrete": float(self.discrete),
            "discrete_unit": self.discrete_unit,
            "slope": float(self.slope),
        }


@dataclass(frozen=True, eq=False)
class InertialNoise:
    """The IEEE-952 terms of one axis of rate data, and the Allan deviation they fit.

    Attributes
    ----------
    terms : tuple of NoiseTerm
        Q, N, B, K, R in that order (:data:`TERMS`).
    allan : AllanResult
        The overlapping Allan deviation that was fitted.
    rate : float
        Sample rate (Hz).
    unit : str
        Unit of the rate data (e.g. ``"rad/s"``).
    ci : float
        Confidence level of the intervals.
    white_level : float
        The measured white level ``sigma(tau0) sqrt(tau0)`` (unit/√Hz): the density of
        the white rate noise that has the record's Allan deviation at ``tau0 = 1/fs``
        (:func:`white_level`). A consumer without Q and B terms (Kalibr) needs at least
        this; N's upper bound reaches it with Q's.
    notes : tuple of str
        Which stretch a ``regimes="still"`` fit ran on; when the fit gave the Allan
        variance at tau0 to terms other than N (:attr:`tau0_holders`), and what that does
        to N and its interval; when the terms do not describe the deviation (a signal:
        :mod:`~noisevar.noise_model.inertial_misfit`; the exports' files then warn).
    regimes : {"all", "still"}
        The record's regimes the fit used (:mod:`noisevar.estimators.regimes`).
    """

    terms: tuple[NoiseTerm, ...]
    allan: AllanResult
    rate: float
    unit: str
    ci: float
    white_level: float
    notes: tuple[str, ...] = ()
    regimes: str = DEFAULT_REGIMES

    def term(self, name: str) -> NoiseTerm:
        """The term called ``name`` (e.g. ``"random_walk"``) or with symbol ``name``."""
        for t in self.terms:
            if name in (t.name, t.symbol):
                return t
        raise NoisevarError(f"No term {name!r}; the terms are {', '.join(TERM_NAMES)}.")

    @property
    def quantization(self) -> float:
        """Q (unit·s)."""
        return self.term("Q").value

    @property
    def random_walk(self) -> float:
        """N, the angle/velocity random walk (unit/√Hz)."""
        return self.term("N").value

    @property
    def bias_instability(self) -> float:
        """B (unit)."""
        return self.term("B").value

    @property
    def rate_random_walk(self) -> float:
        """K (unit/s/√Hz)."""
        return self.term("K").value

    @property
    def rate_ramp(self) -> float:
        """R (unit/s)."""
        return self.term("R").value

    @property
    def tau0_holders(self) -> str:
        """The terms other than N that hold the fitted Allan variance at ``tau0``, with
        their shares (:func:`~noisevar.noise_model.inertial_white.tau0_holders`)."""
        v = np.array([t.value for t in self.terms])
        coef = (v / (np.max(v) or 1.0)) ** 2  # shares only: scale-safe
        return tau0_holders(coef, tau0_weights(self.rate), TERM_LABELS)

    def model(self, taus: ArrayLike | None = None) -> tuple[dict[str, NDArray], NDArray]:
        """Each term's Allan deviation and that of their sum, at ``taus`` (default the data's).

        Returns
        -------
        dict of str to ndarray, ndarray
        """
        t = self.allan.taus if taus is None else np.asarray(taus, dtype=float)
        m = math.ldexp(1.0, math.frexp(max(abs(x.value) for x in self.terms) or 1.0)[1])  # exact
        parts = {s.name: s.coefficient(t) * (self.term(s.name).value / m) ** 2 for s in TERMS}
        total = np.sum(list(parts.values()), axis=0)
        return {k: np.sqrt(v) * m for k, v in parts.items()}, np.sqrt(total) * m

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary: the terms, and the Allan deviation fitted."""
        return {
            "rate": float(self.rate),
            "unit": self.unit,
            "ci": float(self.ci),
            "terms": {t.name: t.to_dict() for t in self.terms},
            "allan": self.allan.to_dict(),
            "white_level": float(self.white_level),
            "notes": list(self.notes),
            "regimes": self.regimes,
        }


def fit_terms(
    taus: NDArray,
    avar: NDArray,
    edf: NDArray,
    *,
    rate: float | None = None,
    n_phase: int | None = None,
    share: NDArray | float = 1.0,
) -> tuple[NDArray, NDArray]:
    """Weighted NNLS of eq. E4.1 on the terms the data support: the squared terms, and
    the weights.

    Parameters
    ----------
    taus, avar, edf : ndarray
        Averaging times, Allan variances and their equivalent degrees of freedom.
    rate, n_phase : float and int, optional
        Sample rate and phase samples: with them the edf of each tau is recomputed
        (Greenhall) for the noise type of the term that dominates the fitted model there,
        instead of the noise identification's, which can call a random walk at the
        longest taus flicker phase noise and weigh the least reliable points 4-6x.
    share : ndarray or float
        The recomputed edf times this (a record with samples dropped: ``res.edf`` over
        Greenhall's for its noise types, :func:`noisevar.noise_model.allan.gapped`).

    Returns
    -------
    coef : ndarray
        ``(Q^2, N^2, B^2, K^2, R^2)``; 0 for a term the choice left out.
    weights : ndarray
        The final weights ``sqrt(edf/2) / sigma^2_model`` (one per tau).

    Notes
    -----
    The choice: every subset of the terms that holds N is fitted with the final
    weights; the one with the least ``sum (w (avar - model))^2 + log(n) (non-zero
    terms)`` is kept (``n`` the samples; the taus alone when ``n_phase`` is not given).
    """
    a = np.column_stack([s.coefficient(taus) for s in TERMS])
    coef, w = _reweighted(a, avar, edf)
    if rate is not None and n_phase is not None:
        m = np.maximum(np.round(np.asarray(taus) * rate), 1).astype(np.int64)
        edf = _model_edf(a, coef, m, n_phase) * share
        coef, w = _reweighted(a, avar, edf)
    penalty = math.log(n_phase if n_phase else taus.size)
    best, best_score = coef, np.inf
    for mask in itertools.product((False, True), repeat=len(TERMS)):
        if not mask[1]:  # N always
            continue
        cols = np.flatnonzero(mask)
        c = np.zeros(len(TERMS))
        c[cols] = _nnls(a[:, cols] * w[:, None], avar * w)
        score = float(np.sum((w * (a @ c - avar)) ** 2)) + penalty * np.count_nonzero(c)
        if score < best_score - 1e-9:
            best, best_score = c, score
    return best, w


def _reweighted(a: NDArray, avar: NDArray, edf: NDArray) -> tuple[NDArray, NDArray]:
    model = avar
    for _ in range(PASSES):
        # var(sigma^2 estimate) ~ 2 sigma^4 / edf: weight each tau by 1 / its standard error
        w = np.sqrt(edf / 2.0) / np.maximum(model, np.finfo(float).tiny)
        coef = _nnls(a * w[:, None], avar * w)
        model = a @ coef
        if not np.any(model > 0):
            break
    return coef, w


def _model_edf(a: NDArray, coef: NDArray, m: NDArray, n_phase: int) -> NDArray:
    """Greenhall's edf per tau for the noise type of the term dominating the fit there."""
    alpha = np.array([ALPHA[TERMS[i].symbol] for i in dominant(a, coef)], dtype=float)
    return _edfs(alpha, KINDS["oadev"], m, n_phase, default=0)


def _nnls(a: NDArray, b: NDArray) -> NDArray:
    """``min ||a c - b||, c >= 0`` with the columns scaled to unit norm first."""
    norm = np.linalg.norm(a, axis=0)
    norm[norm == 0] = 1.0
    c, _ = nnls(a / norm, b, maxiter=50 * a.shape[1])
    return c / norm


def _intervals(
    taus: NDArray,
    coef: NDArray,
    w: NDArray,
    edf: NDArray,
    ci: float,
    seed: int,
    rate: float,
    n_rate: int,
) -> NDArray:
    """Parametric bootstrap: chi-square Allan variances around the fit, refitted.

    Returns the ``(lo, hi)`` of each term: the union of the percentile interval and of
    the replicates' quantiles about their median placed on the estimate.
    """
    rng = np.random.default_rng(seed)
    a = np.column_stack([s.coefficient(taus) for s in TERMS])
    model = a @ coef
    # sigma^2* = sigma^2_fit chi^2_edf / edf, correlated across taus as the fitted model's
    # (a Gaussian copula): independent draws made K's 68 % interval cover 43-52 %
    z = rng.standard_normal((BOOTSTRAP, taus.size))
    corr = _correlation(taus, coef, rate, n_rate)
    if corr is not None:
        z = z @ _root(corr).T
    draws = model * stats.chi2.ppf(stats.norm.cdf(z), edf) / edf
    kept = np.flatnonzero(coef > 0)
    terms = np.zeros((BOOTSTRAP, len(TERMS)))
    for b, d in enumerate(draws):
        terms[b, kept] = np.sqrt(_nnls(a[:, kept] * w[:, None], d * w))
    lo, med, hi = np.quantile(terms, [(1.0 - ci) / 2.0, 0.5, (1.0 + ci) / 2.0], axis=0)
    # the replicates' spread about their median, placed on the estimate (clipped at zero),
    # joined with the plain percentile interval: it holds the estimate
    value = np.sqrt(coef)
    low = np.minimum(np.maximum(value - (med - lo), 0.0), lo)
    high = np.maximum(value + (hi - med), hi)
    # a term the choice left out: from 0 to what all five terms refitted allow
    out = np.setdiff1d(np.arange(len(TERMS)), kept)
    if out.size:
        full = np.sqrt([_nnls(a * w[:, None], d * w) for d in draws[: BOOTSTRAP // 2]])
        low[out] = 0.0
        high[out] = np.quantile(full[:, out], (1.0 + ci) / 2.0, axis=0)
        # refits all at 0 say nothing of its size: what the Allan variances alone allow
        upper = np.quantile(draws, (1.0 + ci) / 2.0, axis=0)[:, None]
        high[out] = np.where(high[out] > 0, high[out], np.sqrt(np.min(upper / a, axis=0))[out])
    return np.column_stack([low, high])


def _correlation(taus: NDArray, coef: NDArray, rate: float, n_rate: int) -> NDArray | None:
    """Correlation of the overlapping Allan variances at octave ``taus`` under the fitted
    terms: the Haar wavelet variances' at ``2 m`` samples (Allan = 2 x Haar), from
    :func:`~noisevar.noise_model.gmwm.wavelet.wv_covariance`. None for other taus."""
    m = np.round(taus * rate).astype(np.int64)
    kept = [
        (t.symbol, c) for t, c in zip(TERMS, coef, strict=True) if c > 0 and t.symbol in PROCESS
    ]
    if not kept or np.any(m < 1) or np.any(m & (m - 1)) or np.any(2 * m > n_rate):
        return None
    keys = tuple(PROCESS[s] for s, _ in kept)
    p = internal_params(keys, np.sqrt([c for _, c in kept]), rate)

    def spectrum(f: NDArray, s2: NDArray, c2: NDArray) -> NDArray:
        return sum(PROCESSES[k].spectrum(p[i : i + 1], f, s2, c2) for i, k in enumerate(keys))

    cov = wv_covariance(2.0 * m, (n_rate - 2 * m + 1).astype(float), spectrum)
    d = np.sqrt(np.diag(cov))
    return cov / np.outer(d, d)


def _root(corr: NDArray) -> NDArray:
    """A square root of a correlation matrix (negative eigenvalues clipped)."""
    vals, vecs = np.linalg.eigh(corr)
    return vecs * np.sqrt(np.clip(vals, 0.0, None))


def _one_axis(
    y: NDArray,
    rate: float,
    unit: str,
    taus: str | ArrayLike,
    ci: float,
    seed: int,
    regimes: str = DEFAULT_REGIMES,
    est: VarianceEstimate | None = None,
    t: ArrayLike | None = None,
    stretch: StillStretch | None = None,
) -> InertialNoise:
    e = scale_exponent(y)
    if e:  # scale-safe: every term is linear in the record's unit (estimators' _scale)
        fit = _one_axis(np.ldexp(y, e), rate, unit, taus, ci, seed, regimes, est, t, stretch)
        return _rescaled(fit, e)
    # ``est`` (of the unscaled axis) gives the same regimes: the estimate scales by 2**e too
    notes = [] if regimes == "still" else regime_warning(y, est)
    if regimes == "still":
        # two taus of the overlapping ADEV: 2 span + 2 phase samples
        need = 2 * KINDS["oadev"].span + 2
        y, note = (
            (stretch.take(y), stretch.note)
            if stretch
            else still_record(y, "rate", need, "the noise terms", est)
        )
        notes.append(note)
        t = None  # the stretch's own times are not kept
    res = allan(y, rate=rate, data="rate", kind="oadev", taus=taus, ci=ci, t=t)
    rate = res.rate  # the stamps' base rate when samples were dropped (allan's t)
    if res.taus.size < 2:
        raise NoisevarError("The record is too short: the fit needs at least two taus.")
    notes = [*res.notes, *notes]  # how the samples were placed first
    res = replace(res, regimes=regimes, notes=tuple(notes))
    m = np.maximum(np.round(res.taus * rate), 1).astype(np.int64)
    # 1 exactly for a uniform record; the edf lost to dropped samples otherwise
    share = res.edf / _edfs(res.alpha, KINDS["oadev"], m, y.size + 1, default=0)
    coef, w = fit_terms(res.taus, res.variance, res.edf, rate=rate, n_phase=y.size + 1, share=share)
    a = np.column_stack([s.coefficient(res.taus) for s in TERMS])
    edf = _model_edf(a, coef, m, y.size + 1) * share
    notes += misfit_note(res.taus, res.variance, a @ coef, edf)
    ivals = _intervals(res.taus, coef, w, edf, ci, seed, rate, y.size)
    white = white_level(y, rate)
    notes += resolve(a, coef, res.variance, edf, ivals, ci, TERM_LABELS)
    notes += n_against_white(coef, ivals, white, unit, tau0_weights(rate), TERM_LABELS)
    notes += left_out_note(coef, ivals, [t.symbol for t in TERMS])
    terms = []
    for spec, c, (lo, hi) in zip(TERMS, coef, ivals, strict=True):
        value = float(np.sqrt(c))
        terms.append(
            NoiseTerm(
                spec.name,
                spec.symbol,
                value,
                (float(lo), float(hi)),
                units.term_unit(unit, spec.symbol),
                spec.discrete(value, rate),
                spec.discrete_unit.format(u=units.unit_text(unit)),
                spec.slope,
            )
        )
    return InertialNoise(
        tuple(terms), res, float(rate), unit, float(ci), white, tuple(notes), regimes
    )


def _rescaled(fit: InertialNoise, e: int) -> InertialNoise:
    """A fit of ``y 2**e`` in the units of ``y``: every term, level and deviation x ``2**-e``."""
    terms = tuple(
        replace(
            t,
            value=scale_back(t.value, -e, t.name),
            interval=tuple(scale_back(v, -e, t.name) for v in t.interval),
            discrete=scale_back(t.discrete, -e, t.name),
        )
        for t in fit.terms
    )
    return replace(
        fit,
        terms=terms,
        allan=rescale_allan(fit.allan, fit.rate, e, 0),
        white_level=scale_back(fit.white_level, -e, "white level"),
    )


def inertial_noise(
    z: ArrayLike,
    rate: float,
    *,
    axis: int = -1,
    unit: str | None = "u",
    taus: str | ArrayLike = "octave",
    ci: float = ONE_SIGMA,
    seed: int = 0,
    workers: int | None = None,
    regimes: str = DEFAULT_REGIMES,
    estimates: VarianceEstimate | Sequence[VarianceEstimate] | None = None,
    t: ArrayLike | None = None,
    stretch: StillStretch | None = None,
) -> InertialNoise | tuple[InertialNoise, ...]:
    """Fit the five IEEE-952 noise terms to the Allan variance of rate data.

    Parameters
    ----------
    z : array_like
        Rate samples (gyro rate, specific force, fractional frequency); several axes
        along the other dimension of a 2-D array.
    rate : float
        Sample rate (Hz).
    axis : int
        The time axis of ``z``.
    unit : str or None
        Unit of the rate data, for the terms' units (e.g. ``"rad/s"``, ``"m/s^2"``);
        None: no unit (``"u"``).
    taus : "octave", "all" or array_like
        Averaging times of the Allan deviation (see :func:`noisevar.allan`).
    ci : float
        Confidence level of the intervals.
    seed : int
        Seed of the bootstrap behind the intervals.
    workers : int, optional
        Threads for several axes (default: the number of CPUs).
    regimes : {"all", "still"}
        Fit each axis's whole record, or its longest still stretch only (each axis
        its own, or ``stretch``; said in ``notes``).
    estimates : VarianceEstimate or sequence of them, optional
        :func:`noisevar.estimate` of each axis (method auto, one per axis for a 2-D
        ``z``), when they were made already: the regime warning and the still stretch
        are taken from them instead of estimating each axis again (the same numbers).
    t : array_like, optional
        Sample times (s), one per sample: samples dropped are placed on their base
        period (:func:`noisevar.allan`'s ``t``).
    stretch : StillStretch, optional
        With ``regimes="still"``: the stretch every axis is fitted on, an IMU's where all
        its axes are still (:func:`~noisevar.estimators.regimes.common_still_stretch`).

    Returns
    -------
    InertialNoise, or a tuple of them (one per axis) for a 2-D ``z``

    Notes
    -----
    docs/algorithms.md §E4. Eq. E4.1 is linear in the squared terms; they are fitted
    with ``scipy.optimize.nnls``, each tau weighted by Greenhall's edf for the noise type
    of the term the fit says dominates there, and reweighted with the fitted variance;
    only the terms the data support are kept (:func:`fit_terms`; a left-out term is 0,
    its interval from 0 to what the five terms refitted allow). Intervals: parametric
    bootstrap of chi-square Allan variances, taken as independent across taus (so they
    are rather narrow at long taus); the percentile interval joined with the
    replicates' spread placed on the estimate; N's upper bound then reaches the white
    level with Q's (:func:`~noisevar.noise_model.inertial_white.n_against_white`: the
    terms that took the Allan variance at tau0 are named in ``notes``). Composite
    models (Gauss-Markov biases) with model choice: :func:`noisevar.fit_imu_model`.
    """
    check_regimes(regimes)
    check_rate(rate)
    check_exact_ints(z)
    unit = "u" if unit is None else unit
    if not isinstance(unit, str):
        raise NoisevarError(f"unit must be a unit's name such as 'rad/s', not {unit!r}")
    arr = np.asarray(z, dtype=float)
    if arr.ndim == 1:
        (est,) = per_axis(estimates, 1, one=True)
        return _one_axis(arr, rate, unit, taus, ci, seed, regimes, est, t, stretch)
    if arr.ndim != 2:
        raise NoisevarError(f"z must be 1-D or 2-D (time x axes); it has shape {arr.shape}.")
    cols = np.moveaxis(arr, axis, -1)
    ests = per_axis(estimates, cols.shape[0])
    n_workers = max(1, min(cols.shape[0], workers or os.cpu_count() or 1))
    with ThreadPoolExecutor(n_workers) as pool:
        jobs = [
            pool.submit(_one_axis, c, rate, unit, taus, ci, seed, regimes, est, t, stretch)
            for c, est in zip(cols, ests, strict=True)
        ]
        return tuple(j.result() for j in jobs)

