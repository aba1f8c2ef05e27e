"""The GMWM estimator of one composite model on one wavelet variance (docs/algorithms.md §E10).

Guerrier, Skaloud, Stebler & Victoria-Feser, JASA 108 (2013): minimise
``(nu_hat - nu(theta))' Omega (nu_hat - nu(theta))``, ``Omega`` the inverse covariance of
``nu_hat``. The parameters are fitted as logarithms (all positive) with
``scipy.optimize.least_squares``; ``Omega`` is first the diagonal of a chi-square
approximation from the data, then the asymptotic covariance of the fitted model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cholesky
from scipy.optimize import least_squares

from noisevar.noise_model.gmwm.processes import PROCESSES
from noisevar.noise_model.gmwm.wavelet import (
    covariance_matrix,
    covariance_nodes,
    pair_integrals,
)

#: Reweighting passes with the fitted model's covariance.
PASSES = 2
#: Condition number above which only the diagonal of the covariance is inverted.
MAX_CONDITION = 1e12
#: Weight by the diagonal of the covariance only (intervals still use all of it).
DIAGONAL = True


@dataclass(frozen=True)
class WaveletVariance:
    """The wavelet variance an estimator fits: scales (samples), values, coefficients."""

    tau: NDArray
    nu: NDArray
    m: NDArray
    inflation: float = 1.0  # variance of a robust estimate over the classical one

    @property
    def n_samples(self) -> float:
        """Samples behind the finest scale (all records' for a pooled one)."""
        return float(self.m[0] + self.tau[0] - 1)


@dataclass(frozen=True)
class Solution:
    """A fitted model: internal parameters, their log-covariance, objective and weights."""

    keys: tuple[str, ...]
    log_params: NDArray
    log_cov: NDArray
    objective: float
    cov: NDArray

    @property
    def n_params(self) -> int:
        return int(self.log_params.size)


def sizes(keys: tuple[str, ...]) -> list[int]:
    """Number of internal parameters of each process."""
    return [len(PROCESSES[k].params) for k in keys]


def split(keys: tuple[str, ...], p: NDArray) -> list[NDArray]:
    """The internal parameters of each process, from the flat vector ``p``."""
    return np.split(np.asarray(p, dtype=float), np.cumsum(sizes(keys))[:-1])


@dataclass(frozen=True)
class Design:
    """A model at given scales: the linear processes' shapes and the GMs' positions.

    ``nu(p) = p[linear] @ shapes + sum of the GMs'``; the Jacobian in the log-parameters
    has the linear processes' components as columns, and each GM's two derivatives.
    """

    tau: NDArray
    linear: NDArray  # indices of the linear processes' parameters
    shapes: NDArray  # (linear, scales): their wavelet variance per unit parameter
    gm: tuple[int, ...]  # index of each GM's variance (its correlation time follows)
    n_params: int

    def wv(self, p: NDArray) -> NDArray:
        """Wavelet variance of the model at parameters ``p``."""
        out = p[self.linear] @ self.shapes
        for i in self.gm:
            out = out + PROCESSES["GM"].wv(p[i : i + 2], self.tau)
        return out

    def wv_jac(self, p: NDArray) -> tuple[NDArray, NDArray]:
        """:meth:`wv` and :meth:`jac` at once (a GM's first column is its wavelet variance)."""
        jac = self.jac(p)
        out = p[self.linear] @ self.shapes
        for i in self.gm:
            out = out + jac[:, i]
        return out, jac

    def jac(self, p: NDArray) -> NDArray:
        """Derivatives of :meth:`wv` in the log-parameters, shape ``(scales, params)``."""
        out = np.empty((self.tau.size, self.n_params))
        out[:, self.linear] = (p[self.linear][:, None] * self.shapes).T
        for i in self.gm:
            out[:, i : i + 2] = PROCESSES["GM"].jac(p[i : i + 2], self.tau).T
        return out


@lru_cache(maxsize=512)
def _design(keys: tuple[str, ...], tau: tuple[float, ...]) -> Design:
    t = np.array(tau)
    starts = np.concatenate([[0], np.cumsum(sizes(keys))[:-1]]).astype(int)
    lin = [int(i) for k, i in zip(keys, starts, strict=True) if PROCESSES[k].linear]
    shapes = [PROCESSES[k].wv(np.ones(1), t) for k in keys if PROCESSES[k].linear]
    gm = tuple(int(i) for k, i in zip(keys, starts, strict=True) if not PROCESSES[k].linear)
    shapes_arr = np.array(shapes) if shapes else np.zeros((0, t.size))
    return Design(t, np.array(lin, dtype=int), shapes_arr, gm, int(sum(sizes(keys))))


def design(keys: tuple[str, ...], tau: NDArray) -> Design:
    """The :class:`Design` of the model ``keys`` at the scales ``tau`` (cached)."""
    return _design(keys, tuple(np.asarray(tau, dtype=float).tolist()))


def model_wv(keys: tuple[str, ...], p: NDArray, tau: NDArray) -> NDArray:
    """Wavelet variance of the model: the sum of its processes'."""
    return design(keys, tau).wv(np.asarray(p, dtype=float))


def model_jac(keys: tuple[str, ...], p: NDArray, tau: NDArray) -> NDArray:
    """Derivatives of :func:`model_wv` in the log-parameters, shape ``(scales, params)``."""
    return design(keys, tau).jac(np.asarray(p, dtype=float))


def model_cov(
    keys: tuple[str, ...], p: NDArray, wv: WaveletVariance, diagonal: bool = False
) -> NDArray:
    """Asymptotic covariance of ``nu_hat`` under the model with parameters ``p``
    (``diagonal``: only its diagonal, the variances).

    Notes
    -----
    ``S = L + G``, ``L = sum p_k s_k`` the linear processes' spectra (fixed shapes ``s_k``),
    ``G`` the GMs': the integrals of ``S^2`` are ``sum p_k p_l int s_k s_l`` (cached per
    pair of shapes and scales) plus ``int G (2 L + G)``, evaluated on the nodes only
    with a GM.
    """
    p = np.asarray(p, dtype=float)
    model = design(keys, wv.tau)
    tau = tuple(model.tau.tolist())
    lin = [(k, float(p[i])) for k, i in zip(_linear_keys(keys), model.linear, strict=True)]
    a = 0.0
    for n, (k, pk) in enumerate(lin):
        for kl, pl in lin[n:]:
            a = a + (1.0 if kl == k else 2.0) * pk * pl * _shape_integrals(k, kl, tau, diagonal)
    if model.gm:
        nodes = covariance_nodes(model.tau, diagonal)
        g = sum(PROCESSES["GM"].spectrum(p[i : i + 2], *nodes) for i in model.gm)
        low = np.zeros_like(g)
        for k, pk in lin:
            low += pk * _unit_spectrum(k, tau, diagonal)
        a = a + pair_integrals(model.tau, g * (2.0 * low + g), diagonal)
    cov = covariance_matrix(model.tau, wv.m, a, wv.inflation, diagonal)
    # a drift adds no variance to the spectrum: keep every scale's variance positive
    floor = 2.0 * (model.wv(p) ** 2) / wv.m * 1e-6
    cov[np.diag_indices_from(cov)] = np.maximum(np.diag(cov), floor)
    return cov


def _linear_keys(keys: tuple[str, ...]) -> list[str]:
    return [k for k in keys if PROCESSES[k].linear]


@lru_cache(maxsize=32)
def _unit_spectrum(key: str, tau: tuple[float, ...], diagonal: bool) -> NDArray:
    """A linear process's spectrum at unit parameter on the covariance's nodes."""
    return PROCESSES[key].spectrum(np.ones(1), *covariance_nodes(np.array(tau), diagonal))


@lru_cache(maxsize=256)
def _shape_integrals(k: str, kl: str, tau: tuple[float, ...], diagonal: bool) -> NDArray:
    """``int |H_i|^2 |H_j|^2 s_k s_l`` for each pair of scales (unit parameters)."""
    u = _unit_spectrum(k, tau, diagonal) * _unit_spectrum(kl, tau, diagonal)
    return pair_integrals(np.array(tau), u, diagonal)


def chi2_cov(wv: WaveletVariance) -> NDArray:
    """Diagonal start: ``var nu_j = 2 nu_j^2 / eta_j``, ``eta_j = max(M_j / tau_j, 1)``.

    Percival & Walden's third equivalent degrees of freedom, which need no noise type.
    """
    eta = np.maximum(wv.m / wv.tau, 1.0)
    return np.diag(2.0 * wv.nu**2 / eta * wv.inflation)


def whitener(cov: NDArray) -> NDArray:
    """``L^-1`` with ``cov = L L'`` (its diagonal alone when ill-conditioned)."""
    d = np.sqrt(np.diag(cov))
    if not np.any(cov - np.diag(np.diag(cov))):  # diagonal: L^-1 = diag(1 / d) exactly
        return np.diag(1.0 / d)
    corr = cov / np.outer(d, d)
    try:
        if np.linalg.cond(corr) > MAX_CONDITION:
            raise np.linalg.LinAlgError
        low = cholesky(corr, lower=True)
    except (np.linalg.LinAlgError, ValueError):
        return np.diag(1.0 / d)
    return np.linalg.inv(low) / d[None, :]


def bounds(keys: tuple[str, ...], tau: NDArray, nu: NDArray) -> tuple[NDArray, NDArray]:
    """Bounds of the log-parameters: a GM's correlation time stays within the scales."""
    lo, hi = [], []
    for k in keys:
        for name in PROCESSES[k].params:
            if name == "tc":
                lo.append(math.log(0.5))
                hi.append(math.log(float(tau[-1])))
            else:  # no process may exceed the wavelet variance 1e6-fold at any scale
                lo.append(-np.inf)
                hi.append(math.log(1e6 * float(np.max(nu * tau**2))))
    return np.array(lo), np.array(hi)


def _solve(keys: tuple[str, ...], start: NDArray, wv: WaveletVariance, wl: NDArray):
    lo, hi = bounds(keys, wv.tau, wv.nu)
    x0 = np.clip(np.log(np.maximum(start, 1e-300)), lo + 1e-9, hi - 1e-9)

    model = design(keys, wv.tau)

    last: dict[str, NDArray] = {}  # least_squares asks the Jacobian where it last evaluated

    def resid(x: NDArray) -> NDArray:
        nu, last["jac"] = model.wv_jac(np.exp(x))
        last["x"] = x.copy()
        return wl @ (wv.nu - nu)

    def jac(x: NDArray) -> NDArray:
        same = "x" in last and np.array_equal(x, last["x"])
        return -wl @ (last["jac"] if same else model.jac(np.exp(x)))

    # a process the data do not support runs its log-parameter down to its -inf bound, where
    # trf's step arithmetic overflows: np.errstate changes no number, only the warnings
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        return least_squares(
            resid, x0, jac=jac, bounds=(lo, hi), method="trf", x_scale=1.0, max_nfev=400
        )


def fit(keys: tuple[str, ...], starts: list[NDArray], wv: WaveletVariance) -> Solution:
    """Fit the model ``keys`` from each start (chi-square weights), then reweight.

    Returns the best solution, with the delta-method covariance of the log-parameters
    ``(J' Omega J)^-1`` at the final weights.
    """
    wl = whitener(chi2_cov(wv))
    best = min((_solve(keys, s, wv, wl) for s in starts), key=lambda r: r.cost)
    cov = chi2_cov(wv)
    for i in range(PASSES):
        # the last pass's covariance serves the objective and intervals: all of it
        cov = model_cov(keys, np.exp(best.x), wv, diagonal=DIAGONAL and i < PASSES - 1)
        wl = whitener(np.diag(np.diag(cov)) if DIAGONAL else cov)
        best = _solve(keys, np.exp(best.x), wv, wl)
    # the objective of the choice: the residual under the full covariance
    resid = whitener(cov) @ (wv.nu - model_wv(keys, np.exp(best.x), wv.tau))
    return Solution(keys, best.x, sandwich(best.jac, wl, cov), float(resid @ resid), cov)


def sandwich(jac: NDArray, wl: NDArray, cov: NDArray) -> NDArray:
    """Delta-method covariance of the log-parameters, ``jac`` that of ``wl (nu - nu(x))``.

    ``(A'A)^-1 A' (wl cov wl') A (A'A)^-1`` with ``A = jac``: exact for any weights, and
    ``(J' cov^-1 J)^-1`` when ``wl`` whitens ``cov``.
    """
    bread = np.linalg.pinv(jac.T @ jac)
    meat = jac.T @ (wl @ cov @ wl.T) @ jac
    return bread @ meat @ bread


def order_gm(sol: Solution) -> Solution:
    """Gauss-Markov processes sorted by correlation time (GM1 the shortest)."""
    keys = sol.keys
    blocks = np.split(np.arange(sol.n_params), np.cumsum(sizes(keys))[:-1])
    gm = [b for k, b in zip(keys, blocks, strict=True) if k == "GM"]
    if len(gm) < 2:
        return sol
    gm_sorted = sorted(gm, key=lambda b: sol.log_params[b[1]])
    it = iter(gm_sorted)
    perm = np.concatenate([next(it) if k == "GM" else b for k, b in zip(keys, blocks, strict=True)])
    perm = perm.astype(int)
    return Solution(
        keys, sol.log_params[perm], sol.log_cov[np.ix_(perm, perm)], sol.objective, sol.cov
    )
