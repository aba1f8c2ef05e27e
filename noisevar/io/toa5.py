"""Campbell Scientific datalogger tables (LoggerNet's TOA5 export): their layout and units.

Line 1 is the file's environment (``TOA5,station,CR1000,...``), line 2 names the columns,
line 3 states their units, line 4 how each was processed (``Smp``, ``Avg``, ``Std``); the data
follow (brightwind's met-mast file; docs/algorithms.md *Reading logs*).
"""

from __future__ import annotations

import re
from collections.abc import Callable

from noisevar.units import declared_unit


def toa5_layout(
    head: list[tuple[int, str]], split: Callable[[str], list[str]]
) -> tuple[list[str], int, list[str]] | None:
    """A Campbell Scientific datalogger's TOA5 table (LoggerNet's export): its column names,
    the last line before its data and its units, when the first line is the file's
    environment (``TOA5,station,CR1000,...``), else None; ``split`` cuts a line into fields.

    Notes
    -----
    Line 2 names the columns, line 3 states their units, line 4 how each was processed
    (``Smp``, ``Avg``, ``Std``); the data follow. Read as a plain CSV, the environment line
    was the header: brightwind's met-mast file was refused for its width.
    """
    cells = [c.strip().strip('"').strip() for c in split(head[0][1])]
    if len(head) < 5 or cells[0].lstrip("\ufeff") != "TOA5":
        return None
    names, units = (split(ln) for _, ln in head[1:3])
    if len(units) != len(names):
        return None
    said = [c.strip().strip('"').strip() for c in units]
    return names, head[3][0], ["" if u in _TOA5_MARKS else u for u in said]


#: TOA5's units row marks the time stamp ``TS`` and the record number ``RN``: no units (pint
#: reads them as tesla-seconds and rankine-newtons)
_TOA5_MARKS = ("TS", "RN")


#: A capital after a small letter in a word (``dB``): a unit's spelling, not a title's case
_MID_CAPITAL = re.compile(r"[a-z][A-Z]")


def stated_unit(word: str) -> str:
    """A units row's word as pint reads it: as written, else in lower case when only that
    reads (a Campbell Scientific logger's ``Metres/Second``, ``Millibars``, ``Volts``).

    Parameters
    ----------
    word : str
        The units row's cell.

    Returns
    -------
    str
        The unit the table states for the column.

    Notes
    -----
    A capital inside a word is the unit's own (``dB/ft``, an attenuation): lower-cased, it
    read as another unit (``db/ft``: decibarns per foot, Totem #9's cement-bond log), so such
    a word is kept as written (said on load when pint does not read it).
    """
    if _MID_CAPITAL.search(word):
        return word
    if declared_unit(word) is None and declared_unit(word.lower()) is not None:
        return word.lower()
    return word
