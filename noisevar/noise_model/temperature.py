"""Temperature models of rate data: bias(T) with the warm-up, noise(T), bias process noise.

docs/algorithms.md §E9. The bias of each axis is a polynomial in ``T - T_ref`` plus a
power-on exponential, fitted jointly on block means by separable least squares (the
time constant profiled on a grid); the model (order, warm-up or not) is chosen by BIC;
intervals come from a moving-block bootstrap of the residuals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.noise_model import _temperature_fit as tf
from noisevar.noise_model.allan import ONE_SIGMA

#: Reference temperature (°C) of the polynomial and of MATLAB's ``gyroparams``/``accelparams``.
REFERENCE_TEMPERATURE = 25.0
#: Least temperature span (°C, between the block means) a bias(T) fit accepts: below it the
#: slope is set by the temperature sensor's resolution (0.004-0.1 °C on IMUs), not by the data.
MIN_SPAN = 0.5
#: Block means the fit aims for (a block is at least one sample).
TARGET_BLOCKS = 4000
#: Fewest block means a fit accepts.
MIN_BLOCKS = 30
#: Highest polynomial order BIC chooses from (``order=None``).
MAX_ORDER = 3
#: Points of the warm-up time constant's log grid (refined by a parabola in log tau).
TAU_GRID = 80
#: Warm-up time constants searched: from this many blocks to the record over ``TAU_SPAN``.
TAU_MIN_BLOCKS = 3
TAU_SPAN = 4.0
#: Bootstrap replicates behind the intervals.
BOOTSTRAP = 200
#: Temperature bins of the white-noise level.
BINS = 5
_LETTERS = "abcd"


@dataclass(frozen=True)
class Coefficient:
    """One fitted coefficient: value, interval (at the model's ``ci``) and unit."""

    name: str
    value: float
    interval: tuple[float, float]
    unit: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        lo, hi = self.interval
        return {"name": self.name, "value": self.value, "interval": [lo, hi], "unit": self.unit}


@dataclass(frozen=True)
class Warmup:
    """The power-on transient ``A exp(-t / tau)`` (t from the record's first sample).

    ``amplitude`` is the bias at power-on over the settled bias(T) (unit of the data);
    ``time_constant`` in seconds.
    """

    amplitude: float
    amplitude_interval: tuple[float, float]
    time_constant: float
    time_constant_interval: tuple[float, float]
    unit: str

    @property
    def settled_after(self) -> float:
        """Seconds until the transient is 1 % of its amplitude (``tau ln 100``)."""
        return self.time_constant * math.log(100.0)

    def at(self, t: ArrayLike) -> NDArray:
        """The transient at times ``t`` (s)."""
        return self.amplitude * np.exp(-np.asarray(t, dtype=float) / self.time_constant)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "amplitude": self.amplitude,
            "amplitude_interval": list(self.amplitude_interval),
            "time_constant": self.time_constant,
            "time_constant_interval": list(self.time_constant_interval),
            "settled_after": self.settled_after,
            "unit": self.unit,
        }


@dataclass(frozen=True, eq=False)
class NoiseByTemperature:
    """The white level ``sigma(tau0) sqrt(tau0)`` (unit/√Hz) in temperature bins.

    ``edges`` has one more entry than ``level``; ``interval`` is ``(lo, hi)`` arrays;
    ``count`` the first differences behind each bin.
    """

    edges: NDArray
    level: NDArray
    interval: tuple[NDArray, NDArray]
    count: NDArray
    unit: str

    @property
    def centres(self) -> NDArray:
        """Bin centres (°C)."""
        return (self.edges[:-1] + self.edges[1:]) / 2.0

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "edges": self.edges.tolist(),
            "level": self.level.tolist(),
            "interval": [self.interval[0].tolist(), self.interval[1].tolist()],
            "count": self.count.tolist(),
            "unit": self.unit,
        }


@dataclass(frozen=True)
class BiasProcessNoise:
    """A bias random-walk density that covers the temperature drift.

    ``density = max|db/dT| sqrt(r ΔT)`` (unit/√s, i.e. unit/s/√Hz as K) over the
    temperature range ``temperature_range`` (°C) crossed at ``temperature_rate`` (°C/s).

    Notes
    -----
    Crossing ΔT at r takes ``D = ΔT / r``. In a time ``t <= D`` the temperature moves the
    bias by at most ``max|b'| r t``; the random walk's 1σ spread ``density √t`` is at
    least that (equal at ``t = D``). Beyond ``D`` the bias change is at most
    ``max|b'| ΔT = density √D``. So at every horizon the 1σ spread covers the drift, when
    the temperature stays in the range and changes no faster than ``r``. Add it to the
    sensor's own rate random walk K in quadrature; the warm-up is not covered (start the
    filter after it, or give the bias an initial variance of at least its amplitude²).
    """

    density: float
    unit: str
    temperature_range: tuple[float, float]
    temperature_rate: float
    max_slope: float
    per_step_variance: float
    slope_unit: str = "u/°C"

    @property
    def assumption(self) -> str:
        """The stated coverage assumption, one sentence."""
        lo, hi = self.temperature_range
        return (
            f"covers the bias drift at 1σ for any horizon while T stays in [{lo:.3g}, {hi:.3g}] °C "
            f"and changes at most {self.temperature_rate * 60:.3g} °C/min "
            f"(max |db/dT| {self.max_slope:.3g} {self.slope_unit})"
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "density": self.density,
            "unit": self.unit,
            "temperature_range": list(self.temperature_range),
            "temperature_rate": self.temperature_rate,
            "max_slope": self.max_slope,
            "per_step_variance": self.per_step_variance,
            "slope_unit": self.slope_unit,
            "assumption": self.assumption,
        }


@dataclass(frozen=True)
class ModelChoice:
    """One candidate bias model: polynomial order, warm-up or not, its fit and BIC."""

    order: int
    warmup: bool
    parameters: int
    rss: float
    bic: float
    selected: bool

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return dict(self.__dict__)


@dataclass(frozen=True, eq=False)
class TemperatureModel:
    """The temperature model of one axis of rate data.

    Attributes
    ----------
    coefficients : tuple of Coefficient
        ``a`` (bias at the reference temperature), ``b`` (per °C), ``c`` (per °C²),
        ``d`` (per °C³) up to ``order``; with a known input rate also ``scale_factor``
        (fraction at the reference temperature) and ``scale_factor_slope`` (per °C).
    order : int
        Polynomial order of bias(T).
    reference_temperature : float
        ``T_ref`` (°C) of the polynomial.
    warmup : Warmup or None
        The power-on transient, when the data support one.
    noise : NoiseByTemperature
        The white level in temperature bins.
    process_noise : BiasProcessNoise
        A bias random-walk density that covers the temperature drift.
    candidates : tuple of ModelChoice
        The models compared, with their BIC (the selected one flagged).
    time, temperature, data : ndarray
        Block centres (s), block means of T and of the data: what was fitted.
    curve : tuple of ndarray
        ``(T, bias, lo, hi)``: the fitted bias(T) on a grid of the range, with its band.
    rate, block : float
        Sample rate (Hz) and block length (s).
    unit : str
    ci : float
        Confidence level of the intervals.
    n_samples : int
    notes : tuple of str
    residual_white, residual_walk : float
        The residual's white level N (unit/√Hz) and rate random walk K (unit/s/√Hz) that
        the fit's weights assumed. Block means of length h: increments of variance
        ``q = K² h``, and ``s2 = N²/h - K² h / 6`` (a random walk's block means add
        ``K² h / 6`` to the lag-1 covariance of their differences).
    """

    coefficients: tuple[Coefficient, ...]
    order: int
    reference_temperature: float
    warmup: Warmup | None
    noise: NoiseByTemperature
    process_noise: BiasProcessNoise
    candidates: tuple[ModelChoice, ...]
    time: NDArray
    temperature: NDArray
    data: NDArray
    curve: tuple[NDArray, NDArray, NDArray, NDArray]
    rate: float
    block: float
    unit: str
    ci: float
    n_samples: int
    notes: tuple[str, ...] = ()
    residual_white: float = math.nan
    residual_walk: float = math.nan

    def coefficient(self, name: str) -> Coefficient:
        """The coefficient called ``name`` (``"a"``, ``"b"``, ... ``"scale_factor_slope"``)."""
        for c in self.coefficients:
            if c.name == name:
                return c
        names = ", ".join(c.name for c in self.coefficients)
        raise NoisevarError(f"No coefficient {name!r}; this model has {names}.")

    @property
    def polynomial(self) -> NDArray:
        """Coefficients of bias(T) in powers of ``T - T_ref``, lowest first."""
        return np.array([c.value for c in self.coefficients[: self.order + 1]])

    def bias(self, temperature: ArrayLike) -> NDArray:
        """The settled bias at ``temperature`` (°C), without the warm-up."""
        d = np.asarray(temperature, dtype=float) - self.reference_temperature
        return np.polynomial.polynomial.polyval(d, self.polynomial)

    def slope(self, temperature: ArrayLike) -> NDArray:
        """``d bias / dT`` (unit/°C) at ``temperature``."""
        d = np.asarray(temperature, dtype=float) - self.reference_temperature
        return np.polynomial.polynomial.polyval(
            d, np.polynomial.polynomial.polyder(self.polynomial)
        )

    def settled(self) -> NDArray:
        """The block means with the warm-up removed (what bias(T) is drawn over)."""
        if self.warmup is None:
            return self.data
        return self.data - self.warmup.at(self.time)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary (without the block series)."""
        return {
            "coefficients": {c.name: c.to_dict() for c in self.coefficients},
            "order": self.order,
            "reference_temperature": self.reference_temperature,
            "warmup": None if self.warmup is None else self.warmup.to_dict(),
            "noise": self.noise.to_dict(),
            "process_noise": self.process_noise.to_dict(),
            "candidates": [c.to_dict() for c in self.candidates],
            "rate": self.rate,
            "block": self.block,
            "unit": self.unit,
            "ci": self.ci,
            "n_samples": self.n_samples,
            "notes": list(self.notes),
            "residual_white": self.residual_white,
            "residual_walk": self.residual_walk,
        }


@dataclass(frozen=True)
class TemperatureExport:
    """Temperature terms in the form of MATLAB's ``gyroparams``/``accelparams``, one per axis.

    Attributes
    ----------
    temperature_bias : tuple of float
        ``TemperatureBias``: the bias change per °C (data unit/°C), the slope of the
        least-squares line through the fitted bias(T) over the record's temperature range
        (``b`` itself for a first-order fit). MATLAB's model is linear:
        ``bias = ConstantBias + (T - 25 °C) TemperatureBias``.
    constant_bias : tuple of float
        ``ConstantBias``: that line at 25 °C (data unit).
    temperature_scale_factor : tuple of float or None
        ``TemperatureScaleFactor`` (%/°C): ``100 x scale_factor_slope``, or None when no
        known input rate was given (a still record cannot show it).
    unit : str
        The data's unit (convert before writing a MATLAB file: rad/s, m/s²).
    notes : tuple of str
    """

    temperature_bias: tuple[float, ...]
    constant_bias: tuple[float, ...]
    temperature_scale_factor: tuple[float, ...] | None
    unit: str
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """MATLAB's property names to per-axis lists (``TemperatureScaleFactor`` if known)."""
        out: dict[str, Any] = {
            "ConstantBias": list(self.constant_bias),
            "TemperatureBias": list(self.temperature_bias),
        }
        if self.temperature_scale_factor is not None:
            out["TemperatureScaleFactor"] = list(self.temperature_scale_factor)
        return out


def _names_units(order: int, inputs: int, unit: str) -> list[tuple[str, str]]:
    out = [
        (_LETTERS[k], unit + ("" if k == 0 else "/°C" if k == 1 else f"/°C^{k}"))
        for k in range(order + 1)
    ]
    if inputs:
        out += [("scale_factor", "1"), ("scale_factor_slope", "1/°C")]
    return out


def _process_noise(model_slope, blocks: tf.Blocks, opts: tf.Options, unit: str) -> BiasProcessNoise:
    t_range = opts.temperature_range or (
        float(blocks.temperature.min()),
        float(blocks.temperature.max()),
    )
    rate_t = opts.temperature_rate
    if rate_t is None:
        # the 95th percentile of |dT/dt| over windows of 1 % of the record
        w = max(1, blocks.time.size // 100)
        dt = w * blocks.length / blocks.rate
        rate_t = float(
            np.quantile(np.abs(blocks.temperature[w:] - blocks.temperature[:-w]), 0.95) / dt
        )
    slope = float(np.max(np.abs(model_slope(np.linspace(*t_range, 201)))))
    span = t_range[1] - t_range[0]
    density = slope * math.sqrt(rate_t * span)
    return BiasProcessNoise(
        density, f"{unit}/s/√Hz", t_range, rate_t, slope, density**2 / blocks.rate, f"{unit}/°C"
    )


def _one_axis(
    axis: tf.Axis, raw: NDArray, temperature: NDArray, opts: tf.Options, notes: list[str]
):
    axis, fits, scores, best, more = tf.choose(axis, opts.orders, opts.warmups)
    fit = fits[best]
    table = tuple(
        ModelChoice(f.order, f.warmup, f.parameters, f.rss, s, i == best)
        for i, (f, s) in enumerate(zip(fits, scores, strict=True))
    )
    lo, hi, coefs, _ = tf.intervals(axis, fit, opts.bootstrap, opts.ci, opts.seed)
    k = fit.x.shape[1]
    coefficients = tuple(
        Coefficient(name, float(fit.coef[i]), (float(lo[i]), float(hi[i])), u)
        for i, (name, u) in enumerate(_names_units(fit.order, axis.inputs, opts.unit))
    )
    warm = None
    if fit.warmup:
        warm = Warmup(
            float(fit.coef[k]),
            (float(lo[k]), float(hi[k])),
            fit.tau,
            (float(lo[k + 1]), float(hi[k + 1])),
            opts.unit,
        )
    blocks = axis.blocks
    model_block = blocks.length / blocks.rate
    lvl, llo, lhi, count = tf.white_levels(
        raw[:, None], temperature, blocks.rate, tf.bin_edges(temperature, opts.bins), opts.ci
    )
    noise = NoiseByTemperature(
        tf.bin_edges(temperature, opts.bins),
        lvl[:, 0],
        (llo[:, 0], lhi[:, 0]),
        count,
        f"{opts.unit}/√Hz",
    )
    model = TemperatureModel(
        coefficients,
        fit.order,
        opts.reference,
        warm,
        noise,
        _process_noise(lambda t: tf.slope(fit, t, opts.reference), blocks, opts, opts.unit),
        table,
        blocks.time,
        blocks.temperature,
        axis.y,
        tf.curve(blocks, fit, coefs, opts.reference, opts.ci),
        blocks.rate,
        blocks.length / blocks.rate,
        opts.unit,
        opts.ci,
        raw.size,
        tuple(notes + more),
        math.sqrt((axis.white.s2 + axis.white.q / 6.0) * model_block),
        math.sqrt(axis.white.q / model_block),
    )
    return model


def temperature_model(
    z: ArrayLike,
    temperature: ArrayLike,
    rate: float,
    *,
    axis: int = -1,
    unit: str = "u",
    order: int | None = None,
    warmup: bool | None = None,
    reference_temperature: float = REFERENCE_TEMPERATURE,
    input_rate: ArrayLike | None = None,
    block: float | None = None,
    bins: int = BINS,
    temperature_range: tuple[float, float] | None = None,
    temperature_rate: float | None = None,
    ci: float = ONE_SIGMA,
    bootstrap: int = BOOTSTRAP,
    seed: int = 0,
) -> TemperatureModel | tuple[TemperatureModel, ...]:
    """Fit bias(T), the warm-up, noise(T) and a covering bias process noise to rate data.

    Parameters
    ----------
    z : array_like
        Rate samples (gyro rate, specific force) at a uniform rate, power-on at the first
        sample; several axes along the other dimension of a 2-D array.
    temperature : array_like, shape (n,)
        The sensor's temperature (°C) at each sample.
    rate : float
        Sample rate (Hz).
    axis : int
        The time axis of a 2-D ``z``.
    unit : str
        Unit of the rate data.
    order : int, optional
        Polynomial order of bias(T) in ``T - T_ref`` (0-3); default: 1-3 by BIC.
    warmup : bool, optional
        Fit the power-on exponential (default: when BIC prefers it).
    reference_temperature : float
        ``T_ref`` (°C); 25 °C is MATLAB's.
    input_rate : array_like, optional
        The known applied rate (turntable), one per sample (or per sample and axis):
        adds the scale factor ``(s0 + s1 (T - T_ref)) w`` to the model.
    block : float, optional
        Block length (s) of the means fitted (default: the record over 4000).
    bins : int
        Equal-count temperature bins of the white level.
    temperature_range : (float, float), optional
        The range (°C) the process noise must cover (default: the record's).
    temperature_rate : float, optional
        The fastest temperature change (°C/s) it must cover (default: the record's
        95th percentile of |dT/dt| over windows of 1 % of the record).
    ci : float
        Confidence level of the intervals.
    bootstrap : int
        Moving-block bootstrap replicates behind the intervals.
    seed : int
        Seed of the bootstrap.

    Returns
    -------
    TemperatureModel, or a tuple of them (one per axis) for a 2-D ``z``

    Notes
    -----
    docs/algorithms.md §E9. Model of each axis, on block means (t from the first sample):
    ``y = sum_k c_k (T - T_ref)^k + A exp(-t/tau) [+ (s0 + s1 (T - T_ref)) w] + noise``.
    The warm-up is fitted jointly with bias(T) because T changes during the warm-up too:
    linear least squares for fixed tau, tau profiled on a log grid and refined by a
    parabola. BIC counts the likelihood on ``n (1 - rho)/(1 + rho)`` blocks (rho: the
    largest model's residual lag-1 correlation). Intervals: moving-block bootstrap of the
    residuals. A bias random walk that is not driven by T is confounded with a slow
    monotone ramp: a record that goes up and down in T separates them.
    """
    opts = tf.options(
        order,
        warmup,
        reference_temperature,
        ci,
        bootstrap,
        seed,
        unit,
        bins,
        temperature_range,
        temperature_rate,
        MAX_ORDER,
    )
    single, cols, temp = tf.prepare(z, temperature, rate, axis)
    n = cols.shape[1]
    length = max(1, n // TARGET_BLOCKS) if block is None else max(1, round(float(block) * rate))
    if n // length < MIN_BLOCKS:
        raise NoisevarError(
            f"The record has {n // length} blocks of {length} samples: the temperature fit needs "
            f"at least {MIN_BLOCKS} (a longer record, or a shorter block)."
        )
    blocks = tf.make_blocks(temp, rate, length, opts.reference, max(opts.orders))
    span = float(np.ptp(blocks.temperature))
    if span < MIN_SPAN and max(opts.orders) > 0:
        raise NoisevarError(
            f"The temperature varies by only {span:.3g} °C over the record: a bias(T) fit needs "
            f"at least {MIN_SPAN} °C (record through a temperature ramp or chamber cycle)."
        )
    grid = tf.tau_grid(blocks, TAU_MIN_BLOCKS, TAU_SPAN, TAU_GRID)
    exps = blocks.exponential(grid)
    w = tf.inputs(input_rate, cols.shape)
    notes = [f"blocks of {length} samples ({length / rate:.4g} s); T_ref {opts.reference:g} °C"]
    models = []
    for i, col in enumerate(cols):
        linear = blocks.powers
        if w is not None:
            d = temp - opts.reference
            extra = [tf.block_means(w[i], length), tf.block_means(d * w[i], length)]
            linear = np.column_stack([linear, *extra])
        ax = tf.Axis.make(
            tf.block_means(col, length), linear, 0 if w is None else 2, blocks, grid, exps
        )
        models.append(_one_axis(ax, col, temp, opts, notes))
    return models[0] if single else tuple(models)


def matlab_temperature_params(
    models: TemperatureModel | tuple[TemperatureModel, ...],
) -> TemperatureExport:
    """``TemperatureBias``, ``ConstantBias`` (and ``TemperatureScaleFactor``) per axis.

    Parameters
    ----------
    models : TemperatureModel or tuple of them
        One per axis (x, y, z), all of the same unit.

    Returns
    -------
    TemperatureExport

    Notes
    -----
    MATLAB's ``gyroparams``/``accelparams`` model the temperature linearly about 25 °C:
    the slope and the 25 °C value of the least-squares line through each fitted bias(T)
    over its record's range (exact for a first-order fit).
    """
    ms = (models,) if isinstance(models, TemperatureModel) else tuple(models)
    if not ms or len({m.unit for m in ms}) != 1:
        raise NoisevarError("matlab_temperature_params needs one or more models of one unit.")
    slopes, consts, scale, notes = [], [], [], []
    for i, m in enumerate(ms):
        t = m.curve[0]
        line = np.polynomial.polynomial.polyfit(t - REFERENCE_TEMPERATURE, m.bias(t), 1)
        consts.append(float(line[0]))
        slopes.append(float(line[1]))
        if m.order > 1:
            notes.append(
                f"axis {i}: order {m.order} fit, linearised over {t[0]:.3g}-{t[-1]:.3g} °C"
            )
        names = {c.name for c in m.coefficients}
        scale.append(
            100.0 * m.coefficient("scale_factor_slope").value
            if "scale_factor_slope" in names
            else None
        )
    known = None if any(s is None for s in scale) else tuple(scale)
    if known is None:
        notes.append("TemperatureScaleFactor needs a known input rate (turntable): not given")
    return TemperatureExport(tuple(slopes), tuple(consts), known, ms[0].unit, tuple(notes))
