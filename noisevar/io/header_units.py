"""The unit a text table's header states for a column, in brackets at the end of its name."""

from __future__ import annotations

import re

#: the unit in the header's last brackets; earlier bracketed words are names, not units
#: (MIDC's ``Global Horiz (tracker) [W/m^2]``)
_HEADER_UNIT = re.compile(  # (a trailing "Run #1": PASCO Capstone's columns of each run)
    r"^(?:[^\[\(]|[\[\(][^\[\]\(\)]*[\]\)])*?[\[\(]\s*([^\[\]\(\)]{1,40}?)\s*[\]\)]"
    r"\s*(?:run\s*#?\s*\d+\s*)?$",
    re.IGNORECASE,
)


#: the astronomers' marks for seconds and minutes of arc
_ARC = {'"': "arcsec", "'": "arcmin"}
#: a level or a quantile in brackets, not a unit: HadCRUT's ``Lower confidence limit (2.5%)``
_NOT_A_UNIT = re.compile(r"^[+-]?\d+(?:\.\d+)?\s*%$|^[+-]?\d*\.\d+$")


def header_unit(column: str) -> str | None:
    """The unit a header names in brackets at its end (``gyro_x [rad/s]``, ``p (Pa)``,
    ``Position (m) Run #1``), or None.

    Parameters
    ----------
    column : str
        A column name.

    Returns
    -------
    str or None
        The text in the brackets, as written (a consumer parses it, e.g. with pint).
    """
    m = _HEADER_UNIT.match(column)
    if m is None or _NOT_A_UNIT.match(m[1]):
        return None
    if m[1][0] in _ARC and m[1][1:2] in ("", "/"):  # the IERS's x(") and xrt("/day)
        return _ARC[m[1][0]] + m[1][1:]
    # an acceleration "in G" is in standard gravities (SensorLog's
    # accelerometerAccelerationX(G)); pint's G is the gauss, a magnetometer's unit
    return "g" if m[1] == "G" and _ACCELERATION.search(column) else m[1]


#: Names of an acceleration column (``acc``, ``gravity``, ``g-force``).
_ACCELERATION = re.compile(r"acc|gravity|g-?force", re.IGNORECASE)
