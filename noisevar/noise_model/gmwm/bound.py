"""The Whittle information bound of a composite IMU model's parameters (docs/algorithms.md §E10).

How well *any* efficient estimator can recover a composite model's parameters from a
record of ``n`` samples: the inverse of the Whittle (spectral) Fisher information of the
first differences (stationary even with a random walk), mapped to the public
(IEEE-952) parameters as relative standard deviations.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from noisevar.errors import NoisevarError
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm.model import labels, name_of, parse_model
from noisevar.noise_model.gmwm.processes import PROCESSES

#: Fourier frequencies summed one by one (the lowest, where the coloured processes
#: live); above, :data:`BINS` log-spaced bins, each its count times its centre's term.
EXACT = 4096
BINS = 2048
#: Step (in the log of a parameter) of the numerical exponents of the public conversions.
LOG_STEP = 1e-3


@dataclass(frozen=True, eq=False)
class InformationBound:
    """Whittle information bound of a composite model on a record of ``n`` samples.

    Attributes
    ----------
    model : str
        The model, e.g. ``"WN+RW"``.
    names : tuple of str
        The public parameters (``N``, ``K``, ``GM1.sigma``, ``GM1.tau_c``...).
    values : tuple of float
        Their values (IEEE-952 units, as :class:`~noisevar.noise_model.ImuModel`).
    relative_sd : tuple of float
        Each parameter's bound: the standard deviation of its log (about its relative
        standard deviation) for an efficient estimator.
    log_cov : ndarray
        The inverse information of the public parameters' logs, in the order of ``names``.
    n : int
        Samples of the record.
    rate : float
        Sample rate (Hz).
    """

    model: str
    names: tuple[str, ...]
    values: tuple[float, ...]
    relative_sd: tuple[float, ...]
    log_cov: NDArray
    n: int
    rate: float

    def sd(self, name: str) -> float:
        """The bound's relative standard deviation of ``name``."""
        return self.relative_sd[self._index(name)]

    def within(self, name: str, tolerance: float) -> float:
        """Probability that an efficient estimate of ``name`` is within ``tolerance``
        (relative, e.g. 0.03) of the truth: its log normal with the bound's sd."""
        if not 0.0 < tolerance < 1.0:
            raise NoisevarError(f"tolerance must be in (0, 1); got {tolerance!r}.")
        s = self.sd(name)
        lo, hi = math.log1p(-tolerance) / s, math.log1p(tolerance) / s
        return float(stats.norm.cdf(hi) - stats.norm.cdf(lo))

    def _index(self, name: str) -> int:
        if name not in self.names:
            raise NoisevarError(f"No parameter {name!r}; the model has {', '.join(self.names)}.")
        return self.names.index(name)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "model": self.model,
            "n": int(self.n),
            "rate": float(self.rate),
            "parameters": [
                {"name": k, "value": float(v), "relative_sd": float(s)}
                for k, v, s in zip(self.names, self.values, self.relative_sd, strict=True)
            ],
        }


def fisher_bound(model: str, values: Mapping[str, float], n: int, rate: float) -> InformationBound:
    """Whittle information bound of a composite model's parameters on ``n`` samples.

    Parameters
    ----------
    model : str
        The model, e.g. ``"WN+RW"`` or ``"QN+WN+GM+RW"`` (no drift: it has no spectrum).
    values : mapping of str to float
        Every public parameter of the model in IEEE-952 units, named as
        :class:`~noisevar.noise_model.ImuModel`'s (``Q``, ``N``, ``B``, ``GM1.sigma``,
        ``GM1.tau_c``, ``K``; with two GMs ``GM1`` the shorter correlation time).
    n : int
        Samples of the record.
    rate : float
        Sample rate (Hz).

    Returns
    -------
    InformationBound

    Notes
    -----
    docs/algorithms.md §E10, *Information bound*. On the ``n - 1`` first differences
    (spectrum ``4 sin^2(pi f) S(f)``), ``I_ij = sum_k d log S/d theta_i d log S/d theta_j``
    over the Fourier frequencies ``k / (n - 1)`` in ``(0, 1/2]`` (the Nyquist one half):
    half the sum over all non-zero ones. Differencing cancels in the derivatives, so it
    only makes the random walk's Whittle likelihood valid. White noise alone gives
    ``sd(N) = 1 / sqrt(2 (n - 2))``.
    """
    keys = parse_model(model)
    if "DR" in keys:
        raise NoisevarError(
            "The drift is deterministic: it has no spectrum, and the Whittle bound does not "
            "hold it. Give the model without DR."
        )
    if not (math.isfinite(rate) and rate > 0):
        raise NoisevarError(f"rate must be a positive number of Hz; got {rate!r}.")
    if n < 8:
        raise NoisevarError(f"n must be at least 8 samples; got {n!r}.")
    names, pub = _public_names(keys), []
    for name in names:
        v = values.get(name)
        if v is None or not (math.isfinite(v) and v > 0):
            raise NoisevarError(f"{model} needs a positive {name}; got {v!r}.")
        pub.append(float(v))
    internal, expo = _internal(keys, np.log(pub), rate)
    info = information(keys, internal, int(n))
    try:
        cov_internal = np.linalg.inv(info)
    except np.linalg.LinAlgError:
        cov_internal = np.full(info.shape, np.inf)
    cov = expo @ cov_internal @ expo.T
    rel = np.sqrt(np.diag(cov))
    if not np.all(np.isfinite(rel)):
        raise NoisevarError(f"The information of {model} on {n} samples is singular.")
    return InformationBound(
        name_of(keys), tuple(names), tuple(pub), tuple(rel.tolist()), cov, int(n), rate
    )


def _public_names(keys: tuple[str, ...]) -> list[str]:
    out = []
    for label, key in zip(labels(keys), keys, strict=True):
        for pub in PROCESSES[key].public:
            out.append(pub if key != "GM" else f"{label}.{pub}")
    return out


def internal_params(keys: tuple[str, ...], values: NDArray, rate: float) -> NDArray:
    """The internal (per-sample) parameters of the public ``values`` (IEEE-952 units,
    all positive) of the processes ``keys``: :meth:`Process.convert` inverted."""
    return _internal(keys, np.log(np.asarray(values, dtype=float)), rate)[0]


def _convert_log(keys: tuple[str, ...], log_p: NDArray, rate: float) -> NDArray:
    """Logs of the public values from the internal parameters' logs."""
    parts = est.split(keys, np.exp(log_p))
    return np.log(
        [v for k, p in zip(keys, parts, strict=True) for v in PROCESSES[k].convert(p, rate)]
    )


def _internal(keys: tuple[str, ...], log_pub: NDArray, rate: float) -> tuple[NDArray, NDArray]:
    """Internal parameters of the public values, and ``d log public / d log internal``.

    Every conversion (:meth:`Process.convert`) is a product of powers, so its log is
    linear in the internal logs: its exponents by central differences, its offset at 0.
    """
    k = log_pub.size
    offset = _convert_log(keys, np.zeros(k), rate)
    expo = np.empty((k, k))
    for j in range(k):
        step = np.zeros(k)
        step[j] = LOG_STEP
        up, down = _convert_log(keys, step, rate), _convert_log(keys, -step, rate)
        expo[:, j] = (up - down) / (2.0 * LOG_STEP)
    return np.exp(np.linalg.solve(expo, log_pub - offset)), expo


def _frequencies(n: int) -> tuple[NDArray, NDArray]:
    """Fourier frequencies of the ``n - 1`` differences in ``(0, 1/2]`` and their weights
    (the lowest one by one, then log-spaced bins with their counts)."""
    m = n - 1
    top = m // 2  # the highest k; the Nyquist one (m even) counts half
    k = np.arange(1, min(top, EXACT) + 1, dtype=float)
    w = np.ones_like(k)
    if top > EXACT:
        edges = np.unique(np.round(np.geomspace(EXACT, top, BINS + 1)))
        count = np.diff(edges)
        centre = 0.5 * (edges[1:] + edges[:-1] + 1.0)  # mean of the k in (lo, hi]
        k, w = np.concatenate([k, centre]), np.concatenate([w, count])
    if m % 2 == 0:
        w[-1] -= 0.5
    return k / m, w


def information(keys: tuple[str, ...], p: NDArray, n: int) -> NDArray:
    """Whittle information of the internal log-parameters ``p`` on ``n`` samples."""
    f, w = _frequencies(n)
    s2, c2 = np.sin(np.pi * f) ** 2, np.cos(2.0 * np.pi * f)
    cols, total = [], np.zeros_like(f)
    for key, q in zip(keys, est.split(keys, p), strict=True):
        s = PROCESSES[key].spectrum(q, f, s2, c2)
        total += s
        cols.append(s)
        if key == "GM":
            cols.append(s * _gm_log_tc(q[1], s2))
    g = np.array(cols) / total  # d log S / d log p, one row per parameter
    return (g * w) @ g.T


def _gm_log_tc(tc: float, s2: NDArray) -> NDArray:
    """``d log S_GM / d log tc``: ``S = v (1 - phi^2) / ((1 - phi)^2 + 4 phi sin^2(pi f))``,
    ``phi = exp(-1/tc)``, ``d phi / d log tc = phi / tc``."""
    phi = math.exp(-1.0 / tc)
    one_m2 = -math.expm1(-2.0 / tc)  # 1 - phi^2
    one_m = -math.expm1(-1.0 / tc)  # 1 - phi
    den = one_m**2 + 4.0 * phi * s2
    dlog_dphi = -2.0 * phi / one_m2 - (-2.0 * one_m + 4.0 * s2) / den
    return dlog_dphi * phi / tc
