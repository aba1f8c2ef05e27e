"""CSV / TSV / whitespace-separated text tables (decimal point or decimal comma)."""

from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar._arrays import EXACT_INT
from noisevar.errors import NoisevarError
from noisevar.io.delimiter import sniff_delimiter
from noisevar.io.header_units import column_units, header_unit
from noisevar.io.headerless import first_column_times, first_line_is_row
from noisevar.io.number_labels import few_values, own_clock
from noisevar.io.opensignals import opensignals_names
from noisevar.io.quirks import (
    code_note,
    leading_header,
    missing_mark,
    repeated_rows,
    rows_continue,
    wrap_note,
)
from noisevar.io.refusal_hints import (
    CLEAN_HINT,
    kinds_hint,
    numbers_for_names,
    preamble_hint,
    report_hint,
    short_header,
    width_hint,
)
from noisevar.io.stacked import one_series, stack_clock
from noisevar.io.table import (
    _NA_TOKENS,
    UNIFORM_TOLERANCE,
    LoadedTable,
    _period_from_time,
    echo,
    is_time_column,
    pick_time_column,
    time_in_seconds,
)
from noisevar.io.text_times import (
    clock_beside,
    digit_date_format,
    digit_time_column,
    is_date_name,
    is_digit_date_name,
    parse_time_strings,
)
from noisevar.io.toa5 import stated_unit, toa5_layout

if TYPE_CHECKING:
    import pandas as pd

    from noisevar.io.time_option import StatedTime

#: A file of one line, or of lines of words: what it lacks and what to give
_NO_ROWS = "has a header but no data rows: give a table with one row of numbers per sample"
#: Most columns a text table may have (a wider header is refused before parsing).
MAX_COLUMNS = 1000
_THOUSANDS = re.compile(r"^[+-]?\d{1,3}(,\d{3})+(\.\d*)?$")
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+([eE][+-]?\d+)?$")
_EURO_THOUSANDS = re.compile(r"^[+-]?\d{1,3}(\.\d{3})+(,\d*)?$")


@dataclass(frozen=True)
class TextSource:
    """A text table on disk: its path, the decoded head and the encoding (streamed, not read)."""

    path: Path
    head: str
    encoding: str

    def text(self) -> str:
        """The whole file (only for error messages that need a line number)."""
        return self.path.read_bytes().decode(self.encoding, errors="replace")


@dataclass(frozen=True)
class _Format:
    """How the table is written: delimiter, decimal mark, thousands separator."""

    delim: str | None
    decimal: str = "."
    thousands: str | None = None


def _split(line: str, delim: str | None) -> list[str]:
    if delim is None:
        return line.split()
    return next(csv.reader([line], delimiter=delim))


def _cells(rows: list[str], delim: str | None) -> list[str]:
    return [c.strip().strip('"') for ln in rows for c in _split(ln, delim) if c.strip()]


def _sniff_format(lines: list[str]) -> _Format:
    """Delimiter and number format from the first lines (header included)."""
    data = lines[1:] or lines
    whole = [ln.strip().strip('"') for ln in data]
    one_name = len(lines) > 1 and "," not in lines[0] and not _is_number(lines[0])
    if one_name and all(_THOUSANDS.match(c) for c in whole):
        return _Format("\t" if any("\t" in ln for ln in lines) else None, ".", ",")
    delim = sniff_delimiter(lines)
    if delim == ",":
        return _Format(delim)
    cells = _cells(data, delim)
    euro = any(_EURO_THOUSANDS.match(c) and "," in c for c in cells)
    if (euro or any(_DECIMAL_COMMA.match(c) for c in cells)) and not any(
        re.match(r"^[+-]?\d*\.\d+([eE][+-]?\d+)?$", c) for c in cells
    ):
        return _Format(delim, ",", "." if euro else None)
    if any(_THOUSANDS.match(c) for c in cells):
        return _Format(delim, ".", ",")
    return _Format(delim)


def _is_number(cell: str, fmt: _Format | None = None) -> bool:
    s = cell.strip()
    if s == "":
        return True
    if fmt is not None:
        if fmt.thousands:
            s = s.replace(fmt.thousands, "")
        if fmt.decimal != ".":
            s = s.replace(fmt.decimal, ".")
    try:
        float(s)
    except ValueError:
        return False
    return True


def _unique_names(raw: list[str]) -> list[str]:
    """Column names, empty ones filled and repeats suffixed ``_2, _3``; linear time."""
    names: list[str] = []
    taken: set[str] = set()
    next_k: dict[str, int] = {}
    for i, r in enumerate(raw):
        base = r.strip().strip('"').strip() or f"col{i}"
        candidate, k = base, next_k.get(base, 1)
        while candidate in taken:
            k += 1
            candidate = f"{base}_{k}"
        next_k[base] = k
        taken.add(candidate)
        names.append(candidate)
    return names


def _meaningful(line: str) -> bool:
    s = line.strip()
    return bool(s) and not s.startswith("#")


def _data_line_number(text: str, header_line: int, row: int) -> int:
    """File line number (1-based) of data row ``row`` (0-based) after line ``header_line``."""
    count = -1
    for i, ln in enumerate(text.splitlines(), start=1):
        if i <= header_line or not _meaningful(ln):
            continue
        count += 1
        if count == row:
            return i
    return header_line + row + 1


def _head_lines(head: str, name: str, complete: bool) -> list[tuple[int, str]]:
    """The first meaningful lines (number, text); refuses a first line too long to sniff."""
    lines = head[:1_000_000].splitlines()
    if not complete and len(lines) <= 1 and len(head) >= 1_000_000:
        raise NoisevarError(
            f"{echo(name)}: the first line is longer than 1 MB: this is not a table of "
            f"measurements (at most {MAX_COLUMNS} columns are read)"
        )
    if not complete and lines:
        lines = lines[:-1]  # the last line of a head may be cut
    out = [(i, ln) for i, ln in enumerate(lines, start=1) if _meaningful(ln)]
    if not out:
        raise NoisevarError(f"{echo(name)} is empty: no data rows (only blank or # comment lines)")
    return out[:60]


def _check_width(
    name: str, fields: list[str], head: list[tuple[int, str]], fmt: _Format, text: str = ""
) -> None:
    """Refuse too many columns, and rows whose field count differs from the first row's
    (``text``: the file's head, for :func:`report_hint`)."""
    if len(fields) > MAX_COLUMNS:
        raise NoisevarError(
            f"{echo(name)} has {len(fields):,} columns, over the limit of {MAX_COLUMNS}: "
            "give a table of at most that many signals"
        )
    split = lambda ln: _split(ln, fmt.delim)  # noqa: E731
    end = fmt.delim or " "  # a delimiter ending every row: an empty last field, no column
    widths = [len(split(ln.rstrip().removesuffix(end))) if fmt.thousands != "," or fmt.delim
              else 1 for _, ln in head[1:]]  # fmt: skip
    for (line_no, _), n in zip(head[1:], widths, strict=True):
        if n > len(fields):  # fewer fields are empty cells (NaN)
            hint = (
                " (numbers with unquoted thousands separators, like 4,867.69, split a "
                "comma-separated row: remove the separators or quote the numbers)"
                if fmt.delim == ","
                else ""
            )
            hint = width_hint(head, line_no, n, hint, lambda at: report_hint(text, split, at))
            if short_header(fields, widths):
                raise NoisevarError(
                    f"{echo(name)}: the header (line {head[0][0]}) names {len(fields)} columns "
                    f"but every row under it has {n} fields: name every column in the "
                    f"header{hint}"
                )
            raise NoisevarError(
                f"{echo(name)}: line {line_no} has {n} fields but line {head[0][0]} has "
                f"{len(fields)}: every row must have the same columns{hint}"
            )


def table_layout(
    text: str, name: str, complete: bool
) -> tuple[_Format, list[str], int, list[str] | None]:
    """How a text table is written, its column names, the last line before its data, and
    the units a row under the header states (None: no such row).

    ``text`` is the whole file (``complete``) or its head.
    """
    head = _head_lines(text, name, complete)
    fmt = _sniff_format([ln for _, ln in head])
    if _title_line(head, fmt):
        head = head[1:]
    if toa5 := toa5_layout(head, lambda ln: _split(ln, fmt.delim)):
        return fmt, _unique_names(toa5[0]), *toa5[1:]
    first = _split(head[0][1], fmt.delim) if fmt.thousands != "," or fmt.delim else [head[0][1]]
    if fmt.delim is None and len(first) > 1 and not all(_is_number(c, fmt) for c in first):
        # a one-column file whose name has spaces ("clock [ns]"): every data row one field
        if len(head) > 1 and all(len(_split(ln, None)) == 1 for _, ln in head[1:]):
            first = [head[0][1].strip()]
    _check_width(name, first, head, fmt, text)
    split = [first, *(_split(ln, fmt.delim) for _, ln in head[1:])]
    if not all(_is_number(c, fmt) for c in first) and not first_line_is_row(
        split, lambda c: _is_number(c, fmt)
    ):
        if len(head) < 2:
            raise NoisevarError(f"{echo(name)} {_NO_ROWS}")
        units = _units_row(head, len(first), fmt)
        line = head[1][0] if units is not None else head[0][0]
        return fmt, _unique_names(first), line, units
    names = _commented_header(text, head[0][0], len(first), fmt)
    if names is None and (found := opensignals_names(text, len(first))) is not None:
        names = _unique_names(found)  # an empty name past the header's: col<i>
    return fmt, names or [f"col{i}" for i in range(len(first))], head[0][0] - 1, None


def _title_line(head: list[tuple[int, str]], fmt: _Format) -> bool:
    """Whether the first line is a title above the header (``Southern Oscillation Index
    (SOI),,`` then ``Date,Year,Value``): one named cell, the others empty, over a row of as
    many names, none empty or a number, over a row of numbers.

    Notes
    -----
    Read as the header, the title named the first column and the real header became a units
    row: the index's values were ``col2`` and the channel named after the title was the dates.
    """
    if len(head) < 3 or fmt.delim is None:
        return False
    title, names, below = (_split(ln, fmt.delim) for _, ln in head[:3])
    cells = [c.strip().strip('"').strip() for c in title]
    named = [c.strip().strip('"').strip() for c in names]
    return (
        len(cells) == len(named) > 1
        and bool(cells[0]) and not any(cells[1:]) and not _is_number(cells[0], fmt)
        and all(c and not _is_number(c, fmt) for c in named)
        and any(_is_number(c.strip().strip('"'), fmt) for c in below)
    )  # fmt: skip


def _units_row(head: list[tuple[int, str]], width: int, fmt: _Format) -> list[str] | None:
    """The row of units under a header (``s,m/s^2,m/s^2``: data loggers and LabVIEW write
    one), or None: a row of as many fields, none a number, above a row that holds numbers."""
    if len(head) < 3:
        return None
    cells = [c.strip().strip('"').strip() for c in _split(head[1][1], fmt.delim)]
    below = _split(head[2][1], fmt.delim)
    if len(cells) != width or any(_is_number(c, fmt) for c in cells if c):
        return None
    if not any(_is_number(c.strip().strip('"'), fmt) for c in below):
        return None
    return [c.strip("[]() ") for c in cells]


def _commented_header(text: str, data_line: int, width: int, fmt: _Format) -> list[str] | None:
    """The column names of a header written as a comment just above the data, or None.

    EuRoC, TUM-VI and Kalibr IMU files start ``#timestamp [ns],w_RS_S_x [rad s^-1],...``:
    the last ``#`` line before the first data row names the columns when it splits into
    as many fields as that row, none a number, and one of them is a time column or states
    a unit in brackets (a remark such as ``# sensor A, 2024`` is not a header). In a table
    split on whitespace, names that hold a space (the IERS's EOP C04: ``x Er``) are told
    apart by two spaces or more between them.
    """
    lines = text.splitlines()[: data_line - 1]
    while lines and not lines[-1].strip():
        lines.pop()
    if not lines or not lines[-1].lstrip().startswith("#"):
        return None
    fields = [f.strip() for f in _split(lines[-1].lstrip()[1:], fmt.delim)]
    if fmt.delim is None and len(fields) != width:  # names with a space, two between them
        fields = re.split(r"\s{2,}", lines[-1].lstrip()[1:].strip())
    if len(fields) != width or any(_is_number(c, fmt) for c in fields):
        return None
    # names, not a remark that happens to hold the delimiter: a time column or a unit
    if not any(is_time_column(c) or header_unit(c) for c in fields):
        return None
    return _unique_names(fields)


def _holds_dates(text: str, fmt: _Format, header_line: int, names: list[str], idx: int) -> bool:
    """Whether column ``idx``'s first data cell is a date-time (text, not a number), or a
    date written as digits in a date column (``AAAAMMJJ``: ``20250101``)."""
    for line in text.splitlines()[header_line : header_line + 60]:
        if _meaningful(line):
            cells = _split(line, fmt.delim)
            cell = cells[idx].strip().strip('"') if idx < len(cells) else ""
            if digit_date_format(names[idx], cell) is not None:
                return True
            return not _is_number(cell, fmt) and parse_time_strings([cell]) is not None
    return False


def read_text_table(text: str, name: str) -> LoadedTable:
    """A whole text table held in memory (a workbook's sheet written as CSV), read as the
    loader reads a CSV file: header, units, time column, missing cells, notes."""
    return _read_text_table(text, name)


def _read_text_table(
    src: str | TextSource, name: str, told: StatedTime | None = None, series: str | None = None
) -> LoadedTable:
    text = src if isinstance(src, str) else src.head
    fmt, names, header_line, unit_row = table_layout(text, name, isinstance(src, str))
    time_idx = pick_time_column(names)
    if time_idx is None:  # a date column (else the first: pandas' index) holding date-times
        date_idx = next((i for i, c in enumerate(names) if is_date_name(c)
                         or is_digit_date_name(c)), 0)  # fmt: skip
        time_idx = date_idx if _holds_dates(text, fmt, header_line, names, date_idx) else None
    columns, notes, first, dated = _parse_body(src, header_line, names, fmt, name, time_idx, series)
    headerless = names == [f"col{i}" for i in range(len(names))]
    if headerless and (head := leading_header(columns)):
        columns = {c: v[head[0] :] for c, v in columns.items()}
        notes.insert(0, head[1])
    if headerless and (rows := rows_continue(columns)):
        notes.insert(0, rows)
    elif headerless and time_idx is None and first_column_times(columns, UNIFORM_TOLERANCE):
        time_idx = 0  # an x,y file: its x the times (read in seconds, said)
    time_col = names[time_idx] if time_idx is not None else None
    columns = repeated_rows(columns, time_col, notes)
    stated = {c: stated_unit(u) for c, u in zip(names, unit_row or [], strict=False) if u}
    names = [c for c in names if c in columns]  # text columns are left out (noted)
    if fmt.decimal == ",":
        notes.insert(0, "read with a decimal comma (1,5 = 1.5)")
    kind = "tsv" if fmt.delim == "\t" else ("csv" if fmt.delim else "text")
    if time_col and not (dated and told is None):  # date-times are read in seconds
        time_in_seconds(columns, time_col, notes, first, stated.get(time_col), told, dated)
    period = _period_from_time(columns[time_col], notes, dated) if time_col else None
    empty = [c for c in names if np.all(np.isnan(columns[c]))]
    if len(empty) == len(names):
        raise NoisevarError(f"{echo(name)} has no numbers: every cell is empty or NaN")
    for c in empty:
        notes.append(f"column {echo(c)!r} is empty")
    notes += [n for c in names if c != time_col and (n := code_note(c, columns[c]))]
    notes += [n for c in names if c != time_col and (n := wrap_note(c, columns[c]))]
    units = column_units(names, time_col, stated, notes)
    return LoadedTable(name, columns, kind, time_col, period, notes, units)


def _read_frame(
    src: str | TextSource,
    header_line: int,
    ncol: int,
    fmt: _Format,
    name: str,
    chunksize: int | None = None,
) -> pd.DataFrame:
    """The table body parsed by pandas (streamed from disk for a :class:`TextSource`).

    With ``chunksize``, an iterator of frames of that many rows.
    """
    import pandas as pd  # here: pandas is heavy, and a .npy file does not need it

    sep = r"\s+" if fmt.delim is None else fmt.delim
    if fmt.thousands == "," and fmt.delim is None:
        sep = "\t"  # one column of 4,867.69: no delimiter inside a row
    try:
        return pd.read_csv(
            io.StringIO(src) if isinstance(src, str) else src.path,
            encoding=None if isinstance(src, str) else src.encoding,
            encoding_errors="replace",
            sep=sep,
            header=None,
            names=list(range(ncol)),
            skiprows=header_line,
            comment="#",
            skip_blank_lines=True,
            na_values=_NA_TOKENS,
            keep_default_na=True,
            engine="c",
            skipinitialspace=True,
            on_bad_lines="error",
            quotechar='"',
            index_col=False,
            decimal=fmt.decimal,
            thousands=fmt.thousands,
            chunksize=chunksize,
        )
    except Exception as exc:  # noqa: BLE001 - pandas raises several parser types
        msg = str(exc)
        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", msg)
        if m:
            raise NoisevarError(
                f"{echo(name)}: line {m.group(2)} has {m.group(3)} fields but the "
                f"table has {m.group(1)}: every row must have the same columns (remove the "
                "extra fields from that line and any like it, e.g. a mark after a value; or "
                "name every column in a header)"
            ) from None
        if "No columns to parse" in msg:
            raise NoisevarError(f"{echo(name)} {_NO_ROWS}") from None
        first = msg.splitlines()[0] if msg else type(exc).__name__
        raise NoisevarError(f"{echo(name)}: cannot parse the table ({echo(first, 200)})") from None


def _integer_column(col: pd.Series, cname: str, name: str, is_time: bool) -> NDArray | None:
    """An integer column as floats; times beyond 2**53 as offsets from the first (exact)."""
    arr = col.to_numpy()
    if arr.size == 0 or (arr.max() <= EXACT_INT and arr.min() >= -EXACT_INT):
        return None  # float conversion is exact: the ordinary path
    if is_time:
        # t - t[0] in integers (exact), then float
        rel = [int(v) - int(arr[0]) for v in arr]
        return np.asarray(rel, dtype=float)
    raise NoisevarError(
        f"{echo(name)}: column {echo(cname)!r} holds integers beyond 2**53 (up to "
        f"{float(max(abs(int(arr.max())), abs(int(arr.min())))):.3g}), which floating point "
        "cannot hold exactly (precision lost): subtract an offset (e.g. the first value) first"
    )


def _parse_body(
    src: str | TextSource,
    header_line: int,
    names: list[str],
    fmt: _Format,
    name: str,
    time_idx: int | None,
    series: str | None = None,
) -> tuple[dict[str, NDArray], list[str], float | None, bool]:
    """The columns as floats (the rows of one ``series`` of a stacked file), the loader's
    notes, the time column's first value when it was taken relative to it (integers beyond
    2**53: nanoseconds since 1970), and whether the time column was read from date-times or
    clock times (text: seconds already)."""
    import pandas as pd

    df = _read_frame(src, header_line, len(names), fmt, name)
    if len(df) == 0:
        raise NoisevarError(f"{echo(name)} {_NO_ROWS}")
    columns: dict[str, NDArray] = {}
    notes: list[str] = []
    first = None
    done: set[int] = set()
    clock = clock_beside(df, names, time_idx)
    if clock is not None and time_idx is not None:  # a date column, a clock column: one time
        columns[names[time_idx]], joined = clock
        notes.append(joined)
        done = {time_idx, time_idx + 1}
    dated = bool(done)
    keys: dict[str, pd.Series] = {}  # the text columns left out
    # a column of text is left out when another holds numbers (else its error says why)
    text = {i for i in range(len(names)) if i != time_idx and i not in done and _is_label(df[i])}
    numeric = len(text) < len(names) - (time_idx is not None) - len(done) // 2
    for i, cname in enumerate(names):
        if i in done:
            continue
        col = df[i]
        if i == time_idx and (digits := digit_time_column(col, cname, name)) is not None:
            columns[cname], dated = digits, True  # seconds already, as date-times are
            continue
        if pd.api.types.is_integer_dtype(col.dtype):
            # any time column (a log's second clock too) may be an epoch beyond 2**53
            exact = _integer_column(col, cname, name, i == time_idx or is_time_column(cname))
            if exact is not None:
                columns[cname] = exact
                first = float(col.iloc[0]) if i == time_idx else first
                notes.append(f"time column {echo(cname)!r} taken relative to its first value")
                continue
        if pd.api.types.is_numeric_dtype(col.dtype) and not pd.api.types.is_bool_dtype(col.dtype):
            # a writable copy: pandas may hand out read-only views (copy-on-write), which
            # some numerical libraries (PyWavelets) refuse
            columns[cname] = np.array(col.to_numpy(dtype=float, na_value=np.nan), dtype=float)
            continue
        if i in text and numeric:  # a log's label (frame_id)
            notes.append(f"column {echo(cname)!r} holds text ({echo(str(col.iloc[0]), 40)!r}), "
                         "not numbers: left out")  # fmt: skip
            keys[cname] = col
            continue
        if i != time_idx and (marked := missing_mark(col, cname, notes)) is not None:
            columns[cname] = marked
            continue
        try:
            columns[cname] = _text_column(col, cname, src, header_line, name, i == time_idx)
        except NoisevarError as e:
            raise NoisevarError(f"{e}{kinds_hint(df, names, text, col)}") from None
        dated = dated or (i == time_idx and _only_text(col))  # (numbers raised, or parsed)
    t = stack_clock(columns, names, time_idx)
    columns = one_series(keys, columns, t, name, series, notes)
    picked = names[time_idx] if series is not None and time_idx is not None else None
    first = own_clock(columns, picked, dated, first)  # a picked series' clock: its own
    return columns, notes, first, dated


def _only_text(col: pd.Series) -> bool:
    """Whether no cell of ``col`` is a number (and some cell is not empty)."""
    import pandas as pd

    if pd.api.types.is_numeric_dtype(col.dtype):  # (pandas parsed every cell as a number)
        return False
    return bool(col.notna().any()) and not pd.to_numeric(col, errors="coerce").notna().any()


def _is_label(col: pd.Series) -> bool:
    """Whether ``col`` names things rather than measures them: text (:func:`_only_text`),
    or mostly text in a few values, some of which read as numbers.

    Notes
    -----
    ADS-B's ``icao24`` hex codes: ``4690e2`` reads as 469000.0, so traffic's CSV of ten
    aircraft was refused on that column, with a hint about lines above the header.
    """
    import pandas as pd

    if _only_text(col):
        return True
    if pd.api.types.is_numeric_dtype(col.dtype):
        return False
    cells = col.dropna()
    numbers = pd.to_numeric(cells, errors="coerce").notna()
    few = few_values(cells)
    return bool(cells.size) and few and float(numbers.mean()) < 0.5


def _text_column(
    col: pd.Series,
    cname: str,
    src: str | TextSource,
    header_line: int,
    name: str,
    is_time: bool,
) -> NDArray:
    """A column pandas left as text: ISO times, or a clear error on the first bad cell."""
    import pandas as pd

    if any(isinstance(v, int) and not isinstance(v, bool) for v in col.head(100)):
        raise NoisevarError(
            f"{echo(name)}: column {echo(cname)!r} holds integers of more than 19 digits, "
            "which floating point cannot hold exactly (precision lost): subtract an offset first"
        )
    coerced = pd.to_numeric(col, errors="coerce")
    bad = (coerced.isna() & col.notna()).to_numpy()
    if bad.any():
        if is_time:  # date-times, some cells perhaps empty (a track's untimed fixes)
            present = col.notna().to_numpy()
            times = parse_time_strings([str(v).strip() for v in col[present].tolist()])
            if times is not None:
                out = np.full(col.size, np.nan)
                out[present] = times
                return out
        j = int(np.argmax(bad))
        text = src if isinstance(src, str) else src.text()

        def line_of(row: int) -> int:
            return _data_line_number(text, header_line, row)

        hint = preamble_hint(coerced.notna().to_numpy(), j, line_of)
        raise NoisevarError(
            f"{echo(name)}: line {line_of(j)}, column "
            f"{echo(cname)!r}: {echo(str(col.iloc[j]))!r} is not a number (only numeric "
            f"columns can be loaded){hint + numbers_for_names(cname, header_line) or CLEAN_HINT}"
        )
    return np.array(coerced.to_numpy(dtype=float, na_value=np.nan), dtype=float)
