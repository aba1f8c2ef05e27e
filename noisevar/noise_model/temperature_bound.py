"""The Cramér-Rao bound of the temperature model under white noise and a bias random walk.

docs/algorithms.md §E9. How well *any* unbiased estimator can recover bias(T)'s slope and
the warm-up's time constant from a record, given its temperature profile, the white level
N and the rate random walk K: the inverse Fisher information of the block means.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.noise_model import _temperature_fit as tf
from noisevar.noise_model.temperature import (
    MIN_BLOCKS,
    REFERENCE_TEMPERATURE,
    TARGET_BLOCKS,
    TemperatureModel,
)

#: Relative step (in log tau) of the central difference behind d(warm-up)/d(log tau).
LOG_TAU_STEP = 1e-4


@dataclass(frozen=True, eq=False)
class TemperatureBound:
    """Cramér-Rao standard deviations of the temperature model's parameters.

    Attributes
    ----------
    names : tuple of str
        ``b``, ``c``, ``d`` (the polynomial's non-constant coefficients, up to the order),
        then with a warm-up ``amplitude`` and ``log_time_constant`` (the standard deviation
        of ``ln tau``: about the relative standard deviation of ``tau``).
    covariance : ndarray
        The inverse Fisher information, in the order of ``names``.
    white, walk : float
        N (unit/√Hz) and K (unit/s/√Hz) assumed.
    block : float
        Block length (s) of the means the information is counted on.
    """

    names: tuple[str, ...]
    covariance: NDArray
    white: float
    walk: float
    block: float

    def sd(self, name: str) -> float:
        """The bound's standard deviation of ``name``."""
        if name not in self.names:
            raise NoisevarError(f"No parameter {name!r}; this bound has {', '.join(self.names)}.")
        i = self.names.index(name)
        return float(math.sqrt(self.covariance[i, i]))


def temperature_bound(
    temperature: ArrayLike,
    rate: float,
    *,
    white: float,
    walk: float = 0.0,
    order: int = 1,
    warmup: tuple[float, float] | None = None,
    reference_temperature: float = REFERENCE_TEMPERATURE,
    block: float | None = None,
) -> TemperatureBound:
    """Cramér-Rao bound of bias(T) and the warm-up on a temperature profile.

    Parameters
    ----------
    temperature : array_like, shape (n,)
        The temperature (°C) at each sample.
    rate : float
        Sample rate (Hz).
    white : float
        White level N (unit/√Hz), > 0.
    walk : float
        Rate random walk K (unit/s/√Hz), >= 0: a bias drift not driven by T.
    order : int
        Polynomial order of bias(T) (1-3).
    warmup : (float, float), optional
        The warm-up's amplitude A (unit) and time constant tau (s), when it is fitted too.
    reference_temperature : float
        ``T_ref`` (°C).
    block : float, optional
        Block length (s) (default: as :func:`temperature_model`, the record over 4000).

    Returns
    -------
    TemperatureBound

    Notes
    -----
    The block means ``y = f(theta) + u + e`` with ``u`` a random walk from an unknown level
    and ``e`` white: their first differences are MA(1) with covariance
    ``tridiag(-s2, q + 2 s2, -s2)``, ``q = K² h``, ``s2 = N²/h - K² h/6`` for blocks of
    ``h`` s (the model :func:`temperature_model` weighs by). The information is
    ``J' D' Σ⁻¹ D J``, ``J`` the model's derivatives, ``D`` the differencing: the intercept
    (and the walk's start) carry none. Blocks lose nothing the model's slow terms hold.
    """
    temp = tf.check_array("The temperature", temperature, "°C, one value per sample")
    if temp.ndim != 1:
        raise NoisevarError("The temperature must be one value per sample (1-D).")
    if not (math.isfinite(rate) and rate > 0):
        raise NoisevarError(f"The sample rate must be positive (Hz); got {rate!r}.")
    if not (math.isfinite(white) and white > 0 and math.isfinite(walk) and walk >= 0):
        raise NoisevarError("white (N) must be > 0 and walk (K) >= 0, both finite.")
    if order not in (1, 2, 3):
        raise NoisevarError(f"order must be 1, 2 or 3; got {order!r}.")
    n = temp.size
    length = max(1, n // TARGET_BLOCKS) if block is None else max(1, round(float(block) * rate))
    if n // length < MIN_BLOCKS:
        raise NoisevarError(f"The record has {n // length} blocks: the bound needs {MIN_BLOCKS}.")
    blocks = tf.make_blocks(temp, rate, length, reference_temperature, order)
    jac = [blocks.powers[:, 1:]]
    names = list("bcd"[:order])
    if warmup is not None:
        amp, tau = (float(v) for v in warmup)
        if not (math.isfinite(amp) and math.isfinite(tau) and tau > 0):
            raise NoisevarError("warmup must be (amplitude, time constant > 0 s), finite.")
        step = np.exp([-LOG_TAU_STEP, 0.0, LOG_TAU_STEP]) * tau
        e = blocks.exponential(step)
        jac += [e[1][:, None], amp * (e[2] - e[0])[:, None] / (2.0 * LOG_TAU_STEP)]
        names += ["amplitude", "log_time_constant"]
    h = length / rate
    q, s2 = walk**2 * h, white**2 / h - walk**2 * h / 6.0
    if s2 <= 0:
        raise NoisevarError("The blocks are too long for this N and K (white share <= 0).")
    white_diff = tf.Whitener.make(q, s2, blocks.time.size - 1)
    wj = white_diff(np.column_stack(jac)) / math.sqrt(q + s2)
    info = wj.T @ wj
    try:
        cov = np.linalg.inv(info)
    except np.linalg.LinAlgError as err:
        raise NoisevarError("The profile does not identify the model (singular).") from err
    return TemperatureBound(tuple(names), cov, float(white), float(walk), h)


def model_bound(model: TemperatureModel, temperature: ArrayLike) -> TemperatureBound:
    """The bound at a fitted model's own estimates: an asymptotic interval's width.

    Parameters
    ----------
    model : TemperatureModel
        One axis's fit (its residual N and K, order, warm-up and block length are used).
    temperature : array_like, shape (n,)
        The temperature column the model was fitted on.

    Returns
    -------
    TemperatureBound

    Notes
    -----
    ``temperature_bound`` with ``white = model.residual_white``, ``walk =
    model.residual_walk``, the model's order (at least 1) and warm-up ``(A, tau)``.
    """
    if not isinstance(model, TemperatureModel):
        raise NoisevarError("model_bound needs one axis's TemperatureModel.")
    warm = None if model.warmup is None else (model.warmup.amplitude, model.warmup.time_constant)
    return temperature_bound(
        temperature,
        model.rate,
        white=model.residual_white,
        walk=model.residual_walk,
        order=max(model.order, 1),
        warmup=warm,
        reference_temperature=model.reference_temperature,
        block=model.block,
    )
