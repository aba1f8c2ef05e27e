"""Spreadsheet workbooks (Excel ``.xlsx``/``.xlsm``/``.xlsb``/``.xls``, LibreOffice ``.ods``),
through ``python-calamine``; nothing is evaluated.

Each sheet holding numbers is a topic (phyphox's and lab loggers' exports: one sheet per
sensor, beside sheets of metadata). A sheet is read as a text table is
(:func:`noisevar.io.text.read_text_table`): its header row and the units in it
(``Acceleration x (m/s^2)``), its time column (seconds, a clock or a date-time) and its
missing cells, so one record gives one answer as a sheet or saved as CSV. Cells keep the
values the spreadsheet stored: a formula's last computed value, never the formula.

Untrusted files: a zipped workbook's entries are sized from the zip's directory before
anything is parsed (:data:`MAX_UNZIPPED`: a small file cannot expand to gigabytes), and
calamine's XML parser expands no entities; the cells one sheet holds are capped
(:data:`~noisevar.io.logs.spec.MAX_VALUES`).
"""

from __future__ import annotations

import csv
import datetime as dt
import io
import os
import zipfile
from collections.abc import Iterator, Sequence
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from noisevar.errors import NoisevarError
from noisevar.io.limits import MAX_BYTES, echo
from noisevar.io.logs.spec import MAX_FIELDS, MAX_VALUES, Chunk, LogReader, TopicInfo, report
from noisevar.io.text import read_text_table

if TYPE_CHECKING:
    from noisevar.io.table import LoadedTable

#: Most bytes a zipped workbook's entries may expand to (their declared sizes, summed): a
#: sheet is held whole while it is read, about 50 bytes a cell for 20 bytes of its XML.
MAX_UNZIPPED = MAX_BYTES // 4
#: Workbook formats that are zip files (the binary ``.xls`` is not).
ZIPPED = (".xlsx", ".xlsm", ".xlsb", ".ods")


def _check_zip(path: Path) -> None:
    """Refuse a zipped workbook that is no whole zip, or whose entries would expand past
    :data:`MAX_UNZIPPED`."""
    if not path.name.lower().endswith(ZIPPED):
        return
    if not zipfile.is_zipfile(path):
        raise NoisevarError(
            f"{echo(path.name)} is not a whole workbook (an .xlsx or .ods is a zip file; this "
            "one is cut short, or another format): save it again, or save the sheet as CSV"
        )
    with zipfile.ZipFile(path) as z:
        total = sum(i.file_size for i in z.infolist())
    if total > MAX_UNZIPPED:
        raise NoisevarError(
            f"{echo(path.name)} expands to {total:,} bytes, over the limit of "
            f"{MAX_UNZIPPED:,}: save the sheet you need as CSV"
        )


def _cell(value: object) -> str:
    """A cell as text the text-table reader reads back: numbers exactly (``repr``),
    date-times as ISO 8601, a clock time as ``hh:mm:ss.ffffff``, empty as empty."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dt.datetime | dt.date | dt.time):
        return value.isoformat()
    if isinstance(value, dt.timedelta):
        return repr(value.total_seconds())
    return str(value)


def _sheet_csv(rows: Iterator[list], name: str) -> str | None:
    """A sheet's rows as CSV text, trailing empty cells and rows dropped; None if empty."""
    buf = io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    cells = 0
    for row in rows:
        cols = [_cell(v) for v in row]
        while cols and cols[-1] == "":
            cols.pop()
        if not cols:
            continue
        cells += len(cols)
        if cells > MAX_VALUES:
            raise NoisevarError(
                f"sheet {echo(name)!r} holds over {MAX_VALUES:,} cells, over the limit: "
                "save the columns you need as CSV"
            )
        out.writerow(cols)
    return buf.getvalue() or None


@lru_cache(maxsize=1)
def _tables(path: str, stamp: tuple[int, int]) -> dict[str, tuple[LoadedTable | None, str]]:
    """Each sheet read as a text table (None, with why, for a sheet without numbers).

    Cached on the file's path, size and modification time: listing the topics and reading
    one parse the workbook once.
    """
    from python_calamine import CalamineWorkbook

    _check_zip(Path(path))
    book = CalamineWorkbook.from_path(path)
    try:
        out: dict[str, tuple[LoadedTable | None, str]] = {}
        for title in book.sheet_names:
            text = _sheet_csv(book.get_sheet_by_name(title).iter_rows(), title)
            if text is None:
                out[title] = None, "empty"
                continue
            try:
                out[title] = read_text_table(text, f"{title}.csv"), ""
            except NoisevarError as exc:
                out[title] = None, str(exc)
        return out
    finally:
        book.close()


def _sheets(path: Path) -> dict[str, tuple[LoadedTable | None, str]]:
    st = os.stat(path)
    return _tables(str(path.resolve()), (st.st_size, st.st_mtime_ns))


def topics(path: Path) -> list[TopicInfo]:
    """One topic per sheet with numbers: its rows, rate (with a time column), columns, units."""
    found = []
    for title, (table, _) in _sheets(path).items():
        if table is None or not table.data_columns:
            continue
        rate = 1.0 / table.sample_period if table.sample_period else None
        fields = tuple(table.data_columns[:MAX_FIELDS])
        units = {f: u for f, u in table.units.items() if f in fields}
        found.append(TopicInfo(title, "sheet", table.n_rows, rate, fields, units))
    return found


def read(path: Path, topic: str, fields: Sequence[str] | None) -> Iterator[Chunk]:
    """One sheet's columns (all at once: a sheet is capped), times in seconds."""
    sheets = _sheets(path)
    table, why = sheets.get(topic, (None, "no such sheet"))
    if table is None:
        listed = ", ".join(echo(s, 40) for s, (t, _) in sheets.items() if t is not None)
        raise NoisevarError(
            f"{echo(path.name)}: sheet {echo(topic)!r} has no numbers to read ({echo(why, 200)})"
            f"; sheets with numbers: {listed or 'none'}"
        )
    names = tuple(fields) if fields is not None else tuple(table.data_columns)
    bad = [f for f in names if f not in table.data_columns]
    if bad:
        raise NoisevarError(
            f"sheet {echo(topic)!r} has no column {echo(bad[0])!r}; columns: "
            + ", ".join(echo(c, 40) for c in table.data_columns[:40])
        )
    for note in table.notes:
        report(note)
    yield Chunk(table.time(), {f: table.columns[f] for f in names})


READER = LogReader(
    name="workbook",
    title="spreadsheet workbook",
    suffixes=(*ZIPPED, ".xls"),
    magic=(),
    topics=topics,
    read=read,
    time_note="times from the sheet's time column",
    repair="save it again from Excel or LibreOffice, or save the sheet as CSV",
    in_folders=True,
)
