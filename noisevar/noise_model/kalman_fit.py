"""Q and R together for a kinematic model: :func:`fit_kalman` -> :class:`KalmanTuning`.

Models (docs/algorithms.md §E6): ``"rw"`` (random walk, the local-level model),
``"cv"`` (constant velocity, white acceleration) and ``"ca"`` (constant
acceleration, white jerk), each observed in position with white noise of
variance ``r``. ``q`` is the continuous-time spectral density of the driving
noise; ``h = q T^k / r`` the per-sample ratio of the alpha-beta-gamma papers.
Methods: steady-state maximum likelihood (``"mle"``) and autocovariance least
squares (``"als"``, Odelson, Rajamani and Rawlings 2006).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.signal
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import check_exact_ints
from noisevar.errors import NoisevarError
from noisevar.estimators import check_rate, scale_exponent
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes, longest_still_stretch
from noisevar.estimators.results import VarianceEstimate
from noisevar.format import pvalue
from noisevar.kalman.divergence import nis_band
from noisevar.noise_model._rescale import rescale_tuning
from noisevar.noise_model._steady import FilterPass, diffuse_start, steady_state
from noisevar.noise_model.kalman_als import als_fit
from noisevar.noise_model.kalman_pieces import Pieces, between_jumps, pieces_pass, whole
from noisevar.noise_model.kalman_record import RecordCheck, record_estimate, with_record
from noisevar.noise_model.kalman_tails import (
    STEP,
    RobustCovariance,
    information_and_scores,
    sandwich,
    tails_note,
)

#: Kinematic models: name -> (number of states, power k of T in h = q T^k / r, q's name).
MODELS: dict[str, tuple[int, int, str]] = {
    "rw": (1, 1, "random-walk density"),
    "cv": (2, 3, "white-acceleration density"),
    "ca": (3, 5, "white-jerk density"),
}
METHODS = ("mle", "als", "auto")
#: The method a fit is asked for by default: the best of the others (:data:`DEFAULT_METHOD`).
AUTO_METHOD = METHODS[-1]
#: The method ``"auto"`` uses (chosen on benchmarks/kalman_tuning.py).
DEFAULT_METHOD = "mle"
#: Largest magnitudes (powers of two) a fit runs on as they are; beyond, on a copy scaled by
#: a power of two (exact): the Riccati and likelihood numerics lose their way far from 1
#: (a record x 1e30 had no Riccati solution), not only where squares overflow.
SCALE_RANGE = (-20, 20)
#: Search range of log10 h for the likelihood (per sample).
LOG10_H_RANGE = (-14.0, 4.0)
#: An estimate of ln h closer than this to an end of its range is at that end (noted; at
#: the bottom, h and q are not identified and their intervals are open).
EDGE_MARGIN = 0.5
#: p-value of the Ljung-Box test below which the innovations are called coloured.
WHITE_ALPHA = 0.01
#: The interval of a term the data do not identify.
OPEN = (0.0, float("inf"))


def kinematic_model(model: str, dt: float) -> tuple[NDArray, NDArray, NDArray]:
    """``F``, ``H`` (as a vector) and ``Q / q`` of a kinematic model with period ``dt``.

    Parameters
    ----------
    model : {"rw", "cv", "ca"}
    dt : float
        Sample period T.

    Returns
    -------
    F : ndarray (n, n)
    h : ndarray (n,)
    Q1 : ndarray (n, n)
        The process-noise covariance per unit density, ``Q = q Q1``.
    """
    if model not in MODELS:
        raise NoisevarError(f"unknown model {model!r}; choose one of: {', '.join(MODELS)}")
    n = MODELS[model][0]
    i, j = np.indices((n, n))
    p = j - i
    fact = np.vectorize(math.factorial)
    # F_ij = T^(j-i) / (j-i)!  for j >= i
    F = np.where(p >= 0, dt ** np.maximum(p, 0) / fact(np.maximum(p, 0)), 0.0)
    # Q1_ij = T^(a+b+1) / ((a+b+1) a! b!),  a = n-1-i, b = n-1-j   (E6.1)
    a, b = n - 1 - i, n - 1 - j
    Q1 = dt ** (a + b + 1) / ((a + b + 1) * fact(a) * fact(b))
    h = np.zeros(n)
    h[0] = 1.0
    return F.astype(float), h, Q1.astype(float)


@dataclass(frozen=True)
class KalmanTuning:
    """A tuned kinematic Kalman filter and its validation on the record it was fitted to.

    Attributes
    ----------
    model, method : str
        Kinematic model and how ``q, r`` were found (``"mle"``, ``"als"``, ``"given"``).
    dt : float
        Sample period (``1 / rate``; 1 sample when no rate was given).
    q, r, h : float
        Process-noise density, measurement variance, ``h = q T^k / r``.
    q_interval, r_interval, h_interval : (float, float)
        95 % intervals (in logs; the sandwich of the likelihood's curvature and its scores,
        right for non-Gaussian noise too).
    F, H, Q, R, gain, P : ndarray
        The filter; ``gain`` is the steady-state Kalman gain, ``P`` the steady
        predicted covariance.
    x0, P0 : ndarray
        The exact diffuse start: the estimate after the first ``start`` samples.
    nis_mean, nis_band : float, (float, float)
        Mean normalised innovation squared and its 95 % chi-square band.
    ljung_box_p : float
        Ljung-Box p-value of the normalised innovations; ``innovations_white`` is
        ``ljung_box_p >= 0.01``.
    loglik : float
        Gaussian log-likelihood (diffuse: the first ``start`` samples condition).
    units : dict
        Units of ``q`` and ``r`` (``u`` is the signal's unit).
    notes : tuple of str
        Warnings, including "the data reject this model", and which stretch a
        ``regimes="still"`` fit ran on.
    regimes : {"all", "still"}
        The record's regimes the fit used (:mod:`noisevar.estimators.regimes`).
    innovations_kurtosis : float
        Of the normalised innovations (3 for Gaussian noise).
    innovations_tails : {"gaussian", "heavy", "light"}
        Their tails (:func:`~noisevar.diagnostics.tails.tails_shape`, two-sided): heavy
        above :data:`~noisevar.diagnostics.tails.HEAVY_KURTOSIS` (the fit's Gaussian
        assumption is broken), light below
        :data:`~noisevar.diagnostics.tails.LIGHT_KURTOSIS` and outside a Gaussian's
        sampling interval (quantised or periodic noise); :attr:`innovations_gaussian` is
        False for both and a note says so (the intervals are the robust sandwich ones
        either way).
    record : RecordCheck or None
        ``r`` beside the record's answer (:func:`noisevar.estimate`, method auto) for the same
        regime choice: whether they agree, the fit's assumptions the record breaks, the R to
        use and what to do (its ``note`` is the last of ``notes``); None for a record the
        estimate refuses (a note says so).
    """

    model: str
    method: str
    dt: float
    rate: float | None
    q: float
    r: float
    h: float
    q_interval: tuple[float, float]
    r_interval: tuple[float, float]
    h_interval: tuple[float, float]
    F: NDArray
    H: NDArray
    Q: NDArray
    R: NDArray
    gain: NDArray
    P: NDArray
    x0: NDArray
    P0: NDArray
    start: int
    n: int
    nis_mean: float
    nis_band: tuple[float, float]
    ljung_box_p: float
    innovations_white: bool
    loglik: float
    units: dict[str, str] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    regimes: str = DEFAULT_REGIMES
    innovations_kurtosis: float = 3.0
    innovations_tails: str = "gaussian"
    record: RecordCheck | None = None
    left_out: int = 0

    @property
    def innovations_gaussian(self) -> bool:
        """Whether the innovations' tails are Gaussian (:attr:`innovations_tails`)."""
        return self.innovations_tails == "gaussian"

    def tails_text(self, kurtosis: str) -> str:
        """The innovations' tails in words, ``kurtosis`` their kurtosis written (the CLI's
        and the Noise model page's): ``"NOT Gaussian (kurtosis 1.51; light tails)"``."""
        if self.innovations_gaussian:
            return f"Gaussian (kurtosis {kurtosis}; Gaussian 3)"
        return f"NOT Gaussian (kurtosis {kurtosis}; {self.innovations_tails} tails; Gaussian 3)"

    @property
    def aic(self) -> float:
        """Akaike's criterion of the fit (two parameters, q and r)."""
        return 4.0 - 2.0 * self.loglik

    @property
    def bic(self) -> float:
        """Schwarz's criterion of the fit (two parameters, ``n - start`` innovations)."""
        return 2.0 * np.log(self.n - self.start) - 2.0 * self.loglik

    @property
    def nis_consistent(self) -> bool:
        """Whether the mean NIS lies inside its 95 % band."""
        return self.nis_band[0] <= self.nis_mean <= self.nis_band[1]

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary (matrices as nested lists; no NaN or infinity)."""

        def num(v: float) -> float | None:
            return float(v) if np.isfinite(v) else None

        out: dict[str, Any] = {"model": self.model, "method": self.method}
        out.update(dt=self.dt, rate=self.rate, n=self.n, start=self.start)
        for name in ("q", "r", "h"):
            out[name] = num(getattr(self, name))
            out[f"{name}_interval"] = [num(v) for v in getattr(self, f"{name}_interval")]
        for name in ("F", "H", "Q", "R", "gain", "P", "x0", "P0"):
            m = np.asarray(getattr(self, name), float)
            out[name] = np.where(np.isfinite(m), m, None).tolist()
        out.update(
            nis_mean=num(self.nis_mean),
            nis_band=[num(v) for v in self.nis_band],
            nis_consistent=self.nis_consistent,
            ljung_box_p=num(self.ljung_box_p),
            innovations_white=self.innovations_white,
            innovations_kurtosis=num(self.innovations_kurtosis),
            innovations_tails=self.innovations_tails,
            loglik=num(self.loglik),
            aic=num(self.aic),
            bic=num(self.bic),
            units=dict(self.units),
            notes=list(self.notes),
            regimes=self.regimes,
            record=None if self.record is None else self.record.to_dict(),
            left_out=self.left_out,
        )
        return out


# ---------------------------------------------------------------- likelihood
def _unit_pass(z: tuple[NDArray, ...], model: str, dt: float, h_ratio: float) -> FilterPass:
    """The filter with ``r = 1`` and ``q = h / T^k`` (gains depend on ``h`` only) on the
    record's pieces."""
    F, hv, Q1 = kinematic_model(model, dt)
    k = MODELS[model][1]
    return pieces_pass(z, F, hv, Q1 * (h_ratio / dt**k), 1.0, states=False)


def _profile(
    z: tuple[NDArray, ...], model: str, dt: float, log_h: float
) -> tuple[float, float, float]:
    """``(sum log s, sum e²/s, n)`` of the unit-r filter at ``h = exp(log_h)``."""
    fp = _unit_pass(z, model, dt, float(np.exp(log_h)))
    return float(np.sum(np.log(fp.s))), float(np.sum(fp.innovations**2 / fp.s)), fp.s.size


def _loglik(sum_log_s: float, g: float, n: int, log_r: float) -> float:
    # l = -1/2 sum(log 2 pi r s_k + e_k² / (r s_k))
    return -0.5 * (n * (np.log(2 * np.pi) + log_r) + sum_log_s + g * np.exp(-log_r))


def _concentrated(z: tuple[NDArray, ...], model: str, dt: float, log_h: float) -> float:
    """Negative log-likelihood with ``r`` at its optimum ``r = mean(e²/s)``."""
    try:
        sl, g, n = _profile(z, model, dt, log_h)
    except NoisevarError:
        return np.inf
    return -_loglik(sl, g, n, np.log(g / n))


def _mle_log_h(z: tuple[NDArray, ...], model: str, dt: float, progress: Callable | None) -> float:
    """Grid over log h, then Brent's method around the best grid point."""
    grid = np.log(10.0) * np.arange(LOG10_H_RANGE[0], LOG10_H_RANGE[1] + 1.0, 1.0)
    values = []
    for i, u in enumerate(grid):  # a 1-D search: 19 LTI passes
        values.append(_concentrated(z, model, dt, u))
        if progress is not None:
            progress((i + 1) / (grid.size + 20))
    best = int(np.nanargmin(values))
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)]
    f, opt = (lambda u: _concentrated(z, model, dt, u)), {"xatol": 1e-7}
    res = scipy.optimize.minimize_scalar(f, bounds=(lo, hi), method="bounded", options=opt)
    return float(res.x) if res.fun <= values[best] else float(grid[best])


def _at_edge(log_h: float) -> tuple[bool, bool]:
    """Whether ``ln h`` is at the bottom, at the top of its search range."""
    lo, hi = np.log(10.0) * np.array(LOG10_H_RANGE)
    return bool(log_h - lo < EDGE_MARGIN), bool(hi - log_h < EDGE_MARGIN)


def _log_cov(
    z: tuple[NDArray, ...], model: str, dt: float, log_h: float, log_r: float
) -> tuple[RobustCovariance, bool]:
    """Robust covariance of ``(log h, log r)``, or of ``log r`` alone, and whether h is
    identified: the sandwich of the observed information (central differences in ``log h``,
    analytic in ``log r``) and the per-sample scores."""
    fps = [_unit_pass(z, model, dt, float(np.exp(log_h + s * STEP))) for s in (-1, 0, 1)]
    info, scores = information_and_scores(fps, log_r)
    try:
        if not _at_edge(log_h)[0] and np.all(np.diag(np.linalg.inv(info)) > 0):
            return sandwich(info, scores), True
    except np.linalg.LinAlgError:
        pass
    # h not identified (at the bottom of its range: the likelihood flat, its score and
    # curvature both near 0, their sandwich meaningless; a NaN curvature): r's given h
    return sandwich(info[1:, 1:], scores[:, 1:]), False


# ---------------------------------------------------------------- public
def min_samples(model: str) -> int:
    """Fewest samples a fit of ``model`` takes: ten per state and per parameter."""
    return 10 * (MODELS[model][0] + 2)


def _check_input(z: ArrayLike, model: str, rate: float | None) -> tuple[NDArray, float]:
    if model not in MODELS:
        raise NoisevarError(f"unknown model {model!r}; choose one of: {', '.join(MODELS)}")
    check_rate(rate)
    check_exact_ints(z)
    try:
        arr = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError("the signal must be a 1-D array of numbers") from None
    if arr.ndim != 1:
        raise NoisevarError(f"the signal must be 1-D, got shape {arr.shape}")
    need = min_samples(model)
    if arr.size < need:
        raise NoisevarError(
            f"the record has {arr.size} samples; fitting the {model!r} model needs at least {need}"
        )
    if not np.all(np.isfinite(arr)):
        raise NoisevarError("the signal contains NaN or infinite values: remove or fill them first")
    if np.ptp(arr) == 0:
        raise NoisevarError("the signal is constant: there is no noise to fit")
    return arr, 1.0 / float(rate) if rate is not None else 1.0


def _units(model: str, rate: float | None) -> dict[str, str]:
    k = MODELS[model][1]
    t = "s" if rate is not None else "sample"
    return {"q": f"u²/{t}^{k} ({MODELS[model][2]})", "r": "u²", "h": "1 (per sample)"}


def _tuning(  # long: assembles the filter, its intervals and its validation
    z: NDArray,
    model: str,
    dt: float,
    rate: float | None,
    q: float,
    r: float,
    method: str,
    notes: list[str],
    pieces: Pieces | None = None,
) -> KalmanTuning:
    """Build the :class:`KalmanTuning` for (q, r) and validate it on ``z``'s ``pieces``
    (default the whole record); the initial state is the whole record's."""
    from statsmodels.tsa.stattools import acf, q_stat

    F, hv, Q1 = kinematic_model(model, dt)
    k = MODELS[model][1]
    lo_h = 10.0 ** LOG10_H_RANGE[0]
    if q * dt**k / r < lo_h:
        q = lo_h * r / dt**k
    pieces = pieces or whole(z.size)
    zc = pieces.take(z)
    Q = q * Q1
    P, K, _ = steady_state(F, hv, Q, r)
    fp = pieces_pass(zc, F, hv, Q, r, states=True)
    x0, P0, start = diffuse_start(z - z[0], F, hv, Q, r)
    x0 = x0.copy()
    x0[0] += z[0]
    nu = fp.innovations / np.sqrt(fp.s)
    nis_mean = float(np.mean(nu**2))
    band = nis_band(1, nu.size)
    lags = int(min(20, max(1, nu.size // 5)))
    # Ljung-Box Q = n(n+2) sum rho_k² / (n-k)   (§E2)
    p = float(q_stat(acf(nu, nlags=lags, fft=True)[1:], nu.size)[1][-1])
    white = bool(p >= WHITE_ALPHA)
    # l = -n/2 log 2 pi - 1/2 sum_{k >= d} (log S_k + e_k²/S_k)   (diffuse, Durbin-Koopman)
    loglik = -0.5 * float(pieces.size * np.log(2 * np.pi) + np.sum(np.log(fp.s) + nu**2))
    h_ratio = q * dt**k / r
    tails, kurt, shape = tails_note(nu)
    rc, h_known = _log_cov(zc, model, dt, np.log(h_ratio), np.log(r))
    # ln q = ln h + ln r - k ln T; h not identified: h and q unbounded
    q_iv, h_iv = (
        (rc.interval(np.log(q), [1, 1]), rc.interval(np.log(h_ratio), [1, 0]))
        if h_known
        else (OPEN, OPEN)
    )
    if not white:
        notes.append(
            f"the innovations are not white (Ljung-Box {pvalue(p)} over {lags} lags): the data "
            f"reject the {model!r} model; try another model or a coloured-noise model"
        )
    notes += [tails] if tails else []
    if not band[0] <= nis_mean <= band[1]:
        notes.append(
            f"the mean NIS {nis_mean:.3g} is outside its 95 % band "
            f"[{band[0]:.3g}, {band[1]:.3g}]: the filter is not consistent on this record"
        )
    return KalmanTuning(
        model=model,
        method=method,
        dt=dt,
        rate=rate,
        q=float(q),
        r=float(r),
        h=float(h_ratio),
        q_interval=q_iv,
        r_interval=rc.interval(np.log(r), [0, 1] if h_known else [1]),
        h_interval=h_iv,
        F=F,
        H=hv[None, :],
        Q=Q,
        R=np.array([[r]]),
        gain=K,
        P=P,
        x0=x0,
        P0=P0,
        start=start,
        n=int(pieces.size),
        nis_mean=nis_mean,
        nis_band=band,
        ljung_box_p=p,
        innovations_white=white,
        innovations_kurtosis=kurt,
        innovations_tails=shape,
        loglik=loglik,
        units=_units(model, rate),
        notes=tuple(notes),
        left_out=pieces.left_out,
    )


def fit_kalman(
    z: ArrayLike,
    model: str = "cv",
    rate: float | None = None,
    method: str = AUTO_METHOD,
    lags: int = 20,
    progress: Callable[[float], None] | None = None,
    regimes: str = DEFAULT_REGIMES,
    record: VarianceEstimate | None = None,
) -> KalmanTuning:
    """Fit the process-noise density ``q`` and the measurement variance ``r`` together.

    Parameters
    ----------
    z : array_like, shape (n,)
        The measured record (positions, any unit ``u``), equally spaced.
    model : {"rw", "cv", "ca"}
        Random walk (local level), constant velocity or constant acceleration.
    rate : float, optional
        Samples per second; ``q`` is then per second (``u²/s^k``), else per sample.
    method : {"auto", "mle", "als"}
        Steady-state maximum likelihood, autocovariance least squares, or the
        default (``"auto"`` = :data:`DEFAULT_METHOD`).
    lags : int
        Innovation autocovariance lags used by ALS.
    progress : callable, optional
        Called with the fraction done (0 to 1).
    regimes : {"all", "still"}
        Fit the whole record, or its longest still stretch only
        (:func:`~noisevar.estimators.regimes.longest_still_stretch`; said in ``notes``).
    record : VarianceEstimate, optional
        The record's answer (:func:`noisevar.estimate` of ``z``, with its sample times where
        it has some) that ``r`` is checked against; default ``estimate(z)``.

    Returns
    -------
    KalmanTuning

    Raises
    ------
    NoisevarError
        Unknown model, method or regimes, bad rate, a record too short, non-finite or
        constant; with ``regimes="still"``, no still stretch long enough.

    Notes
    -----
    docs/algorithms.md §E6. The first ``d`` samples (``d`` states) fix the state
    exactly (diffuse start) and are left out of the likelihood.
    """
    arr, dt = _check_input(z, model, rate)
    if method not in METHODS:
        raise NoisevarError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    if not isinstance(lags, int) or lags < 3:
        raise NoisevarError(f"lags must be an integer of at least 3, got {lags!r}")
    est = record if record is not None else record_estimate(arr)
    notes: list[str] = []
    need = min_samples(model)
    if check_regimes(regimes) == "still":
        stretch = longest_still_stretch(arr, need, f"the {model!r} model", est)
        arr, _ = _check_input(stretch.take(arr), model, rate)
        notes.append(stretch.note)
        pieces = whole(arr.size)
    else:
        pieces = between_jumps(arr.size, est, need)
        notes += [pieces.note] if pieces.note else []
    e = scale_exponent(arr, SCALE_RANGE)
    # scale-safe: the fit on z 2**e (exact), q and r back (estimators' _scale)
    fit = _fit(np.ldexp(arr, e), pieces, model, dt, rate, method, lags, progress, notes)
    fit = replace(rescale_tuning(fit, e) if e else fit, regimes=regimes)
    if progress is not None:
        progress(1.0)
    return with_record(fit, est)


def _fit(
    arr: NDArray,
    pieces: Pieces,
    model: str,
    dt: float,
    rate: float | None,
    method: str,
    lags: int,
    progress: Callable[[float], None] | None,
    notes: list[str],
) -> KalmanTuning:
    """:func:`fit_kalman` on a record of safe magnitude (its stretch already taken), over
    its ``pieces``; ALS on the longest (its autocovariances need one unbroken run)."""
    chosen = DEFAULT_METHOD if method == AUTO_METHOD else method
    zc = pieces.take(arr)
    k = MODELS[model][1]
    if chosen == "mle":
        log_h = _mle_log_h(zc, model, dt, progress)
        sl, g, n = _profile(zc, model, dt, log_h)
        r = g / n
        q = float(np.exp(log_h)) * r / dt**k
        bottom, top = _at_edge(log_h)
        if bottom:
            notes.append("q is at the bottom of its range: no process noise is detectable")
        if top:
            notes.append("h is at the top of its range: the measurement noise is negligible")
    else:
        F, hv, Q1 = kinematic_model(model, dt)
        longest = max(zc, key=len)
        q, r, als_notes = als_fit(longest, (F, hv, Q1), dt**k, lags, 10.0 ** LOG10_H_RANGE[0])
        notes += als_notes
    return _tuning(arr, model, dt, rate, q, r, chosen, notes, pieces)


def evaluate_kalman(
    z: ArrayLike,
    model: str,
    q: float,
    r: float,
    rate: float | None = None,
    record: VarianceEstimate | None = None,
) -> KalmanTuning:
    """Validate a given ``q`` and ``r`` (for example from a config) on a record.

    Parameters
    ----------
    z : array_like, shape (n,)
    model : {"rw", "cv", "ca"}
    q, r : float
        Process-noise density (per second when ``rate`` is given) and
        measurement variance, both positive.
    rate : float, optional
    record : VarianceEstimate, optional
        The record's answer ``r`` is checked against (as :func:`fit_kalman`'s).

    Returns
    -------
    KalmanTuning
        With ``method = "given"``.
    """
    arr, dt = _check_input(z, model, rate)
    for name, v in (("q", q), ("r", r)):
        if isinstance(v, bool) or not isinstance(v, int | float | np.number) or not v > 0:
            raise NoisevarError(f"{name} must be a positive number, got {v!r}")
        if not np.isfinite(v):
            raise NoisevarError(f"{name} must be finite, got {v!r}")
    e = scale_exponent(arr, SCALE_RANGE)
    qs, rs = (float(np.ldexp(float(v), 2 * e)) for v in (q, r))
    if not all(np.isfinite(v) and v > 0 for v in (qs, rs)):
        raise NoisevarError("q and r are out of floating-point range for this record's scale")
    fit = _tuning(np.ldexp(arr, e), model, dt, rate, qs, rs, "given", [])
    est = record if record is not None else record_estimate(arr)
    return with_record(rescale_tuning(fit, e) if e else fit, est)
