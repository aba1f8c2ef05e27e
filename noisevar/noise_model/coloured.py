"""Coloured measurement noise as states: :func:`fit_coloured_noise` (docs/algorithms.md §E5).

A detrended record is fitted by exact maximum likelihood (statsmodels'
``UnobservedComponents`` state space) as white noise plus, optionally, a
first-order Gauss-Markov process (AR(1)) and/or a random walk; the models are
ranked by AIC or BIC. The winner gives ``R`` (the white part) and the coloured
part as an augmented state ``b_{k+1} = phi b_k + w_k`` with its ``Q``.
Flicker (1/f) noise is not modelled: it has no finite-state form.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import check_exact_ints
from noisevar.errors import NoisevarError
from noisevar.estimators import check_rate, scale_back, scale_exponent
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes, longest_still_stretch

#: The models, each as its white / AR(1) / random-walk parts.
COLOURED_MODELS: dict[str, tuple[bool, bool]] = {
    "white": (False, False),
    "white+ar1": (True, False),
    "white+rw": (False, True),
    "white+ar1+rw": (True, True),
}
DEFAULT_MODELS = ("white", "white+ar1", "white+rw")
CRITERIA = ("bic", "aic")
#: Fewest samples a fit takes.
MIN_SAMPLES = 50


@dataclass(frozen=True)
class ModelFit:
    """One fitted model: its parameters (per sample) and information criteria."""

    name: str
    r: float
    phi: float | None
    q_ar: float | None
    q_rw: float | None
    loglik: float
    aic: float
    bic: float
    k: int
    converged: bool

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {k: _safe(v) for k, v in self.__dict__.items()}


def _safe(v: Any) -> Any:
    if isinstance(v, float | np.floating):
        return float(v) if np.isfinite(v) else None
    return v


@dataclass(frozen=True)
class ColouredNoiseFit:
    """The chosen noise model, ready for a filter's augmented state.

    Attributes
    ----------
    model : str
        The chosen model (``"white"``, ``"white+ar1"``, ``"white+rw"``, ...).
    criterion : str
        ``"bic"`` or ``"aic"``.
    r : float
        Variance of the white part (the filter's ``R``).
    phi : tuple of float
        Transition of each coloured state (AR(1) first, then the random walk's 1).
    q : tuple of float
        Driving-noise variance per sample of each coloured state (its ``Q``).
    tau_c : float or None
        AR(1) correlation time ``-T / ln phi`` (seconds with a rate, else samples).
    sigma2_ar : float or None
        Stationary variance of the AR(1) part, ``q / (1 - phi²)``.
    fits : tuple of ModelFit
        Every fitted model.
    rate : float or None
    notes : tuple of str
        Among them, which fits did not converge and whether the choice could change, and
        which stretch a ``regimes="still"`` fit ran on.
    regimes : {"all", "still"}
        The record's regimes the fit used (:mod:`noisevar.estimators.regimes`).
    """

    model: str
    criterion: str
    r: float
    phi: tuple[float, ...]
    q: tuple[float, ...]
    tau_c: float | None
    sigma2_ar: float | None
    fits: tuple[ModelFit, ...]
    rate: float | None
    n: int
    notes: tuple[str, ...] = field(default_factory=tuple)
    regimes: str = DEFAULT_REGIMES

    @property
    def converged(self) -> dict[str, bool]:
        """Whether each model's optimiser converged (see ``notes`` for what it means)."""
        return {f.name: f.converged for f in self.fits}

    @property
    def F(self) -> NDArray:
        """Transition matrix of the coloured states (diagonal ``phi``)."""
        return np.diag(np.array(self.phi, float)).reshape(len(self.phi), len(self.phi))

    @property
    def Q(self) -> NDArray:
        """Process-noise covariance of the coloured states."""
        return np.diag(np.array(self.q, float)).reshape(len(self.q), len(self.q))

    @property
    def H(self) -> NDArray:
        """Measurement row of the coloured states: each adds to ``z``."""
        return np.ones((1, len(self.phi)))

    @property
    def R(self) -> NDArray:
        """The white part as a 1x1 measurement covariance."""
        return np.array([[self.r]])

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary (augmented-state matrices as nested lists)."""
        return {
            "model": self.model,
            "criterion": self.criterion,
            "r": _safe(self.r),
            "phi": [_safe(v) for v in self.phi],
            "q": [_safe(v) for v in self.q],
            "tau_c": _safe(self.tau_c) if self.tau_c is not None else None,
            "sigma2_ar": _safe(self.sigma2_ar) if self.sigma2_ar is not None else None,
            "F": self.F.tolist(),
            "Q": self.Q.tolist(),
            "H": self.H.tolist(),
            "R": self.R.tolist(),
            "fits": [f.to_dict() for f in self.fits],
            "converged": self.converged,
            "rate": self.rate,
            "n": self.n,
            "notes": list(self.notes),
            "regimes": self.regimes,
        }


def _start_ar1(y: NDArray) -> list[float]:
    """Moment start for white + AR(1): c1 = s² phi, c2 = s² phi², c0 = r + s².

    Without a valid moment solution (noise close to white): a small AR(1) part.
    """
    n = y.size
    c = [float(np.dot(y[j:], y[: n - j]) / n) for j in range(3)]
    if c[1] > 0 and c[2] > 0:
        phi = min(c[2] / c[1], 0.999)
        s2 = c[1] / phi
        if 0 < phi < 1 and c[0] - s2 > 0:
            return [c[0] - s2, s2 * (1 - phi**2), phi]
    return [0.9 * c[0], 0.1 * c[0] * (1 - 0.5**2), 0.5]


def _start_rw(y: NDArray) -> list[float]:
    """Moment start for white + random walk: var(dy) = q + 2r, cov(dy_k, dy_k+1) = -r.

    Without a valid moment solution (noise close to white): a small random walk.
    """
    d = np.diff(y)
    r = -float(np.dot(d[1:], d[:-1]) / d.size)
    q = float(np.mean(d**2)) - 2 * r
    if r > 0 and q > 0:
        return [r, q]
    return [float(np.var(y)), 1e-4 * float(np.var(y))]


def _fit_one(y: NDArray, name: str) -> ModelFit:
    """Exact-likelihood fit of one model with statsmodels' UnobservedComponents.

    ``y`` is standardised (:func:`_standardise`); one restart from the end point with
    more iterations when the first run did not converge.
    """
    from statsmodels.tools.sm_exceptions import ConvergenceWarning
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    ar, rw = COLOURED_MODELS[name]
    n = y.size
    if not ar and not rw:
        # white: r = mean(y²), l = -n/2 (log 2 pi r + 1)
        r = float(np.mean(y**2))
        ll = -0.5 * n * (np.log(2 * np.pi * r) + 1)
        return ModelFit(name, r, None, None, None, ll, 2 - 2 * ll, np.log(n) - 2 * ll, 1, True)
    start = None
    if ar and not rw:
        start = _start_ar1(y)
    elif rw and not ar:
        start = _start_rw(y)
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        for category in (ConvergenceWarning, UserWarning, RuntimeWarning):
            warnings.simplefilter("ignore", category)
        mod = UnobservedComponents(
            y, level="llevel" if rw else False, irregular=True, autoregressive=1 if ar else None
        )
        res = mod.fit(start_params=start, disp=False, maxiter=200)
        if not res.mle_retvals.get("converged", True):
            res = mod.fit(start_params=res.params, disp=False, maxiter=1000)
    p = dict(zip(mod.param_names, np.asarray(res.params, float), strict=True))
    k = len(p)
    ll = float(res.llf)
    return ModelFit(
        name=name,
        r=p["sigma2.irregular"],
        phi=p.get("ar.L1"),
        q_ar=p.get("sigma2.ar"),
        q_rw=p.get("sigma2.level"),
        loglik=ll,
        aic=2 * k - 2 * ll,
        bic=k * np.log(n) - 2 * ll,
        k=k,
        converged=bool(res.mle_retvals.get("converged", True)),
    )


def _check(z: ArrayLike, rate: float | None, models: Sequence[str], criterion: str) -> NDArray:
    if criterion not in CRITERIA:
        raise NoisevarError(
            f"unknown criterion {criterion!r}; choose one of: {', '.join(CRITERIA)}"
        )
    if isinstance(models, str) or not models:
        raise NoisevarError("models must be a non-empty list of model names")
    for m in models:
        if m not in COLOURED_MODELS:
            raise NoisevarError(
                f"unknown noise model {m!r}; choose among: {', '.join(COLOURED_MODELS)}"
            )
    check_rate(rate)
    check_exact_ints(z)
    try:
        arr = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError("the signal must be a 1-D array of numbers") from None
    if arr.ndim != 1 or arr.size < MIN_SAMPLES:
        raise NoisevarError(
            f"the signal must be 1-D with at least {MIN_SAMPLES} samples, got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise NoisevarError("the signal contains NaN or infinite values: remove or fill them first")
    if np.ptp(arr) == 0:
        raise NoisevarError("the signal is constant: there is no noise to fit")
    return arr


def _standardise(arr: NDArray) -> tuple[NDArray, float, int]:
    """The record without its mean and least-squares line, divided by its white scale.

    The scale is ``sqrt(mean(diff(y)²) / 2)`` (the std of white noise; for white + AR(1)
    or + random walk it keeps every per-sample variance of order 1), so the fits see the
    same numbers whatever the units. It is computed on the record scaled by ``2**e``
    (:func:`~noisevar.estimators.scale_exponent`: exact), so that its squares neither
    overflow nor underflow; the scale returned is the copy's, with ``e``.
    """
    e = scale_exponent(arr)
    y = np.ldexp(arr, e) if e else arr
    y = y - y.mean()
    t = np.arange(y.size, dtype=float)
    y = y - np.polyval(np.polyfit(t, y, 1), t)
    scale = float(np.sqrt(np.mean(np.diff(y) ** 2) / 2.0))
    if not (np.isfinite(scale) and scale > 0):
        raise NoisevarError("the signal is a straight line: there is no noise to fit")
    return y / scale, scale, e


def _rescale(fit: ModelFit, scale: float, n: int, e: int = 0) -> ModelFit:
    """A fit of ``y / scale`` in the units of ``y 2**-e``: variances x scale² 2**-2e,
    l - n ln(scale 2**-e)."""
    s2 = scale**2

    def var(v: float | None) -> float | None:
        return None if v is None else scale_back(v * s2, -2 * e, "noise variance")

    ll = fit.loglik - n * (np.log(scale) - e * np.log(2.0))
    return ModelFit(
        name=fit.name,
        r=var(fit.r),
        phi=fit.phi,
        q_ar=var(fit.q_ar),
        q_rw=var(fit.q_rw),
        loglik=ll,
        aic=2 * fit.k - 2 * ll,
        bic=fit.k * np.log(n) - 2 * ll,
        k=fit.k,
        converged=fit.converged,
    )


def convergence_notes(fits: Sequence[ModelFit], best: ModelFit) -> list[str]:
    """What the fits that did not converge mean for the choice of ``best``.

    An unconverged fit stopped short of its maximum likelihood, so its criterion can
    only improve: a losing model that did not converge could still win (the choice
    could change); an unconverged winner would only win by more (its parameters are
    not the maximum-likelihood ones, but the choice would not change).
    """
    notes = []
    losers = [f.name for f in fits if not f.converged and f is not best]
    if losers:
        notes.append(
            f"{', '.join(losers)}: the optimiser did not converge, so "
            f"{'this model' if len(losers) == 1 else 'these models'} could fit better than "
            f"reported and the choice of {best.name} could change"
        )
    if not best.converged:
        notes.append(
            f"the chosen model {best.name}: the optimiser did not converge; its parameters "
            "are not the maximum-likelihood ones (converged, it would fit better, so the "
            + (
                "choice would not change)"
                if not losers
                else "choice would not change against the converged models)"
            )
        )
    return notes


def _augmented(best: ModelFit, rate: float | None) -> tuple[list, list, float | None, float | None]:
    """The coloured states of ``best``: phi, q, tau_c and the AR(1) stationary variance."""
    phi: list[float] = []
    q: list[float] = []
    tau = s2 = None
    if best.phi is not None:
        phi.append(best.phi)
        q.append(best.q_ar)
        dt = 1.0 / rate if rate else 1.0
        # phi = exp(-T / tau_c)
        tau = float(-dt / np.log(best.phi)) if 0 < best.phi < 1 else None
        # sigma_b² = q / (1 - phi²)
        s2 = float(best.q_ar / (1 - best.phi**2)) if abs(best.phi) < 1 else None
    if best.q_rw is not None:
        phi.append(1.0)
        q.append(best.q_rw)
    return phi, q, tau, s2


def fit_coloured_noise(
    z: ArrayLike,
    rate: float | None = None,
    models: Sequence[str] = DEFAULT_MODELS,
    criterion: str = "bic",
    progress: Callable[[float], None] | None = None,
    regimes: str = DEFAULT_REGIMES,
) -> ColouredNoiseFit:
    """Fit white, white + AR(1) and white + random-walk noise models; pick one by BIC or AIC.

    Parameters
    ----------
    z : array_like, shape (n,)
        The noise record (a residual, or a static sensor's log); a straight
        line is removed first.
    rate : float, optional
        Samples per second (for ``tau_c`` in seconds).
    models : sequence of str
        Among ``"white"``, ``"white+ar1"``, ``"white+rw"``, ``"white+ar1+rw"``.
    criterion : {"bic", "aic"}
    progress : callable, optional
        Called with the fraction done after each model.
    regimes : {"all", "still"}
        Fit the whole record, or its longest still stretch only
        (:func:`~noisevar.estimators.regimes.longest_still_stretch`; said in ``notes``).

    Returns
    -------
    ColouredNoiseFit

    Notes
    -----
    docs/algorithms.md §E5. The record is standardised before the fits and the
    variances scaled back, so the choice, ``phi`` and ``r / unit²`` do not depend on
    the units. Parameters are per sample: ``q`` is the variance of each coloured
    state's increment. A fit that did not converge is said in ``notes``.
    """
    arr = _check(z, rate, models, criterion)
    regime_notes = []
    if check_regimes(regimes) == "still":
        # found on the record x 2**e (exact): its whole R may be beyond a float here
        scaled = np.ldexp(arr, scale_exponent(arr))
        stretch = longest_still_stretch(scaled, MIN_SAMPLES, "the noise models")
        arr = _check(stretch.take(arr), rate, models, criterion)
        regime_notes.append(stretch.note)
    y, scale, e = _standardise(arr)
    fits = []
    for i, name in enumerate(models):
        fits.append(_rescale(_fit_one(y, name), scale, arr.size, e))
        if progress is not None:
            progress((i + 1) / len(models))
    best = min(fits, key=lambda f: getattr(f, criterion))
    phi, q, tau, s2 = _augmented(best, rate)
    notes = regime_notes + convergence_notes(fits, best)
    if best.phi is not None and best.phi <= 0:
        notes.append("the AR(1) part has phi <= 0: it is not a Gauss-Markov process")
    return ColouredNoiseFit(
        model=best.name,
        criterion=criterion,
        r=best.r,
        phi=tuple(phi),
        q=tuple(q),
        tau_c=tau,
        sigma2_ar=s2,
        fits=tuple(fits),
        rate=rate,
        n=int(arr.size),
        notes=tuple(notes),
        regimes=regimes,
    )
