"""A datasheet's ARW, bias instability and VRW as IEEE-952 terms, and their Allan deviation.

docs/algorithms.md §E9 (compare with the datasheet). A gyro datasheet quotes the angle
random walk (ARW, e.g. °/√h) and the bias instability (°/h); an accelerometer's the
velocity random walk (VRW, e.g. m/s/√h) and the bias instability (µg). Both are turned
into the terms ``N`` (data unit/√Hz) and ``B`` (data unit) of eq. E4.1, in the unit of the
rate data, so that their Allan deviation ``sqrt(N²/τ + (2 ln 2/π) B²)`` overlays the data's.

TODO(units): these conversions cover the datasheet units listed here only; once
``noisevar/units.py`` (pint, helper "exports") is on main, parse the units with it and keep
only the table of datasheet spellings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError

_DEG = math.pi / 180.0
_G = 9.80665  # standard gravity (m/s²)
_FLICKER = 2.0 * math.log(2.0) / math.pi

#: Rate units of the data: (dimension, SI value of one unit: rad/s or m/s²).
DATA_UNITS = {
    "rad/s": ("angular", 1.0),
    "deg/s": ("angular", _DEG),
    "°/s": ("angular", _DEG),
    "dps": ("angular", _DEG),
    "m/s^2": ("linear", 1.0),
    "m/s²": ("linear", 1.0),
    "g": ("linear", _G),
    "mg": ("linear", 1e-3 * _G),
}
#: Datasheet units of the white-noise density N: SI value (rad/s/√Hz or m/s²/√Hz) of one.
#: 1 °/√h = (π/180) rad / √(3600 s) = (π/180)/60 rad/s/√Hz; 1 m/s/√h = 1/60 m/s²/√Hz.
DENSITY_UNITS = {
    "°/√h": ("angular", _DEG / 60.0),
    "°/s/√Hz": ("angular", _DEG),
    "°/h/√Hz": ("angular", _DEG / 3600.0),
    "rad/s/√Hz": ("angular", 1.0),
    "m/s/√h": ("linear", 1.0 / 60.0),
    "m/s²/√Hz": ("linear", 1.0),
    "mg/√Hz": ("linear", 1e-3 * _G),
    "µg/√Hz": ("linear", 1e-6 * _G),
}
#: Datasheet units of the bias instability B: SI value (rad/s or m/s²) of one.
BIAS_UNITS = {
    "°/h": ("angular", _DEG / 3600.0),
    "°/s": ("angular", _DEG),
    "rad/s": ("angular", 1.0),
    "mg": ("linear", 1e-3 * _G),
    "µg": ("linear", 1e-6 * _G),
    "m/s²": ("linear", 1.0),
}


@dataclass(frozen=True)
class DatasheetTerms:
    """A datasheet's white-noise density and bias instability in the data's unit.

    Attributes
    ----------
    random_walk : float
        ``N`` (data unit/√Hz): the ARW or VRW.
    bias_instability : float
        ``B`` (data unit), the IEEE-952 coefficient (the Allan floor is ``0.664 B``).
    unit : str
        The data's unit.
    quoted : str
        What was typed, for the legend.
    """

    random_walk: float
    bias_instability: float
    unit: str
    quoted: str

    def deviation(self, taus: ArrayLike) -> NDArray:
        """The Allan deviation ``sqrt(N²/τ + (2 ln 2/π) B²)`` at ``taus`` (s)."""
        t = np.asarray(taus, dtype=float)
        return np.sqrt(self.random_walk**2 / t + _FLICKER * self.bias_instability**2)


def _factor(table: dict, unit: str, dimension: str, what: str) -> float:
    if unit not in table:
        raise NoisevarError(f"{what}: unit {unit!r} not known; use one of {', '.join(table)}.")
    dim, si = table[unit]
    if dim != dimension:
        kind = "a gyroscope's" if dimension == "angular" else "an accelerometer's"
        raise NoisevarError(f"{what} in {unit} is not {kind}, as the data's unit says.")
    return si


def datasheet_terms(
    random_walk: tuple[float, str],
    bias_instability: tuple[float, str],
    data_unit: str,
    *,
    floor: bool = False,
) -> DatasheetTerms:
    """The datasheet's ARW/VRW and bias instability as ``N`` and ``B`` in ``data_unit``.

    Parameters
    ----------
    random_walk : (float, str)
        The ARW (gyro) or VRW (accelerometer) and its unit (a key of :data:`DENSITY_UNITS`).
    bias_instability : (float, str)
        The bias instability and its unit (a key of :data:`BIAS_UNITS`).
    data_unit : str
        The rate data's unit (a key of :data:`DATA_UNITS`).
    floor : bool
        The datasheet quotes the Allan deviation's floor (``0.664 B``) rather than B.

    Returns
    -------
    DatasheetTerms
    """
    if data_unit not in DATA_UNITS:
        raise NoisevarError(
            f"To compare with a datasheet, give the data's unit as one of {', '.join(DATA_UNITS)}"
            f" (it is {data_unit!r})."
        )
    dim, scale = DATA_UNITS[data_unit]
    (n_value, n_unit), (b_value, b_unit) = random_walk, bias_instability
    if not all(math.isfinite(v) and v >= 0 for v in (n_value, b_value)):
        raise NoisevarError("The datasheet values must be finite and non-negative.")
    name = "ARW" if dim == "angular" else "VRW"
    n = n_value * _factor(DENSITY_UNITS, n_unit, dim, name) / scale
    b = b_value * _factor(BIAS_UNITS, b_unit, dim, "Bias instability") / scale
    if floor:
        b /= math.sqrt(_FLICKER)
    quoted = f"{name} {n_value:g} {n_unit}, BI {b_value:g} {b_unit}"
    return DatasheetTerms(n, b, data_unit, quoted)
