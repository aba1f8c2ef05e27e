"""Units of a record, declared once and carried everywhere (docs/algorithms.md §E7).

The one home of every unit conversion and of the continuous/discrete forms of the
inertial noise terms:

- a user's unit string (``"deg/s"``, ``"m/s^2"``, ``"g"``, ``"mg"``, ``"0.00875 deg/s"``
  for raw counts with a scale factor, ``"ns"``, ...) parsed by ``pint`` (imported on
  first use), and UDUNITS' exponents of netCDF files (``"W/m2"``, ``"m s-1"``);
- values scale by the conversion factor, variances by its square;
- the labels of the IEEE-952 terms' units (N in ``u/√Hz``, K in ``u/s/√Hz``, ...);
- white noise of density N seen at rate ``f``: ``σ = N √f``; a bias random walk of
  density K: its step over ``1/f`` has ``σ = K / √f``, and that step divided by the step
  time, ``K √f``, is what a filter that adds ``(dt·σ)²`` per step takes.

In an IMU's context ``g`` is standard gravity (9.80665 m/s²), not the gram, and ``mg``,
``ug``/``µg`` are milli- and micro-g.
A magnetometer's ``gauss`` (``G``, ``mG``; PX4, DataFlash) is 1e-4 T, so it converts to
the tesla of ROS's ``sensor_msgs/MagneticField``.
A temperature unit (``degC``, ``degF``, as logs declare them) is a temperature difference:
noise and its variance have no offset, so ``degC`` to ``degF`` is the factor 1.8 (the
values converted have no offset either).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.format import NO_UNIT, unit_text

#: Unit strings a user may give, for error messages and help texts.
EXAMPLES = ("rad/s", "deg/s", "m/s^2", "g", "mg", "m", "ns", "0.00875 deg/s (counts x scale)")
#: What an undeclared unit is called (no conversion possible).
UNKNOWN = NO_UNIT
#: IMU spellings pint reads otherwise (g: gram), rewritten before parsing.
_ALIASES = (
    # UDUNITS' exponents (netCDF/CF files, HDF5 attributes: "W/m2", "m s-1"): a unit's
    # letters followed by an integer; a number's own exponent (1e-6) is left alone
    (re.compile(r"(?<![\w.])([A-Za-zµΩ]+)([-+]?\d+)(?![\w.^])"), r"\1^\2"),
    (re.compile(r"(?<![\w.])(?:µ|u)g(?![\w^])"), "(1e-6 * standard_gravity)"),
    (re.compile(r"(?<![\w.])mg(?![\w^])"), "(1e-3 * standard_gravity)"),
    (re.compile(r"(?<![\w.])g(?![\w^])"), "standard_gravity"),
    (re.compile(r"(?<![\w.])counts?(?![\w^])"), "count"),
    # gauss as SI's 1e-4 T (pint's gauss is the Gaussian system's: not convertible to T)
    (re.compile(r"(?<![\w.])(?:milli|m)(?:gauss|G)(?![\w^])"), "(1e-7 * tesla)"),
    (re.compile(r"(?<![\w.])(?:micro|u|µ)(?:gauss|G)(?![\w^])"), "(1e-10 * tesla)"),
    (re.compile(r"(?<![\w.])(?:gauss|G)(?![\w^])"), "(1e-4 * tesla)"),
    # a temperature's noise is a difference: degC and degF are their degrees (no offset)
    # ("deg C", as climate files write it, was degree x coulomb)
    (re.compile(r"(?<![\w.])(?:deg ?C|celsius|degree_Celsius|°C)(?![\w^])"), "delta_degC"),
    (re.compile(r"(?<![\w.])(?:deg ?F|fahrenheit|degree_Fahrenheit|°F)(?![\w^])"), "delta_degF"),
    (re.compile(r"√"), "sqrt"),
)


@lru_cache(maxsize=1)
def _registry() -> Any:
    import pint  # lazily: the units library is needed only when a unit is converted

    return pint.UnitRegistry()


@dataclass(frozen=True)
class Unit:
    """A parsed unit: the user's text, its scale to the SI unit and that unit's name.

    Attributes
    ----------
    text : str
        As the user wrote it (``"deg/s"``).
    scale : float
        One of these in SI base units (``deg/s``: ``π/180``).
    si : str
        The SI unit of the same dimension (``"rad / second"``, pint's spelling).
    """

    text: str
    scale: float
    si: str

    @property
    def label(self) -> str:
        """The unit as written (for tables and file comments)."""
        return self.text


def parse_unit(text: str | None) -> Unit | None:
    """The unit named by ``text``; None for no unit (empty, None or ``"u"``).

    Parameters
    ----------
    text : str or None
        A unit (``"deg/s"``), optionally with a scale factor for raw counts
        (``"0.00875 deg/s"``: one count is 0.00875 deg/s).

    Returns
    -------
    Unit or None

    Raises
    ------
    NoisevarError
        Naming the unit and listing examples, when pint cannot read it.
    """
    if text is None or not str(text).strip() or str(text).strip() == UNKNOWN:
        return None
    raw = str(text).strip()
    return _parse(raw)


@lru_cache(maxsize=256)
def _parse(raw: str) -> Unit:
    expr = raw
    for pattern, repl in _ALIASES:
        expr = pattern.sub(repl, expr)
    ureg = _registry()
    try:
        q = ureg.Quantity(1.0) * ureg.parse_expression(expr.replace("^", "**"))
        base = q.to_base_units()
    except Exception as exc:  # noqa: BLE001 - pint raises many types for a bad unit
        raise NoisevarError(
            f"unknown unit {raw!r} ({type(exc).__name__}); examples: {', '.join(EXAMPLES)}"
        ) from None
    scale = float(base.magnitude)
    if not (math.isfinite(scale) and scale > 0):
        raise NoisevarError(
            f"unit {raw!r} has a non-positive scale; examples: {', '.join(EXAMPLES)}"
        )
    return Unit(raw, scale, str(base.units))


#: The SI unit (pint's spelling) of each IMU sensor's measurement.
SENSOR_SI = {"gyro": "radian / second", "accel": "meter / second ** 2"}


def sensor_of(text: str | None) -> str | None:
    """``"gyro"`` for an angular rate unit (rad/s, deg/s, rpm), ``"accel"`` for an
    acceleration (m/s^2, g, mg), else None (no unit, an unknown one, or another kind)."""
    try:
        unit = parse_unit(text)
    except NoisevarError:
        return None
    return next((k for k, si in SENSOR_SI.items() if unit is not None and unit.si == si), None)


def sensor_columns(
    declared: Mapping[str, str | None], data: Mapping[str, ArrayLike] | None = None
) -> tuple[list[str], list[str]]:
    """The columns whose declared unit is an angular rate, and those in an acceleration
    (:func:`sensor_of`), each in the columns' order: a ROS Imu message's
    ``angular_velocity.*`` and ``linear_acceleration.*``, EuRoC's ``[rad s^-1]`` and
    ``[m s^-2]``. With the columns' ``data``, a column that is the Euclidean norm of the
    others of its kind (phyphox's ``Absolute acceleration``: :func:`norm_columns`) is left
    out: it is no axis."""
    kinds = {c: sensor_of(u) for c, u in declared.items()}
    gyro = [c for c, k in kinds.items() if k == "gyro"]
    accel = [c for c, k in kinds.items() if k == "accel"]
    if data is not None:
        gyro, accel = ([c for c in g if c not in norm_columns(data, g)] for g in (gyro, accel))
    return gyro, accel


#: A column within this relative error of the norm of others, on every row, is their norm
#: (phyphox writes 9 significant digits: its norm column agrees to about 1e-8).
NORM_RTOL = 1e-6


def norm_columns(data: Mapping[str, ArrayLike], group: list[str]) -> list[str]:
    """The columns of ``group`` equal, row by row, to the Euclidean norm of the others.

    Parameters
    ----------
    data : mapping of str to array
        The columns' samples.
    group : list of str
        Columns of one kind (one sensor's axes and, maybe, their magnitude).

    Returns
    -------
    list of str
        Each column whose finite samples are within :data:`NORM_RTOL` of
        ``sqrt(sum(others**2))`` (at least two others, of the same length; empty when none
        is).
    """
    found: list[str] = []
    cols = {c: np.asarray(data[c], dtype=float) for c in group}
    if len(group) < 3 or len({z.shape for z in cols.values()}) != 1:
        return found  # (columns of several topics: no row-by-row norm)
    for c in group:
        others = np.stack([cols[o] for o in group if o != c and o not in found])
        norm = np.sqrt(np.sum(others**2, axis=0))
        z = cols[c]
        ok = np.isfinite(z) & np.isfinite(norm)
        if ok.sum() >= 2 and np.all(np.abs(z[ok] - norm[ok]) <= NORM_RTOL * norm[ok] + 1e-300):
            found.append(c)
    return found


def declared_unit(text: str | None) -> str | None:
    """A unit a file declares (a log's message definition, a header's ``[unit]``), if
    :func:`parse_unit` reads it; else None (the file's word is not the user's)."""
    try:
        return text if parse_unit(text) is not None else None
    except NoisevarError:
        return None


#: A unit pint does not read is shown as written up to this many characters (a longer
#: one, or one with control characters, is no label: ``u``).
LABEL_CHARS = 20


def unit_label(text: str | None) -> str | None:
    """The unit a file declares, as its results are labelled: as written, whether pint
    reads it (:func:`declared_unit`) or not (LAS's ``GAPI``: shown, never converted);
    None for none, or a text no label (not printable, or one pint does not read over
    :data:`LABEL_CHARS` characters)."""
    said = str(text or "").strip()
    if said in ("", UNKNOWN) or not said.isprintable():
        return None
    return said if len(said) <= LABEL_CHARS or declared_unit(said) is not None else None


def factor(source: str | None, target: str | None) -> float:
    """The factor that converts values in ``source`` to ``target`` (1 when either is unset).

    Raises
    ------
    NoisevarError
        When the two units have different dimensions (``deg/s`` to ``m/s^2``).
    """
    a, b = parse_unit(source), parse_unit(target)
    if a is None or b is None or a.text == b.text:
        return 1.0
    if a.si != b.si:
        raise NoisevarError(
            f"cannot convert {a.text!r} ({a.si}) to {b.text!r} ({b.si}): different dimensions"
        )
    return a.scale / b.scale


def convert(values: ArrayLike, source: str | None, target: str | None) -> NDArray:
    """``values`` in ``source`` expressed in ``target``."""
    return np.asarray(values, dtype=float) * factor(source, target)


def convert_variance(variance: ArrayLike, source: str | None, target: str | None) -> NDArray:
    """A variance in ``source²`` expressed in ``target²`` (the factor squared)."""
    return np.asarray(variance, dtype=float) * factor(source, target) ** 2


def in_data_unit(text: str, unit: str | None) -> str:
    """A unit of a filter's q or r written for unitless data (``u²/s^3``) in the data's
    unit (``nT²/s^3``); unchanged without one."""
    return text.replace("u²", variance_label(unit)) if unit and unit != UNKNOWN else text


def variance_label(unit: str | None) -> str:
    """The unit of a variance: ``(deg/s)²`` (``u²`` without a unit)."""
    u = unit_text(unit or UNKNOWN)
    return f"({u})²" if "/" in u or " " in u else f"{u}²"


#: The IEEE-952 terms' units as templates on the rate unit (docs/algorithms.md §E4).
TERM_UNITS = {
    "Q": "{u}·s",
    "N": "{u}/√Hz",
    "B": "{u}",
    "K": "{u}/s/√Hz",
    "R": "{u}/s",
}


def term_unit(unit: str | None, symbol: str) -> str:
    """The unit of term ``symbol`` (Q, N, B, K, R) of rate data in ``unit``.

    ``K`` of ``rad/s`` is ``rad/s²/√Hz``, of ``m/s^2`` ``m/s³/√Hz`` (a rate per second
    folded into the unit's own ``/s``); any other unit keeps the template.
    """
    u = unit_text(unit or UNKNOWN)
    if symbol not in TERM_UNITS:
        raise NoisevarError(f"no term {symbol!r}; the terms are {', '.join(TERM_UNITS)}")
    if symbol in ("K", "R"):
        folded = _per_second(u)
        if folded is not None:
            return folded + ("/√Hz" if symbol == "K" else "")
    return TERM_UNITS[symbol].format(u=u)


def _per_second(u: str) -> str | None:
    """``u`` divided by a second when ``u`` ends in ``/s`` or ``/s^n`` (else None)."""
    m = re.fullmatch(r"(.*)/s(?:\^(\d)|([²³]))?", u)
    if not m:
        return None
    power = int(m.group(2) or {"²": 2, "³": 3}.get(m.group(3) or "", 1)) + 1
    return f"{m.group(1)}/s{'²³⁴'[power - 2]}" if power <= 4 else None


def sigma_at(density: float, rate: float) -> float:
    """The std of white noise of ``density`` (u/√Hz) per sample at ``rate`` Hz: ``N √f``."""
    return float(density) * math.sqrt(_rate(rate))


def density_from_sigma(sigma: float, rate: float) -> float:
    """The density (u/√Hz) of white noise whose per-sample std at ``rate`` is ``sigma``."""
    return float(sigma) / math.sqrt(_rate(rate))


def walk_step(density: float, rate: float) -> float:
    """The std of a random walk's step over ``1/rate`` s: ``K / √f`` (K in u/s/√Hz)."""
    return float(density) / math.sqrt(_rate(rate))


def walk_rate_sigma(density: float, rate: float) -> float:
    """A random walk's step over ``dt = 1/rate`` divided by ``dt``: ``K √f`` (u/s).

    What a filter that adds ``(dt·σ)²`` to a bias's variance each step takes as ``σ``.
    """
    return float(density) * math.sqrt(_rate(rate))


def _rate(rate: float) -> float:
    if not (math.isfinite(rate) and rate > 0):
        raise NoisevarError(f"the rate must be a positive number of Hz, not {rate}")
    return float(rate)
