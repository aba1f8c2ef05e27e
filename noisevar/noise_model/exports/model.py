"""The one noise model every consumer's file is written from (docs/algorithms.md §E7).

An :class:`ImuModel` holds, per sensor (gyroscope in rad/s, accelerometer in m/s²), the
continuous-time terms the consumers take: the white-noise density N, the bias random
walk K and the bias instability B, each the largest over the sensor's axes, either the
best fit or the conservative overbound (:mod:`noisevar.noise_model.overbound`).

N and B come from the IEEE-952 fit (:func:`noisevar.inertial_noise`). K comes from the
composite fit (:func:`noisevar.fit_imu_model`, GMWM) when its fits are given: its bias as
one random walk, ``FilterBias.random_walk`` (K itself for a WN+RW model; a Gauss-Markov
bias's equivalent density over the fit's stated horizon otherwise). On allan_variance_ros's
configuration that K is nearer the information bound per axis than the Allan fit's
(``benchmarks/exports.py --parts d``); without composite fits K is the Allan fit's. Each
file's header says which fit gave K.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar import units
from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import DEFAULT_REGIMES, StillStretch
from noisevar.noise_model.gmwm.model import ImuModel as CompositeModel
from noisevar.noise_model.inertial import InertialNoise
from noisevar.noise_model.inertial_resolve import axis_warnings
from noisevar.noise_model.inertial_white import why_below_white
from noisevar.noise_model.kalibr import composite_k, composite_k_note, imu_rate, k_rule
from noisevar.noise_model.overbound import NK, overbound

#: The SI unit each sensor's terms are exported in.
SENSOR_UNITS = {"gyroscope": "rad/s", "accelerometer": "m/s^2"}
#: The two sets a consumer file can hold.
VARIANTS = ("best", "conservative")
#: The set written when none is asked for.
DEFAULT_VARIANT = "best"
#: Where K comes from without composite fits.
K_FROM_ALLAN = "the IEEE-952 fit to the Allan variance (no composite fit given)"
#: What every file does with a K not identified (``kalibr.k_rule``; ``Consumer.merged``).
WITHHELD_SAID = (
    "a file merged into a flight config writes its line commented out (the config keeps "
    "its own value); a complete file (Kalibr, OpenVINS, MATLAB, filterpy, "
    "robot_localization) keeps it, with this line: do not fly it as measured"
)


@dataclass(frozen=True)
class SensorTerms:
    """Continuous-time terms of one sensor (SI units), the largest over its axes.

    Attributes
    ----------
    N : float
        White-noise density (rad/s/√Hz or m/s²/√Hz).
    K : float
        Bias random walk (rad/s²/√Hz or m/s³/√Hz).
    B : float
        Bias instability (rad/s or m/s²); 0 in the conservative set, whose N and K hold it.
    unit : str
        The sensor's rate unit (``rad/s`` or ``m/s^2``).
    factors : dict of str to float
        Conservative set: each term over the best fit; empty for the best fit.
    k_withheld : str
        Why K is not identified at the horizon its bias is modelled over
        (:func:`~noisevar.noise_model.kalibr.k_rule`), empty when it is: a file merged into
        a flight config leaves it out.
    """

    N: float
    K: float
    B: float
    unit: str
    factors: dict[str, float] = field(default_factory=dict)
    k_withheld: str = ""


@dataclass(frozen=True)
class ImuModel:
    """The noise model of an IMU that every consumer's file is written from.

    Attributes
    ----------
    gyro, accel : SensorTerms
    rate : float
        The IMU's sample rate (Hz).
    variant : {"best", "conservative"}
    regimes : {"all", "still"}
    notes : tuple of str
        Conversions done, what the conservative set covers, what a value was raised to.
    gnss : dict of str to float
        Optional GNSS measurement stds: ``"position"`` (m), ``"velocity"`` (m/s).
    verdicts : dict of str to str
        Each column's verdict (the record's answer, :mod:`noisevar.estimators.answer`),
        written in every file's header: the file's values assume what it says.
    k_from : str
        Which fit gave K (:data:`K_FROM_ALLAN` or the composite fit's models and horizon),
        written in every file's header.
    """

    gyro: SensorTerms
    accel: SensorTerms
    rate: float
    variant: str = DEFAULT_VARIANT
    regimes: str = "all"
    notes: tuple[str, ...] = ()
    gnss: Mapping[str, float] = field(default_factory=dict)
    verdicts: Mapping[str, str] = field(default_factory=dict)
    k_from: str = ""

    def sensor(self, name: str) -> SensorTerms:
        """``"gyroscope"`` or ``"accelerometer"``."""
        return {"gyroscope": self.gyro, "accelerometer": self.accel}[name]

    def header(self, consumer: str) -> list[str]:
        """The comment lines every file starts with (without the comment character)."""
        said = {
            "best": "BEST FIT (N and B: the IEEE-952 terms fitted to the Allan variance)",
            "conservative": "CONSERVATIVE (terms raised until the model's Allan curve is at or "
            "above the data's 95 % upper bound at every fitted tau; docs §E7.3)",
        }[self.variant]
        lines = [
            f"{consumer} noise model written by noisevar (docs/algorithms.md §E7)",
            f"values: {said}; default of noisevar: {DEFAULT_VARIANT}",
            f"IMU sample rate {self.rate:g} Hz; fitted on regimes={self.regimes}",
            f"K (bias random walk) from: {self.k_from or K_FROM_ALLAN}",
        ]
        for name, s in (("gyroscope", self.gyro), ("accelerometer", self.accel)):
            if s.factors:
                f = ", ".join(f"{k} x{v:.3g}" for k, v in s.factors.items())
                lines.append(f"{name}: factors over the best fit: {f}")
        for name, s in (("gyroscope", self.gyro), ("accelerometer", self.accel)):
            if s.k_withheld:
                lines.append(f"{name}: K NOT IDENTIFIED: {s.k_withheld}; {WITHHELD_SAID}")
        said = [f"verdict, column {c}: {' '.join(v.split())}" for c, v in self.verdicts.items()]
        return lines + said + [f"note: {n}" for n in self.notes]

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "rate": self.rate,
            "variant": self.variant,
            "regimes": self.regimes,
            "gyroscope": vars(self.gyro) | {"factors": dict(self.gyro.factors)},
            "accelerometer": vars(self.accel) | {"factors": dict(self.accel.factors)},
            "notes": list(self.notes),
            "gnss": dict(self.gnss),
            "verdicts": dict(self.verdicts),
            "k_from": self.k_from or K_FROM_ALLAN,
        }


def _axes(fits: InertialNoise | Sequence[InertialNoise], name: str) -> list[InertialNoise]:
    axes = [fits] if isinstance(fits, InertialNoise) else list(fits)
    if not axes:
        raise NoisevarError(f"no {name} axis given: pass the fit of at least one axis")
    return axes


def _sensor(
    fits: list[InertialNoise],
    name: str,
    variant: str,
    unit: str | None,
    bias: Sequence[CompositeModel] | None = None,
) -> tuple[SensorTerms, list[str]]:
    """One sensor's terms in SI: the largest over the axes, best or overbound; K from the
    composite fits ``bias`` when given (same data and unit as ``fits``)."""
    target = SENSOR_UNITS[name]
    notes = []
    source = unit or fits[0].unit
    if units.parse_unit(source) is None:
        notes.append(f"{name}: no unit declared: the data are taken as {target}")
        source = target
    f = units.factor(source, target)
    if f != 1.0:
        notes.append(f"{name}: converted from {source} to {target} (x{f:.10g}, by pint)")
    k_best = (
        max(a.rate_random_walk for a in fits) if bias is None else composite_k(fits, bias, name)
    )
    if variant == "best":
        n = max(max(a.random_walk, a.white_level) for a in fits)
        k = k_best
        b = max(a.bias_instability for a in fits)
        terms = SensorTerms(n * f, k * f, b * f, target, k_withheld=k_rule(fits, bias))
        return terms, notes + _white_note(fits, name)
    bounds = [overbound(a, free=NK) for a in fits]
    n_best = max(max(a.random_walk, a.white_level) for a in fits)
    # never below the best set (whose N is at least the white level)
    n = max(n_best, *(ob.values["N"] for ob in bounds))
    k = max(k_best, *(ob.values["K"] for ob in bounds))
    factors = {"N": n / n_best if n_best > 0 else 1.0, "K": k / k_best if k_best > 0 else 1.0}
    covers = dict.fromkeys(c for ob in bounds for c in ob.covers)
    b = max(a.bias_instability for a in fits)
    notes.append(
        f"{name}: the conservative N and K cover "
        + "; ".join(covers)
        + f" (best-fit B up to {b:.4g} {fits[0].unit}, before conversion)"
    )
    return SensorTerms(n * f, k * f, 0.0, target, factors, k_rule(fits, bias)), notes


def _white_note(fits: list[InertialNoise], name: str) -> list[str]:
    """Why N was raised to the white level of some axes (docs/algorithms.md §E4)."""
    below = [i for i, a in enumerate(fits) if a.white_level > a.random_walk]
    if not below:
        return []
    why = "; ".join(f"axis {i}: {why_below_white(fits[i].tau0_holders)}" for i in below)
    return [f"{name}: N is at least each axis's white level sigma(tau0) sqrt(tau0) ({why})"]


def composite_fits(
    columns: Sequence[NDArray],
    rates: Sequence[float],
    unit: str = "u",
    regimes: str = DEFAULT_REGIMES,
    stretch: StillStretch | None = None,
) -> list[CompositeModel]:
    """The composite fit (model chosen, :func:`noisevar.fit_imu_model`) of each column, for
    :func:`imu_model`'s ``gyro_bias``/``accel_bias``; columns of one rate and length are
    fitted together.

    Parameters
    ----------
    columns : sequence of ndarray
        Each axis's samples, in the unit of its IEEE-952 fit.
    rates : sequence of float
        Each column's sample rate (Hz).
    unit : str
        The columns' unit (for the parameters' units).
    regimes : {"all", "still"}
        Which of each record's regimes are fitted, as for its IEEE-952 fit (``"still"``:
        each column's longest still stretch, :func:`noisevar.fit_imu_model`).
    stretch : StillStretch, optional
        With ``"still"``: the IMU's stretch (all its axes still) every column is fitted on,
        as its IEEE-952 fits' (:func:`~noisevar.noise_model.inertial_axes.imu_still_stretch`).

    Returns
    -------
    list of noisevar.noise_model.gmwm.ImuModel
        One per column, in order.
    """
    from noisevar.noise_model.gmwm import fit_imu_model

    if len(columns) != len(rates):
        raise NoisevarError(f"{len(columns)} columns for {len(rates)} rates: give one rate each")
    groups: dict[tuple[float, int], list[int]] = {}
    for i, (z, f) in enumerate(zip(columns, rates, strict=True)):
        groups.setdefault((float(f), len(z)), []).append(i)
    out: list[CompositeModel | None] = [None] * len(columns)
    for (rate, _), idx in groups.items():
        stacked = np.column_stack([np.asarray(columns[i], dtype=float) for i in idx])
        fits = fit_imu_model(stacked, rate, unit=unit, regimes=regimes, stretch=stretch)
        for i, fit in zip(idx, fits, strict=True):
            out[i] = fit
    return out  # type: ignore[return-value]


def imu_model(
    gyro: InertialNoise | Sequence[InertialNoise],
    accel: InertialNoise | Sequence[InertialNoise],
    *,
    variant: str = DEFAULT_VARIANT,
    gyro_unit: str | None = None,
    accel_unit: str | None = None,
    gnss: Mapping[str, float] | None = None,
    gyro_bias: Sequence[CompositeModel] | None = None,
    accel_bias: Sequence[CompositeModel] | None = None,
) -> ImuModel:
    """The IMU's noise model from the fits of its gyroscope and accelerometer axes.

    Parameters
    ----------
    gyro, accel : InertialNoise or sequence of them
        Fits of each axis (:func:`noisevar.inertial_noise`).
    variant : {"best", "conservative"}
        The best fit, or the least overbound of N and K (:func:`overbound`).
    gyro_unit, accel_unit : str, optional
        The data's units (default: each fit's ``unit``); converted to rad/s and m/s².
    gnss : mapping, optional
        GNSS measurement stds ``{"position": m, "velocity": m/s}`` for PX4/ArduPilot.
    gyro_bias, accel_bias : sequence of noisevar.noise_model.gmwm.ImuModel, optional
        Composite fits (:func:`noisevar.fit_imu_model`) of the same axes, same data and
        unit, same order: K is then their bias as one random walk
        (``FilterBias.random_walk``), the largest over the axes. The conservative K is
        still raised to the overbound where that is larger.

    Returns
    -------
    ImuModel
    """
    if variant not in VARIANTS:
        raise NoisevarError(f"variant must be one of {', '.join(VARIANTS)}, not {variant!r}")
    g, a = _axes(gyro, "gyroscope"), _axes(accel, "accelerometer")
    rate, notes = imu_rate(g, a)
    sensors = {"gyroscope": g, "accelerometer": a}
    notes = axis_warnings(sensors) + notes
    regimes = {x.regimes for x in g + a}
    if len(regimes) != 1:
        raise NoisevarError("the axes were fitted on different regimes: fit them all alike")
    gs, gn = _sensor(g, "gyroscope", variant, gyro_unit, gyro_bias)
    acs, an = _sensor(a, "accelerometer", variant, accel_unit, accel_bias)
    bias = {n: list(b) for n, b in (("gyroscope", gyro_bias), ("accelerometer", accel_bias)) if b}
    for key, value in (gnss or {}).items():
        if key not in ("position", "velocity") or not value > 0:
            raise NoisevarError(f"gnss takes positive 'position' and 'velocity' stds, not {key!r}")
    notes += gn + an
    # which samples the still fits ran on: one line for an IMU's stretch (all axes still)
    notes += dict.fromkeys(n for x in g + a for n in x.notes if n.startswith("regimes='still'"))
    k_from = composite_k_note(bias) if bias else K_FROM_ALLAN
    if len(bias) == 1:
        k_from += f"; the {'accelerometer' if 'gyroscope' in bias else 'gyroscope'}'s: " + (
            K_FROM_ALLAN
        )
    return ImuModel(
        gs, acs, rate, variant, regimes.pop(), tuple(notes), dict(gnss or {}), k_from=k_from
    )
