"""Composite IMU noise models by GMWM, with model choice and intervals (docs/algorithms.md §E10).

:func:`fit_imu_model` is the public entry: per axis, the Haar wavelet variance, the GMWM
fit of each candidate model, the choice by the wavelet variance information criterion,
delta-method intervals, and the bias a random-walk-only filter can use.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm.processes import PROCESSES

#: Default confidence level of the intervals (one sigma, as :func:`noisevar.allan`).
ONE_SIGMA = 0.6826894921370859
#: Order of the processes in a model's name; at most :data:`MAX_GM` Gauss-Markov ones.
ORDER = tuple(PROCESSES)
MAX_GM = 2
#: Default horizon (s) of the random-walk equivalent of the bias processes.
HORIZON = 10.0


@dataclass(frozen=True)
class Parameter:
    """One fitted parameter: ``name`` (``"N"``, ``"GM1.tau_c"``...), value, interval, unit."""

    name: str
    process: str
    value: float
    interval: tuple[float, float]
    unit: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "name": self.name,
            "process": self.process,
            "value": float(self.value),
            "interval": [float(self.interval[0]), float(self.interval[1])],
            "unit": self.unit,
        }


@dataclass(frozen=True)
class ModelRow:
    """A row of the model comparison table.

    ``objective`` is the GMWM objective at the fit (about chi-square with ``scales -
    n_params`` degrees of freedom for the right model); ``wvic = objective + 2 n_params``
    (Guerrier et al.'s criterion in its asymptotic form); ``hq = objective + 2 log(log n)
    n_params`` (Hannan-Quinn's, the default criterion of the choice) and ``bic =
    objective + log(n) n_params``, ``n`` the samples.
    """

    model: str
    n_params: int
    objective: float
    wvic: float
    hq: float
    bic: float
    chosen: bool

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "model": self.model,
            "n_params": self.n_params,
            "objective": float(self.objective),
            "wvic": float(self.wvic),
            "hq": float(self.hq),
            "bic": float(self.bic),
            "chosen": self.chosen,
        }


@dataclass(frozen=True)
class FilterBias:
    """The bias model for a filter: GM states, or one random walk of the same size.

    Attributes
    ----------
    random_walk : float
        Density ``K_eq`` (unit/s/√Hz) of the random walk whose Allan variance equals the
        bias processes' (RW, GM, flicker, drift) at ``tau = horizon``:
        ``K_eq^2 = 3 sigma^2_bias(horizon) / horizon``. For a GM alone and a short horizon
        this is ``sigma sqrt(2 / tau_c)``; it covers the GM's bias change over any
        horizon from ``horizon`` on, and overstates it past ``tau_c``.
    interval : tuple of float
        ``K_eq``'s interval at the fit's level: the delta method on ``log K_eq`` with the
        fit's covariance of the log-parameters (``fitting.filter_bias``).
    horizon : float
        The horizon (s).
    gm_sigma, gm_tau_c : tuple of float
        The fitted Gauss-Markov biases (std, unit; correlation time, s), for a filter
        that holds each as a state ``b' = -b / tau_c + w``, ``q = 2 sigma^2 / tau_c``.
    note : str
        The conversion and its assumption, in words.
    """

    random_walk: float
    interval: tuple[float, float]
    horizon: float
    gm_sigma: tuple[float, ...]
    gm_tau_c: tuple[float, ...]
    note: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "random_walk": float(self.random_walk),
            "interval": [float(self.interval[0]), float(self.interval[1])],
            "horizon": float(self.horizon),
            "gm_sigma": [float(v) for v in self.gm_sigma],
            "gm_tau_c": [float(v) for v in self.gm_tau_c],
            "note": self.note,
        }


@dataclass(frozen=True, eq=False)
class ImuModel:
    """A composite noise model of one axis (or of several records pooled).

    Attributes
    ----------
    model : str
        The chosen model, e.g. ``"QN+WN+GM+RW"`` (:data:`ORDER`).
    parameters : tuple of Parameter
        Its parameters in IEEE-952 continuous units (``Q``, ``N``, ``B``, ``GMi.sigma``,
        ``GMi.tau_c``, ``K``, ``R``), with delta-method intervals at level ``ci``.
    scales : ndarray
        The wavelet variance's scales (s).
    wv : ndarray
        The (robust, with ``robust``) Haar wavelet variance at ``scales``.
    wv_interval : tuple of ndarray
        Its interval at level ``ci`` under the fitted model's covariance.
    table : tuple of ModelRow
        Every model fitted, with its criterion; the chosen one flagged.
    filter_bias : FilterBias
        The bias for a filter (GM states, or the equivalent random walk).
    notes : tuple of str
        A misfit of the chosen model; a model with a random walk nearly as good as a
        chosen one without (its K and interval: ``fitting.random_walk_note``); N at its
        lower bound (``fitting.white_at_bound``); a noise level that varies (motion) or
        the still stretch fitted (``regimes``).
    """

    model: str
    parameters: tuple[Parameter, ...]
    rate: float
    unit: str
    ci: float
    robust: bool
    scales: NDArray
    wv: NDArray
    wv_interval: tuple[NDArray, NDArray]
    table: tuple[ModelRow, ...]
    filter_bias: FilterBias
    keys: tuple[str, ...]
    internal: NDArray
    notes: tuple[str, ...] = ()

    def value(self, name: str) -> float:
        """A parameter's value; 0 for a process the chosen model does not hold."""
        for p in self.parameters:
            if p.name == name:
                return p.value
        return 0.0

    def parameter(self, name: str) -> Parameter:
        """The parameter called ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise NoisevarError(f"No parameter {name!r} in the model {self.model}.")

    def components(self, scales: ArrayLike | None = None) -> dict[str, NDArray]:
        """Each process's wavelet variance at ``scales`` (s; default the data's)."""
        tau = self._tau(scales)
        names = labels(self.keys)
        parts = est.split(self.keys, self.internal)
        return {
            lab: PROCESSES[k].wv(p, tau) for lab, k, p in zip(names, self.keys, parts, strict=True)
        }

    def model_wv(self, scales: ArrayLike | None = None) -> NDArray:
        """The model's wavelet variance (the sum of the components) at ``scales`` (s)."""
        return est.model_wv(self.keys, self.internal, self._tau(scales))

    def _tau(self, scales: ArrayLike | None) -> NDArray:
        s = self.scales if scales is None else np.asarray(scales, dtype=float)
        return s * self.rate

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary, with the components' wavelet variances."""
        return {
            "model": self.model,
            "rate": float(self.rate),
            "unit": self.unit,
            "ci": float(self.ci),
            "robust": self.robust,
            "parameters": [p.to_dict() for p in self.parameters],
            "scales": self.scales.tolist(),
            "wv": self.wv.tolist(),
            "wv_interval": [self.wv_interval[0].tolist(), self.wv_interval[1].tolist()],
            "model_wv": self.model_wv().tolist(),
            "components": {k: v.tolist() for k, v in self.components().items()},
            "table": [r.to_dict() for r in self.table],
            "filter_bias": self.filter_bias.to_dict(),
            "notes": list(self.notes),
        }


def labels(keys: tuple[str, ...]) -> list[str]:
    n_gm = keys.count("GM")
    out, i = [], 0
    for k in keys:
        if k == "GM" and n_gm > 1:
            i += 1
            out.append(f"GM{i}")
        else:
            out.append("GM1" if k == "GM" else k)
    return out


def parse_model(spec: str) -> tuple[str, ...]:
    """``"WN+RW+GM"`` (or ``"wn + rw + 2gm"``) to its keys in :data:`ORDER`."""
    keys: list[str] = []
    for part in spec.upper().replace(" ", "").split("+"):
        count = 1
        if part[:1].isdigit():
            count, part = int(part[0]), part[1:]
        if part not in PROCESSES:
            raise NoisevarError(
                f"Unknown process {part!r} in the model {spec!r}; the processes are "
                + ", ".join(f"{k} ({p.name})" for k, p in PROCESSES.items())
            )
        keys += [part] * count
    if keys.count("GM") > MAX_GM or any(keys.count(k) > 1 for k in ORDER if k != "GM"):
        raise NoisevarError(f"The model {spec!r} repeats a process (at most {MAX_GM} GM).")
    return tuple(sorted(keys, key=ORDER.index))


def name_of(keys: tuple[str, ...]) -> str:
    """The model's name, ``"QN+WN+2GM+RW"`` style."""
    out = []
    for k in ORDER:
        c = keys.count(k)
        if c:
            out.append(k if c == 1 else f"{c}{k}")
    return "+".join(out)
