"""Conservative (overbounding) noise terms: the model's Allan variance at or above the
data's upper confidence bound at every fitted tau (docs/algorithms.md §E7.3).

In the spirit of Lethander & Taylor (NAVIGATION 70(3), 2023): instead of the folklore
"multiply the Allan values by 10", the terms are raised, never lowered, by the least
amount that puts the model's Allan variance on or above the upper bound of every tau
the fit used. "Least" is a linear programme in the squared terms: minimise the model's
mean ratio to the bound over the taus.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog
from scipy.stats import chi2

from noisevar.errors import NoisevarError
from noisevar.noise_model.inertial import TERMS, InertialNoise

#: Confidence level of the upper bound the overbound sits on (one-sided per tau).
OVERBOUND_CI = 0.95
#: The terms a Kalibr-style consumer holds (white noise and bias random walk).
NK = ("N", "K")
_ALL = tuple(t.symbol for t in TERMS)


@dataclass(frozen=True)
class Overbound:
    """Terms raised until the model's Allan curve covers the data's upper bound.

    Attributes
    ----------
    values : dict of str to float
        Each term (symbol Q, N, B, K, R) of the overbound, in the fit's units.
    best : dict of str to float
        The best fit's terms.
    factors : dict of str to float
        ``values / best`` for each free term (inf where the best fit had it at 0).
    free : tuple of str
        The terms that were allowed to rise (the others are 0 in ``values``).
    ci : float
        Confidence level of the per-tau upper bound.
    taus, upper : ndarray
        The fitted taus and the upper bound of the Allan deviation there.
    covers : tuple of str
        What the raise is for, in words (bias instability a consumer cannot hold; the
        regimes the record had).
    """

    values: dict[str, float]
    best: dict[str, float]
    factors: dict[str, float]
    free: tuple[str, ...]
    ci: float
    taus: NDArray
    upper: NDArray
    covers: tuple[str, ...]

    def model(self, taus: NDArray | None = None) -> NDArray:
        """The overbound's Allan deviation at ``taus`` (default the fitted ones)."""
        t = self.taus if taus is None else np.asarray(taus, dtype=float)
        a = np.column_stack([s.coefficient(t) for s in TERMS])
        x = np.array([self.values[s.symbol] ** 2 for s in TERMS])
        return np.sqrt(a @ x)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "values": dict(self.values),
            "best": dict(self.best),
            "factors": {k: (None if not np.isfinite(v) else v) for k, v in self.factors.items()},
            "free": list(self.free),
            "ci": self.ci,
            "covers": list(self.covers),
        }


def upper_bound(fit: InertialNoise, ci: float = OVERBOUND_CI) -> NDArray:
    """The one-sided ``ci`` upper bound of the Allan deviation at each fitted tau.

    ``sigma² edf / chi2.ppf(1 - ci, edf)``, the chi-square bound of each tau's
    Allan variance with its equivalent degrees of freedom.
    """
    if not 0.5 <= ci < 1:
        raise NoisevarError(f"the confidence level must be in [0.5, 1), not {ci}")
    res = fit.allan
    edf = np.maximum(np.asarray(res.edf, dtype=float), 1.0)
    return np.sqrt(res.variance * edf / chi2.ppf(1.0 - ci, edf))


def overbound(
    fit: InertialNoise, *, free: tuple[str, ...] = NK, ci: float = OVERBOUND_CI
) -> Overbound:
    """The least raise of the ``free`` terms whose Allan curve covers the upper bound.

    Parameters
    ----------
    fit : InertialNoise
        The best fit of one axis.
    free : tuple of str
        Terms allowed to rise (default N and K, the ones Kalibr, VINS, ORB-SLAM3, PX4
        and ArduPilot hold); the others are set to 0, so the free terms carry their share.
        ``("Q", "N", "B", "K", "R")`` keeps every term of the fit and raises any.
    ci : float
        Confidence level of the per-tau upper bound (one-sided).

    Returns
    -------
    Overbound

    Notes
    -----
    docs/algorithms.md §E7.3. With ``x = term²`` the model's Allan variance is ``A x``
    (eq. E4.1); minimise ``Σ_τ (A x)_τ / U_τ²`` subject to ``A x ≥ U²`` and
    ``x ≥ x_best`` for the free terms (``scipy.optimize.linprog``, HiGHS).
    """
    bad = [s for s in free if s not in _ALL]
    if bad or not free:
        raise NoisevarError(f"free terms must be among {', '.join(_ALL)}; got {free!r}")
    taus = fit.allan.taus
    upper = upper_bound(fit, ci)
    a = np.column_stack([s.coefficient(taus) for s in TERMS])
    best = {s.symbol: fit.term(s.symbol).value for s in TERMS}
    idx = [i for i, s in enumerate(TERMS) if s.symbol in free]
    # rows scaled to "model / bound >= 1", columns to O(1): HiGHS's tolerances are absolute
    rel = a[:, idx] / (upper**2)[:, None]
    scale = 1.0 / rel.max(axis=0)
    rel = rel * scale
    lower = [best[TERMS[i].symbol] ** 2 / c for i, c in zip(idx, scale, strict=True)]
    sol = linprog(
        rel.sum(axis=0),
        A_ub=-rel,
        b_ub=-np.ones(taus.size),
        bounds=[(lo, None) for lo in lower],
        method="highs",
    )
    if sol.status != 0:
        raise NoisevarError(
            f"no overbound with the terms {', '.join(free)} covers the upper bound: {sol.message}"
        )
    values = dict.fromkeys(best, 0.0)
    for i, yi, c in zip(idx, sol.x, scale, strict=True):
        values[TERMS[i].symbol] = float(np.sqrt(max(yi * c, 0.0)))
    # the solver's feasibility tolerance: lift every free term by what it leaves short
    x = np.array([values[t.symbol] ** 2 for t in TERMS])
    short = float(np.max(upper**2 / np.maximum(a @ x, np.finfo(float).tiny)))
    if short > 1.0:
        values = {k: v * np.sqrt(short) for k, v in values.items()}
    factors = {
        s: (values[s] / best[s] if best[s] > 0 else (np.inf if values[s] > 0 else 1.0))
        for s in free
    }
    return Overbound(values, best, factors, tuple(free), ci, taus, upper, _covers(fit, free))


def _covers(fit: InertialNoise, free: tuple[str, ...]) -> tuple[str, ...]:
    """Words on what the raise holds that the best fit's free terms alone do not."""
    out = []
    dropped = [s.symbol for s in TERMS if s.symbol not in free and fit.term(s.symbol).value > 0]
    if "B" in dropped:
        out.append(
            f"the bias instability B (flat ADEV 0.664 B), which a model of "
            f"{' and '.join(free)} alone (Kalibr's) has no term for"
        )
    for s in dropped:
        if s != "B":
            out.append(f"the fitted {s} term, folded into {' and '.join(free)}")
    for s in TERMS:  # left out by the term choice, yet within what the record allows
        term = fit.term(s.symbol)
        if s.symbol not in free and term.value == 0 and term.interval[1] > 0:
            what = "the bias instability B" if s.symbol == "B" else f"the {s.symbol} term"
            out.append(
                f"{what} up to {term.interval[1]:.3g} {term.unit}, which the best fit leaves "
                "out (the record does not support it) but its upper bound allows"
            )
    out.append("each tau's chi-square scatter up to its upper bound")
    if fit.regimes == "all":
        out.append("the record's every regime, vibration in motion included")
    else:
        out.append("the still stretch only: vibration of the motion regimes is NOT covered")
    return tuple(out)
