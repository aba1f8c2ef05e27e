"""IAGA-2002 files (INTERMAGNET's exchange format for geomagnetic observatory data): a
header block of ``|``-ended lines, a date and a time column, the elements in nT (D and I in
minutes of arc), and the format's codes for missing data."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.text import _read_text_table

if TYPE_CHECKING:
    from noisevar.io.table import LoadedTable
    from noisevar.io.time_option import StatedTime

#: The first header line of an IAGA-2002 file (`` Format   IAGA-2002   |``).
IAGA = re.compile(r"\A\ufeff?\s*Format\s+IAGA-2002\b", re.IGNORECASE)
#: The format's codes: 99999 a missing value, 88888 an element not recorded.
CODES = (99999.0, 88888.0)
#: The elements whose values are in minutes of arc (declination, inclination); the others
#: (X, Y, Z, H, E, F, G) are in nT.
_ARC = ("D", "I")
NOTE = (
    "read as IAGA-2002 (a geomagnetic observatory's file): its header block skipped, the "
    "date and time joined, and the format's codes 99999 (missing) and 88888 (not recorded) "
    "read as empty cells"
)


def is_iaga(text: str) -> bool:
    """Whether ``text`` (a file's head) is an IAGA-2002 file."""
    return IAGA.match(text) is not None


def _value(cell: str) -> str:
    """The cell, or an empty one for a code (:data:`CODES`)."""
    try:
        return "" if float(cell) in CODES else cell
    except ValueError:
        return cell


def iaga_csv(text: str, name: str) -> str:
    """The IAGA-2002 file ``text`` as a CSV table: a ``time`` column of ISO date-times, the
    elements, and a row of their units.

    Notes
    -----
    Read as a table, the header block's first line was taken for the header and the file
    was refused blaming a row's field count (geomagpy's example files of the Conrad
    Observatory); read as numbers, 99999 would be a glitch in R. The day-of-year column
    repeats the date and is left out.
    """
    lines = text.splitlines()
    at = next((i for i, ln in enumerate(lines) if ln.split()[:2] == ["DATE", "TIME"]), None)
    if at is None:
        raise NoisevarError(
            f"{echo(name)}: an IAGA-2002 file without its 'DATE TIME DOY ...' column line: "
            "give the file as the observatory wrote it"
        )
    names = lines[at].rstrip().rstrip("|").split()[3:]
    units = ["", *("arcmin" if n.upper().endswith(_ARC) else "nT" for n in names)]
    out = [",".join(["time", *names]), ",".join(units)]
    for ln in lines[at + 1 :]:
        cells = ln.split()
        if len(cells) < 3 or ln.rstrip().endswith("|"):
            continue
        out.append(",".join([f"{cells[0]}T{cells[1]}", *map(_value, cells[3:])]))
    return "\n".join(out) + "\n"


def read_iaga(
    text: str, name: str, told: StatedTime | None = None, series: str | None = None
) -> LoadedTable:
    """An IAGA-2002 file, read as the CSV table it holds (:func:`iaga_csv`); ``told``: the
    time unit stated, ``series``: a label given (refused: the file holds one series)."""
    table = _read_text_table(iaga_csv(text, name), name, told, series)
    table.notes.insert(0, NOTE)
    return table
