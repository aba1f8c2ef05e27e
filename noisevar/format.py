"""Numbers for people: engineering notation with units, the one formatter of every shown value.

``eng(3.628e-9, "s")`` is ``"3.628 ns"``; ``eng(1.316e-17, "s²")`` is
``"13.16×10⁻¹⁸ s²"`` (no prefix on a squared unit: ``ns²`` reads ambiguously);
``eng(17690.4)`` is ``"17,690"``. Values are never cut: the string is the
whole number at the chosen significant digits.
"""

from __future__ import annotations

import math
from decimal import Decimal
from numbers import Real

#: SI prefixes by power of ten (engineering exponents).
PREFIXES = {
    -24: "y",
    -21: "z",
    -18: "a",
    -15: "f",
    -12: "p",
    -9: "n",
    -6: "µ",
    -3: "m",
    3: "k",
    6: "M",
    9: "G",
    12: "T",
}
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
#: Text shown for a missing or non-finite value.
MISSING = "n/a"


def _finite(value: object) -> float | None:
    if isinstance(value, bool) or not isinstance(value, Real):
        return None
    v = float(value)
    return v if math.isfinite(v) else None


def _plain(v: float, digits: int) -> str:
    """``digits`` significant digits, thousands separated, no exponent."""
    decimals = max(digits - 1 - int(math.floor(math.log10(abs(v)))), 0) if v else 0
    text = f"{v:,.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return text


#: The placeholder of a unit nobody gave (``noisevar.units.UNKNOWN``): no SI prefix on it
#: (``mu`` would read as micro).
NO_UNIT = "u"
#: Powers as a log or pint writes them (``m/s**2``, ``m/s^2``), shown as superscripts.
_POWERS = (("**2", "²"), ("^2", "²"), ("**3", "³"), ("^3", "³"))


def unit_text(unit: str) -> str:
    """A unit as shown: ``m/s**2`` and ``m/s^2`` read ``m/s²``."""
    for raw, shown in _POWERS:
        unit = unit.replace(raw, shown)
    return unit


def _prefixable(unit: str) -> bool:
    return (
        bool(unit)
        and unit != NO_UNIT
        and not any(c in unit for c in "²³^/·*")
        and " " not in unit.strip()
    )


#: Units that take an SI prefix: the SI's own (and g, read as grams or as g-force alike, as
#: accelerometers' µg). A unit with a prefix already (``nT``, ``ms``, ``hPa``) takes no second
#: one, nor one outside the SI (``min``, ``ft``, ``deg``, ``kt``, ``degC``, counts).
SI_PREFIXABLE = frozenset(
    "s m g T Pa V A Hz W N J C F H S K rad sr mol cd lm lx Wb Ω ohm Bq Gy Sv bar L l eV".split()
)


def _takes_prefix(unit: str) -> bool:
    """Whether an SI prefix may go on ``unit`` (:data:`SI_PREFIXABLE`)."""
    return _prefixable(unit) and unit.strip() in SI_PREFIXABLE


def eng(value: object, unit: str = "", digits: int = 4) -> str:
    """A number in engineering notation with its unit.

    Parameters
    ----------
    value : float
        The number (None, NaN or infinity give ``"n/a"``).
    unit : str
        Its unit (``"m"``, ``"s²"``; empty for none).
    digits : int
        Significant digits.

    Returns
    -------
    str
        ``1 <= |value| < 1e6``: plain (``"17,690 s"``); otherwise an SI prefix
        when the unit takes one (``"3.628 ns"``; not ``nT``, which has one), else plain down
        to 1e-3
        (``"0.9951 u²"``, as :func:`eng_range` writes it), else ``"13.16×10⁻¹⁸ s²"``.
    """
    v = _finite(value)
    if v is None:
        return MISSING
    unit = unit_text(unit)
    tail = f" {unit}" if unit else ""
    digits = max(int(digits), 1)
    prefix = _takes_prefix(unit) if not (v == 0 or 1 <= abs(v) < 1e6) else False
    if v == 0 or 1 <= abs(v) < 1e6 or (not prefix and 1e-3 <= abs(v) < 1):
        return _plain(v, digits) + tail
    e3 = 3 * int(math.floor(math.log10(abs(v)) / 3))
    mantissa = float(f"{Decimal(v).scaleb(-e3):.{digits}g}")  # exact: 10**e3 is 0 below 1e-323
    if abs(mantissa) >= 1000:  # rounding carried into the next group: 999.96 -> 1000
        e3, mantissa = e3 + 3, mantissa / 1000
    m_text = _plain(mantissa, digits)
    if prefix and e3 in PREFIXES:
        return f"{m_text} {PREFIXES[e3]}{unit}"
    return f"{m_text}×10{str(e3).translate(_SUPERSCRIPT)}{tail}"


def eng_range(lo: object, hi: object, unit: str = "", digits: int = 4) -> str:
    """An interval ``"lo to hi"`` in engineering notation (``"1.2 ns to 1.4 ns"``).

    A unit that takes no prefix is written once, at the end.
    """
    first = eng(lo, unit if _takes_prefix(unit) else "", digits)
    return f"{first} to {eng(hi, unit, digits)}"


def count(value: object) -> str:
    """A count with thousands separators (``"2,000,000"``)."""
    v = _finite(value)
    return MISSING if v is None else f"{int(round(v)):,}"


def percent(value: object, digits: int = 3, signed: bool = False) -> str:
    """A fraction as a percentage (``0.0123 -> "1.23 %"``)."""
    v = _finite(value)
    if v is None:
        return MISSING
    text = _plain(100 * v, digits) if v else "0"
    return f"{'+' if signed and v > 0 else ''}{text} %"


def squared(unit: str) -> str:
    """The unit of a variance: ``"m" -> "m²"``; empty stays empty."""
    if not unit:
        return ""
    return f"{unit}²" if _prefixable(unit) else f"({unit})²"


#: Below this a p-value is shown as a bound: its digits say nothing more.
P_FLOOR = 1e-4


def pvalue(p: object) -> str:
    """A p-value as ``"p = 0.0312"`` (3 significant digits) or ``"p < 0.0001"``.

    One spelling on every page, figure, note and CLI line: ``2.04e-299`` is
    ``"p < 0.0001"``, never ``"20.4×10⁻³⁰⁰"`` beside ``"2e-299"``.
    """
    v = _finite(p)
    if v is None:
        return f"p {MISSING}"
    return f"p = {_plain(v, 3)}" if v >= P_FLOOR else f"p < {_plain(P_FLOOR, 1)}"


#: Characters a line of a figure's title or legend entry holds on a phone (390 px wide):
#: longer ones are broken at a word boundary.
LINE_CHARS = 36


def wrap_words(text: str, width: int = LINE_CHARS) -> str:
    """``text`` broken with ``<br>`` (Plotly's line break) at word boundaries so that no
    line is longer than ``width`` characters (a longer word keeps its own line).

    Plotly does not wrap titles or legend entries: on a phone a long one runs off the
    figure. Existing ``<br>`` breaks are kept; markup inside a line is counted as text.
    """
    out = []
    for part in str(text).split("<br>"):
        lines: list[str] = []
        for word in part.split(" "):
            if lines and len(lines[-1]) + 1 + len(word) <= width:
                lines[-1] += " " + word
            else:
                lines.append(word)
        out.append("<br>".join(lines))
    return "<br>".join(out)


#: Spans written in a larger unit of time from twice that unit up (seconds under 2 min).
DURATION_UNITS = (("d", 86400.0), ("h", 3600.0), ("min", 60.0))


def duration(seconds: object, digits: int = 4) -> str:
    """A span of time in the unit people read it in: ``"365 d"``, ``"5.25 h"``, ``"90 s"``.

    Parameters
    ----------
    seconds : float
        The span (None, NaN or infinity give ``"n/a"``).
    digits : int
        Significant digits.

    Returns
    -------
    str
        Days, hours or minutes from twice the unit up (:data:`DURATION_UNITS`), else
        :func:`eng` in seconds (``"31.53 Ms"`` read a year of hourly soil moisture).
    """
    v = _finite(seconds)
    if v is None:
        return MISSING
    for unit, size in DURATION_UNITS:
        if abs(v) >= 2.0 * size:
            return eng(v / size, unit, digits)
    return eng(v, "s", digits)
