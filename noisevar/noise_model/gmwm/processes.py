"""The processes of a composite IMU model: their Haar wavelet variance and spectrum.

docs/algorithms.md §E10. Everything here is per sample (scales ``tau`` in samples,
frequencies ``f`` in cycles per sample on ``[0, 1/2]``, two-sided spectra); each process
converts its internal parameters to the IEEE-952 continuous units at the end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from noisevar.noise_model.gmwm.wavelet import flicker_wv

#: Haar wavelet variance of unit flicker: flat at ``(ln 2 / pi) B^2`` (half the Allan
#: variance's ``(2 ln 2 / pi) B^2``), exact for large scales.
FLICKER_WV = math.log(2.0) / math.pi


@dataclass(frozen=True)
class Process:
    """A process of a composite model.

    ``params`` names its internal (per-sample) parameters, all positive and fitted as
    logarithms; ``public`` names what :meth:`convert` returns, with ``units`` (templates
    on the data's unit ``{u}``).
    """

    key: str
    name: str
    params: tuple[str, ...]
    public: tuple[str, ...]
    units: tuple[str, ...]
    description: str

    @property
    def linear(self) -> bool:
        """Its wavelet variance is its one parameter times a shape of the scales."""
        return self.key != "GM"

    def wv(self, p: NDArray, tau: NDArray) -> NDArray:
        """Haar wavelet variance at scales ``tau`` (samples) for parameters ``p``."""
        t = np.asarray(tau, dtype=float)
        if self.key == "WN":  # white noise sigma^2
            return p[0] / t
        if self.key == "QN":  # quantisation: y_k = q_k - q_{k-1}, var(q) = p
            return 6.0 * p[0] / t**2
        if self.key == "RW":  # random walk, increments of variance gamma^2
            return (t**2 + 2.0) * p[0] / (12.0 * t)
        if self.key == "DR":  # drift omega per sample, p = omega^2
            return p[0] * t**2 / 16.0
        if self.key == "FL":  # flicker of bias instability B, p = B^2
            return flicker_wv(t) * p[0]
        return _gm_wv(p[0], p[1], t)

    def jac(self, p: NDArray, tau: NDArray) -> NDArray:
        """Derivatives of :meth:`wv` with respect to the log of each parameter.

        Returns shape ``(len(params), scales)``. All but the GM are linear in their one
        parameter (the derivative is the wavelet variance itself); the GM's in its
        correlation time is analytic (:func:`_gm_wv_jac`).
        """
        t = np.asarray(tau, dtype=float)
        if self.linear:
            return self.wv(p, t)[None, :]
        return np.stack(_gm_wv_jac(p[0], p[1], t))

    def spectrum(
        self, p: NDArray, f: NDArray, s2: NDArray | None = None, c2: NDArray | None = None
    ) -> NDArray:
        """Two-sided spectrum (per sample) at ``f`` cycles per sample; 0 for the drift.

        ``s2 = sin^2(pi f)`` and ``c2 = cos(2 pi f)`` may be given, precomputed.
        """
        s2 = np.sin(np.pi * f) ** 2 if s2 is None else s2
        if self.key == "WN":
            return np.full(f.shape, p[0])
        if self.key == "QN":
            return 4.0 * p[0] * s2
        if self.key == "RW":
            return p[0] / (4.0 * s2)
        if self.key == "DR":
            return np.zeros(f.shape)
        if self.key == "FL":
            return p[0] / (2.0 * math.pi * f)
        phi = math.exp(-1.0 / p[1])
        innovation = p[0] * (1.0 - phi**2)
        c2 = np.cos(2.0 * np.pi * f) if c2 is None else c2
        return innovation / (1.0 + phi**2 - 2.0 * phi * c2)

    def convert(self, p: NDArray, rate: float) -> tuple[float, ...]:
        """The public values (IEEE-952 continuous units; GM: std and seconds)."""
        if self.key == "WN":
            return (math.sqrt(p[0] / rate),)  # N = sigma / sqrt(fs)
        if self.key == "QN":
            return (math.sqrt(p[0]) / rate,)  # Q in unit*s
        if self.key == "RW":
            return (math.sqrt(p[0] * rate),)  # K = gamma sqrt(fs)
        if self.key == "DR":
            return (math.sqrt(p[0]) * rate,)  # R = omega fs, unit/s
        if self.key == "FL":
            return (math.sqrt(p[0]),)
        return (math.sqrt(p[0]), float(p[1]) / rate)

    def start(self, tau: NDArray, nu: NDArray) -> list[NDArray]:
        """Starting values read from the wavelet variance's lines (several for a GM)."""
        if self.key == "WN":
            return [np.array([nu[0] * tau[0]])]
        if self.key == "QN":
            return [np.array([0.05 * nu[0] * tau[0] ** 2 / 6.0])]
        if self.key == "RW":
            return [np.array([0.5 * 12.0 * nu[-1] / tau[-1]])]
        if self.key == "DR":
            return [np.array([0.1 * 16.0 * nu[-1] / tau[-1] ** 2])]
        if self.key == "FL":
            return [np.array([0.5 * float(np.min(nu)) / FLICKER_WV])]
        starts = []
        # a GM's wavelet variance peaks near tau = 2 tau_c: put the peak on the data
        for j in np.unique(np.linspace(1, tau.size - 2, 4).round().astype(int)):
            tc = tau[j] / 2.0
            peak = float(_gm_wv(1.0, tc, np.array([tau[j]]))[0])
            starts.append(np.array([0.5 * nu[j] / peak, tc]))
        return starts


def _gm_wv_jac(var: float, tc: float, t: NDArray) -> tuple[NDArray, NDArray]:
    """The GM's wavelet variance and its derivative with respect to ``log tc``.

    With ``u = 1 / tc``, ``nu = var G(u)``, ``G = bracket / (2 h^2 E(1)^2)``:
    ``d nu / d log tc = -u var G'(u)``, ``G' = (bracket' - 2 bracket e^-u / E(1)) /
    (2 h^2 E(1)^2)``, the bracket's derivative by terms (or by its series for small
    ``h u``, as :func:`_gm_wv`).
    """
    u = 1.0 / tc
    h = t / 2.0
    e1 = -math.expm1(-u)
    bracket, dbracket = _bracket(h, u, True)
    den = 2.0 * h**2 * e1**2
    g = bracket / den
    dg = (dbracket - 2.0 * bracket * math.exp(-u) / e1) / den
    return var * g, -u * var * dg


#: Powers of ``u`` in the bracket's Taylor series (:func:`_bracket`).
SERIES_POWERS = np.arange(3, 10)
#: ``h u`` below which the bracket is summed from its Taylor series.
SERIES_BELOW = 1e-2


@lru_cache(maxsize=64)
def _constants(h: tuple[float, ...]) -> tuple[NDArray, ...]:
    """Per half-scale ``h``: ``(h, [h+1, 2h+1], 2h, 4(h+1), 2h+1, series coefficients)``,
    the coefficients ``(-1)^(k+1) (h 2^k + 3 - 4 (h+1)^k + (2h+1)^k) / k!`` (powers x h)."""
    hv = np.array(h)
    k = SERIES_POWERS[:, None].astype(float)
    hh = hv[None, :]
    sign = (-1.0) ** (k + 1.0)
    fact = np.array([math.factorial(int(j)) for j in SERIES_POWERS], dtype=float)[:, None]
    coef = sign * ((hh * 2.0**k + 3.0 - 4.0 * (hh + 1.0) ** k + (2.0 * hh + 1.0) ** k) / fact)
    return (
        hv,
        np.stack([hv + 1.0, 2.0 * hv + 1.0]),
        2.0 * hv,
        4.0 * (hv + 1.0),
        2.0 * hv + 1.0,
        coef,
    )


def _bracket(h: NDArray, u: float, deriv: bool) -> tuple[NDArray, NDArray | None]:
    """``h E(2) + 3 E(1) - 4 E(h+1) + E(2h+1)`` (``E(a) = 1 - e^(-a u)``), and its
    derivative in ``u`` when ``deriv``.

    Its terms in ``u`` and ``u^2`` cancel, so for ``h u`` small (:data:`SERIES_BELOW`) it
    is its Taylor series from ``u^3`` on (to ``u^9``).
    """
    hv, a, two_h, four_h1, two_h1, coef = _constants(tuple(h.tolist()))
    e2, e1 = -math.expm1(-2.0 * u), -math.expm1(-u)
    m = np.expm1(a * -u)  # -E(h+1), -E(2h+1)
    bracket = hv * e2 + 3.0 * e1 + 4.0 * m[0] - m[1]
    small = hv * u < SERIES_BELOW
    some = bool(small[0] or small.any())
    if some:
        bracket[small] = u**SERIES_POWERS @ coef[:, small]
    if not deriv:
        return bracket, None
    dbracket = (
        two_h * (1.0 - e2) + 3.0 * (1.0 - e1) - four_h1 * (1.0 + m[0]) + two_h1 * (1.0 + m[1])
    )
    if some:
        dbracket[small] = (SERIES_POWERS * u ** (SERIES_POWERS - 1.0)) @ coef[:, small]
    return bracket, dbracket


def _gm_wv(var: float, tc: float, t: NDArray) -> NDArray:
    """Haar WV of a first-order Gauss-Markov process of stationary variance ``var``.

    ``phi = exp(-1 / tc)`` (``tc`` in samples), innovation variance ``s2 = var (1 - phi^2)``:
    ``(t/2 - 3 phi - t phi^2/2 + 4 phi^(t/2+1) - phi^(t+1)) s2 / (2 (t/2)^2 (1-phi)^2 (1-phi^2))``.
    That is the spec's eq. F4.5 over 2: with our Haar filter (white noise ``s2 / t``) it
    gives ``v (1 - phi) / 2`` at ``t = 2`` and ``s2 / ((1 - phi)^2 t)`` at large ``t``,
    as it must, and it matches simulation (tests). The bracket: :func:`_bracket`.
    """
    u = 1.0 / tc
    h = t / 2.0
    bracket, _ = _bracket(h, u, False)
    return var * bracket / (2.0 * h**2 * math.expm1(-u) ** 2)


PROCESSES = {
    p.key: p
    for p in (
        Process("QN", "quantization", ("q2",), ("Q",), ("{u}·s",), "white angle (phase) noise"),
        Process("WN", "white_noise", ("s2",), ("N",), ("{u}/√Hz",), "white rate noise (ARW/VRW)"),
        Process(
            "FL", "flicker", ("b2",), ("B",), ("{u}",), "flicker rate noise (bias instability B)"
        ),
        Process(
            "GM",
            "gauss_markov",
            ("var", "tc"),
            ("sigma", "tau_c"),
            ("{u}", "s"),
            "first-order Gauss-Markov bias (std sigma, correlation time tau_c)",
        ),
        Process("RW", "random_walk", ("g2",), ("K",), ("{u}/s/√Hz",), "rate random walk"),
        Process("DR", "drift", ("w2",), ("R",), ("{u}/s",), "rate ramp (deterministic drift)"),
    )
}
