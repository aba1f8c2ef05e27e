"""The units library's registry (pint), one for the package, and what it reads of a unit's
name: :mod:`noisevar.units` converts with it, :mod:`noisevar.format` asks whether a unit
already has an SI prefix (neither imports the other for it)."""

from __future__ import annotations

from functools import lru_cache
from typing import Any


@lru_cache(maxsize=1)
def registry() -> Any:
    """pint's ``UnitRegistry``, made once (lazily: only when a unit is read)."""
    import pint

    return pint.UnitRegistry()


@lru_cache(maxsize=256)
def has_prefix(text: str) -> bool:
    """Whether the unit ``text`` already carries an SI prefix (``nT``, ``ms``, ``mg``, ``kPa``),
    as pint reads it first (``ft`` is a foot, not a femto-tonne; ``m`` a metre).

    Notes
    -----
    A magnetometer's std of 0.0049 nT was shown "4.924 mnT" (a milli-nanotesla): a prefixed
    unit takes no second prefix (:func:`noisevar.format.eng`).
    """
    try:
        readings = list(registry().parse_unit_name(text.strip()))
    except Exception:  # noqa: BLE001 - pint raises many types for a name it cannot read
        return False
    return bool(readings) and bool(readings[0][0])
