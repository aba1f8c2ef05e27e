"""The unit a text table's header states for a column, in brackets at the end of its name."""

from __future__ import annotations

import re

from noisevar.io.limits import echo
from noisevar.units import declared_unit

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


def column_units(
    names: list[str], time_col: str | None, stated: dict[str, str], notes: list[str]
) -> dict[str, str]:
    """Each column's unit, from its header's brackets or the units row; a unit pint does not
    read is kept as written but said on load, once (``temp [Celcius]``: read unitless).

    Parameters
    ----------
    names : list of str
        The table's columns.
    time_col : str or None
        The time column (its unit is the time's, not a value's).
    stated : dict
        Column to the units row's word.
    notes : list of str
        The load notes; one is appended when some unit is not understood.

    Returns
    -------
    dict
        Column to its unit as written.

    Notes
    -----
    Misspellings are not guessed: pint is the only reader of units (``noisevar.units``), and a
    guess would put a conversion factor on values nobody declared.
    """
    units = {c: u for c in names if c != time_col and (u := header_unit(c) or stated.get(c))}
    unread = [(c, u) for c, u in units.items() if declared_unit(u) is None]
    if unread:
        said = ", ".join(f"{u!r} (column {echo(c)!r})" for c, u in unread[:3])
        more = f" and {len(unread) - 3} more" if len(unread) > 3 else ""
        notes.append(
            f"unit {said}{more} not understood (pint does not read it): the values are read "
            "as written, labelled with it and never converted; to convert them, give the unit "
            "as pint spells it (CLI: --unit, e.g. degC)"
        )
    return units
