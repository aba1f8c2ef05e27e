"""A datasheet's ARW, bias instability and VRW as IEEE-952 terms, and their Allan deviation.

docs/algorithms.md §E9 (compare with the datasheet). A gyro datasheet quotes the angle
random walk (ARW, e.g. °/√h) and the bias instability (°/h); an accelerometer's the
velocity random walk (VRW, e.g. m/s/√h) and the bias instability (µg). Both are turned
into the terms ``N`` (data unit/√Hz) and ``B`` (data unit) of eq. E4.1, in the unit of the
rate data, so that their Allan deviation ``sqrt(N²/τ + (2 ln 2/π) B²)`` overlays the data's.

The spellings a datasheet uses are listed here with the expression ``noisevar.units``
(pint) reads; every conversion is :func:`noisevar.units.factor`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.noise_model.inertial import TERMS

_N, _B = (next(t for t in TERMS if t.symbol == s) for s in ("N", "B"))

#: Rate units of the data: (dimension, the unit as noisevar.units reads it).
DATA_UNITS = {
    "rad/s": ("angular", "rad/s"),
    "deg/s": ("angular", "deg/s"),
    "°/s": ("angular", "deg/s"),
    "dps": ("angular", "deg/s"),
    "m/s^2": ("linear", "m/s**2"),
    "m/s²": ("linear", "m/s**2"),
    "g": ("linear", "g"),
    "mg": ("linear", "mg"),
}
#: Datasheet units of the white-noise density N (1 °/√h = (π/180)/60 rad/s/√Hz).
DENSITY_UNITS = {
    "°/√h": ("angular", "deg/hour**0.5"),
    "°/s/√Hz": ("angular", "deg/s/Hz**0.5"),
    "°/h/√Hz": ("angular", "deg/hour/Hz**0.5"),
    "rad/s/√Hz": ("angular", "rad/s/Hz**0.5"),
    "m/s/√h": ("linear", "m/s/hour**0.5"),
    "m/s²/√Hz": ("linear", "m/s**2/Hz**0.5"),
    "mg/√Hz": ("linear", "mg/Hz**0.5"),
    "µg/√Hz": ("linear", "ug/Hz**0.5"),
}
#: Datasheet units of the bias instability B.
BIAS_UNITS = {
    "°/h": ("angular", "deg/hour"),
    "°/s": ("angular", "deg/s"),
    "rad/s": ("angular", "rad/s"),
    "mg": ("linear", "mg"),
    "µg": ("linear", "ug"),
    "m/s²": ("linear", "m/s**2"),
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
        t = np.asarray(taus, dtype=float)  # the IEEE-952 terms' coefficients (eq. E4.1)
        return np.sqrt(
            _N.coefficient(t) * self.random_walk**2 + _B.coefficient(t) * self.bias_instability**2
        )


def _factor(table: dict, unit: str, dimension: str, what: str, target: str) -> float:
    """One ``unit`` (a key of ``table``) in ``target``, by :func:`noisevar.units.factor`."""
    from noisevar.units import factor

    if unit not in table:
        raise NoisevarError(f"{what}: unit {unit!r} not known; use one of {', '.join(table)}.")
    dim, expression = table[unit]
    if dim != dimension:
        kind = "a gyroscope's" if dimension == "angular" else "an accelerometer's"
        raise NoisevarError(f"{what} in {unit} is not {kind}, as the data's unit says.")
    return factor(expression, target)


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
    dim, data = DATA_UNITS[data_unit]
    (n_value, n_unit), (b_value, b_unit) = random_walk, bias_instability
    if not all(math.isfinite(v) and v >= 0 for v in (n_value, b_value)):
        raise NoisevarError("The datasheet values must be finite and non-negative.")
    name = "ARW" if dim == "angular" else "VRW"
    n = n_value * _factor(DENSITY_UNITS, n_unit, dim, name, f"({data})/Hz**0.5")
    b = b_value * _factor(BIAS_UNITS, b_unit, dim, "Bias instability", data)
    if floor:
        b /= math.sqrt(float(_B.coefficient(np.ones(1))[0]))  # the flat ADEV's 0.664 B
    quoted = f"{name} {n_value:g} {n_unit}, BI {b_value:g} {b_unit}"
    return DatasheetTerms(n, b, data_unit, quoted)
