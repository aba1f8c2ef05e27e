"""One entry point for files: :func:`load_table`, then :func:`pick_column`."""

from __future__ import annotations

import codecs
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import EmptyCells, NoisevarError
from noisevar.io.binary_suffix import refuse_by_suffix
from noisevar.io.foreign import NUL_NOTE, nul_padding, refuse_binary, refuse_fit, refuse_text
from noisevar.io.iaga import is_iaga, read_iaga
from noisevar.io.las import is_las, las_csv
from noisevar.io.limits import MAX_BYTES, check_bytes, check_size
from noisevar.io.nmea import _looks_like_nmea, _read_nmea
from noisevar.io.npy import _read_npy
from noisevar.io.rtklib import is_rtklib, rtklib_csv, with_side_columns
from noisevar.io.series_option import checked_series, not_stacked
from noisevar.io.table import _NPY_MAGIC, NMEA_EXTENSIONS, LoadedTable, echo
from noisevar.io.text import TextSource, _read_frame, _read_text_table, table_layout
from noisevar.io.time_option import StatedTime, stated_time, without_clock
from noisevar.io.upload import log_file

if TYPE_CHECKING:
    import pandas as pd

#: Bytes read to sniff the format and the header of a file given by path.
HEAD_BYTES = 1 << 20


def _decode(raw: bytes, name: str, final: bool = True) -> tuple[str, str]:
    """Text of ``raw`` and its encoding (UTF-16 with its byte-order mark, as Windows tools
    and Excel's "Unicode Text" write it; UTF-8; else Latin-1 for mostly printable text)."""
    head = raw[:65536]
    if head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return codecs.getincrementaldecoder("utf-16")().decode(raw, final=final), "utf-16"
        except UnicodeDecodeError:
            raise NoisevarError(
                f"{name} starts as UTF-16 text but is not: save it as UTF-8 (CSV UTF-8)"
            ) from None
    if b"\x00" in head and not nul_padding(head):
        raise NoisevarError(
            f"{name} looks like a binary file (it contains NUL bytes): give a CSV/TSV text "
            "table, an NMEA 0183 log, or a .npy array"
        )
    raw = raw.replace(b"\x00", b"")  # padding of text fields (nul_padding)
    try:
        # a head cut inside a multi-byte character is still UTF-8
        dec = codecs.getincrementaldecoder("utf-8-sig")()
        return dec.decode(raw, final=final), "utf-8-sig"
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
        ctrl = sum(1 for ch in text[:65536] if ord(ch) < 32 and ch not in "\r\n\t")
        if ctrl > 0.01 * min(len(text), 65536):
            raise NoisevarError(
                f"{name} looks like a binary file (not UTF-8 text): give a CSV/TSV text table, "
                "an NMEA 0183 log, or a .npy array"
            ) from None
    return text, "latin-1"


def _read_head(path: Path, name: str) -> bytes:
    try:
        with path.open("rb") as fh:
            return fh.read(HEAD_BYTES)
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(name)}: {exc.strerror or exc}") from None


def _read_all(path: Path, name: str) -> bytes:
    try:
        return path.read_bytes()
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(name)}: {exc.strerror or exc}") from None


def read_text_chunks(
    path: str | os.PathLike, name: str | None = None, rows: int = HEAD_BYTES
) -> tuple[list[str], Iterator[pd.DataFrame]]:
    """A text table on disk read in pieces: its column names and frames of its rows.

    The table is read as :func:`load_table` reads it (delimiter, decimal mark,
    thousands separator, header), without holding the file in memory.

    Parameters
    ----------
    path : path-like
        A CSV/TSV or whitespace-separated text file.
    name : str, optional
        For messages (default: ``str(path)``).
    rows : int
        Rows per frame.

    Returns
    -------
    names : list of str
        The column names (``col0, col1, ...`` without a header).
    frames : iterator of pandas.DataFrame
        The body, ``rows`` rows at a time, columns numbered ``0 .. len(names) - 1``;
        the file is opened at the first frame and closed after the last.

    Raises
    ------
    NoisevarError
        An unreadable, binary or malformed file (while the frames are read, too).
    """
    p = Path(path)
    name = str(path) if name is None else name
    head = _read_head(p, name)
    whole = p.stat().st_size <= len(head)
    text, encoding = _decode(head, name, final=whole)
    fmt, names, header_line, _ = table_layout(text, name, whole)
    src = TextSource(p, text, encoding)

    def frames() -> Iterator[pd.DataFrame]:
        with _read_frame(src, header_line, len(names), fmt, name, chunksize=rows) as reader:
            yield from reader

    return names, frames()


def load_table(
    source: str | os.PathLike | bytes,
    name: str | None = None,
    *,
    max_bytes: int | None = MAX_BYTES,
    topic: str | None = None,
    fields: Sequence[str] | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> LoadedTable:
    """Read a CSV/TSV text table, a ``.npy`` array, an NMEA 0183 log, or one topic of a log.

    Parameters
    ----------
    source : str, path or bytes
        A file path, or the file's bytes (an upload).
    name : str, optional
        File name; its extension picks the format (``.npy``; ``.nmea`` and
        friends; anything else is sniffed: ``.npy`` magic bytes, NMEA
        sentences, else a text table). Default: the path's name.
    max_bytes : int or None
        Refuse larger files (checked before reading); default :data:`MAX_BYTES`;
        None: no limit. A log given by path is streamed and may be larger: the cap is then
        on the numbers of the topic read (:data:`noisevar.io.logs.MAX_VALUES`).
    topic : str, optional
        For a log (ROS bag, ULog, DataFlash, Parquet, HDF5: :mod:`noisevar.io.logs`): the
        topic to read; may be omitted when the log has one. Refused for other files.
    fields : sequence of str, optional
        For a log: the topic's fields to read, by dotted path (default: all).
    time_unit : str, optional
        The unit of the time column's values (any unit of time pint reads: ``"d"``,
        ``"ms"``; :data:`~noisevar.io.time_option.TIME_UNIT`), over a unit nothing in the
        file states; refused where the column's name states another. For an HDF5 topic
        without a time dataset, its ``dx``/``dt`` attribute is read in it as the period.
        Default: the name's unit, else seconds (said in a note).
    series : str, optional
        For a text table that stacks several series (:func:`noisevar.io.stacked.stacks`,
        refused without it as :class:`~noisevar.errors.StackedSeries`): the label of the
        one to read (:data:`~noisevar.io.series_option.SERIES`), its rows in file order.
        Refused for a file that holds one series and when no row has it.

    Returns
    -------
    LoadedTable

    Raises
    ------
    NoisevarError
        Missing, empty, binary or malformed files (with the line and column),
        NMEA checksum errors, pickled ``.npy`` arrays, files over ``max_bytes``,
        tables over :data:`~noisevar.io.text.MAX_COLUMNS` columns.

    Notes
    -----
    A file given by path is never read whole into memory before it is parsed: a
    ``.npy`` array is memory-mapped and a text table streamed by the parser.

    Examples
    --------
    >>> tab = load_table(b"t,x\\n0,1.0\\n0.5,1.2\\n1.0,0.9\\n", "demo.csv")
    >>> tab.data_columns, tab.sample_period
    (['x'], 0.5)
    """
    from noisevar.io import logs

    told = stated_time(time_unit)  # refused before the file is read
    series = checked_series(series)
    if isinstance(source, (bytes, bytearray, memoryview)):
        raw = bytes(source)
        name = name or "upload"
        check_bytes(len(raw), name, max_bytes)
        if logs.reader_for(name, raw[:64]) is not None:
            not_stacked(name, series, LOG)
            return _load_log_bytes(raw, name, topic, fields, told)
        _no_topic(name, topic)
        return without_clock(_parse(raw, name, None, len(raw), told, series), told)
    path = Path(source)
    name = name or path.name
    size = None if logs.is_ros2_dir(path) else check_size(path, name, None)
    head = b"" if size is None else _read_head(path, name)
    if size is None or logs.reader_for(name, head[:64]) is not None:
        not_stacked(name, series, LOG)
        return logs.with_time_unit(logs.load_log(path, topic, fields, name), path, topic, told)
    _no_topic(name, topic)
    check_bytes(size, name, max_bytes)
    return without_clock(_parse(head, name, path, size, told, series), told)


def load_log_tables(
    source: str | os.PathLike | bytes,
    topics: Sequence[str],
    name: str | None = None,
    *,
    max_bytes: int | None = MAX_BYTES,
) -> dict[str, LoadedTable]:
    """Several topics of one log, each as :func:`load_table` reads it, from one pass over the
    log where its reader can (:func:`noisevar.io.logs.load_logs`).

    Parameters
    ----------
    source : str, path or bytes
        The log, or its bytes (an upload: written once to a private temporary file).
    topics : sequence of str
        The topics (order kept, each once).
    name : str, optional
        File name (default: the path's name).
    max_bytes : int or None
        Refuse larger uploads (:data:`MAX_BYTES`); a log given by path is streamed.

    Returns
    -------
    dict of str to LoadedTable

    Raises
    ------
    NoisevarError
        Not a log, unreadable, a topic not in the log.
    """
    from noisevar.io import logs

    wanted = list(dict.fromkeys(topics))
    if isinstance(source, (bytes, bytearray, memoryview)):
        raw = bytes(source)
        name = name or "upload"
        check_bytes(len(raw), name, max_bytes)
        if logs.reader_for(name, raw[:64]) is None:
            _no_topic(name, wanted[0] if wanted else "")
        with log_file(raw, name) as path:
            return logs.load_logs(path, wanted, name)
    path = Path(source)
    name = name or path.name
    if not logs.is_ros2_dir(path):
        check_size(path, name, None)
        if logs.reader_for(name, _read_head(path, name)[:64]) is None:
            _no_topic(name, wanted[0] if wanted else "")
    return logs.load_logs(path, wanted, name)


def _no_topic(name: str, topic: str | None) -> None:
    if topic is not None:
        raise NoisevarError(
            f"{echo(name)} is not a log (a ROS bag, ULog, DataFlash, Parquet or HDF5 file): "
            "it has no topics; leave out the topic"
        )


def _load_log_bytes(
    raw: bytes, name: str, topic: str | None, fields: Sequence[str] | None, told: StatedTime | None
) -> LoadedTable:
    """One topic of a log uploaded as bytes: written to a private temporary file, read."""
    from noisevar.io import logs

    with log_file(raw, name) as path:
        return logs.with_time_unit(logs.load_log(path, topic, fields, name), path, topic, told)


def log_topics(source: str | os.PathLike | bytes, name: str | None = None) -> list | None:
    """The topics of a log (a path or its bytes), or None when the file is not a log.

    Parameters
    ----------
    source : str, path or bytes
        The file, or its bytes (an upload).
    name : str, optional
        Its name (the suffix helps tell the format); default: the path's name.

    Returns
    -------
    list of noisevar.io.logs.TopicInfo, or None

    Raises
    ------
    NoisevarError
        A log its library cannot read.
    """
    from noisevar.io import logs

    if isinstance(source, (bytes, bytearray, memoryview)):
        raw, name = bytes(source), name or "upload"
        if logs.reader_for(name, raw[:64]) is None:
            return None
        with log_file(raw, name) as path:
            return logs.list_topics(path, name)
    path = Path(source)
    name = name or path.name
    if not logs.is_ros2_dir(path):
        check_size(path, name, None)
        if logs.reader_for(name, _read_head(path, name)[:64]) is None:
            return None
    return logs.list_topics(path, name)


def _parse(
    head: bytes,
    name: str,
    path: Path | None,
    size: int,
    told: StatedTime | None = None,
    series: str | None = None,
) -> LoadedTable:
    """Dispatch on the format; ``head`` is the whole file when ``path`` is None; ``series``:
    the label of the series to read of a text table that stacks several."""
    if size == 0 or not head.strip():
        raise NoisevarError(f"{echo(name)} is empty")
    lower = name.lower()
    if head.startswith(_NPY_MAGIC) or lower.endswith(".npy"):
        if not head.startswith(_NPY_MAGIC):
            raise NoisevarError(f"{echo(name)} is not a valid .npy file (no NumPy header)")
        not_stacked(name, series, " (an array)")
        return _read_npy(path if path is not None else head, name, told)
    if lower.endswith(".npz"):
        raise NoisevarError(
            f"{echo(name)}: .npz archives are not supported; save one array as .npy"
        )
    _refuse_compressed(head, name)
    refuse_fit(head, name)
    refuse_binary(head, name)
    refuse_by_suffix(head, name)
    whole = path is None or size <= len(head)
    padding = nul_padding(head)
    if padding and not whole:  # the padding is left out of the text: read all of it
        head, whole = _read_all(path, name), True
        padding = head.count(b"\x00")
    table = _parse_text(head, name, path, whole, told, series)
    if padding:
        table.notes.append(NUL_NOTE.format(n=padding))
    return table


def _parse_text(
    head: bytes,
    name: str,
    path: Path | None,
    whole: bool,
    told: StatedTime | None = None,
    series: str | None = None,
) -> LoadedTable:
    """A text file: refused when it is of a format noisevar does not read, else NMEA,
    IAGA-2002 or a text table."""
    lower = name.lower()
    text, encoding = _decode(head, name, final=whole)
    refuse_text(text, name)
    _refuse_rinex(text, name)
    _refuse_json(text, name)
    if lower.endswith(NMEA_EXTENSIONS) or _looks_like_nmea(text):
        not_stacked(name, series, " (an NMEA log)")
        if not whole:
            text = _decode(_read_all(path, name), name)[0]
        return _read_nmea(text, name)
    if is_iaga(text):
        text = text if whole else _decode(_read_all(path, name), name)[0]
        return read_iaga(text, name, told, series)
    # formats read as the CSV table they convert to: (is it, convert, finish the table)
    formats = ((is_rtklib, rtklib_csv, with_side_columns), (is_las, las_csv, None))
    for sniff, convert, finish in formats:
        if sniff(text):  # a format read as the CSV table it converts to, with its note
            csv, note = convert(text if whole else _decode(_read_all(path, name), name)[0], name)
            table = _read_text_table(csv, name, told, series)
            table.notes.insert(0, note)
            return table if finish is None else finish(table)
    source = text if whole else TextSource(path, text, encoding)
    return _read_text_table(source, name, told, series)


#: Why a log holds one series (a label given for it is refused).
LOG = " (a log's topic)"


#: Magic bytes of compressed files and archives: (bytes, what it is, what to do).
_COMPRESSED = (
    (b"\x1f\x8b", "gzip-compressed", "decompress it (e.g. gunzip, 7-Zip)"),
    (b"BZh", "bzip2-compressed", "decompress it (e.g. bunzip2, 7-Zip)"),
    (b"\xfd7zXZ\x00", "xz-compressed", "decompress it (e.g. unxz, 7-Zip)"),
    (b"PK\x03\x04", "a zip archive", "extract the file you want from it"),
    (b"7z\xbc\xaf\x27\x1c", "a 7z archive", "extract the file you want from it"),
)


def _refuse_compressed(head: bytes, name: str) -> None:
    """Refuse a compressed file or an archive by name, in one line that says what to do.

    Notes
    -----
    traffic's samples are ``.json.gz``: refused as "a binary file (it contains NUL bytes)",
    which did not say that the table is inside. A workbook (a zip too) is read before this.
    """
    for magic, what, todo in _COMPRESSED:
        if head.startswith(magic):
            raise NoisevarError(
                f"{echo(name)} is {what}: {todo} and give the file inside (a CSV/TSV text "
                "table, an NMEA 0183 log, a .npy array or a log)"
            )


def _refuse_json(text: str, name: str) -> None:
    """Refuse a JSON or JSON-lines file in one line that says how to make it a table.

    Notes
    -----
    readsb's trace and Flightradar24's export (one object over many lines) and rs1090's JSON
    lines were read as a text table and refused blaming thousands separators. A file counts
    as JSON when it starts with ``{``, or with ``[`` then an object, an array, a string or a
    line end (a header of bracketed names, ``[time],[x]``, is a table's).
    """
    body = text.lstrip("\ufeff \t\r\n")
    if not body.startswith("{") and not (
        body.startswith("[") and body[1:].lstrip(" \t")[:1] in ("{", "[", '"', "\n", "\r")
    ):
        return
    raise NoisevarError(
        f"{echo(name)} is a JSON file, which noisevar does not read as a table: write the "
        "values you want as columns of a CSV file (e.g. pandas.read_json(path).to_csv(...), "
        "with lines=True for JSON lines; a trace nested in an object: json_normalize it "
        "first) and give that file"
    )


def _refuse_rinex(text: str, name: str) -> None:
    """Refuse a RINEX file (GNSS observations, navigation, meteorology) in one line that
    says what to do.

    Notes
    -----
    Its header lines end in labels (``RINEX VERSION / TYPE`` in columns 61-80) and each epoch
    lists satellites with several observables: read as a table, it was refused blaming a
    row's field count (hatanaka's ``sample.rnx``).
    """
    first = text.lstrip("\ufeff").split("\n", 1)[0]
    if "RINEX VERSION / TYPE" not in first and "CRINEX VERS" not in first:
        return
    kind = first[20:40].strip().lower() or "observation"
    raise NoisevarError(
        f"{echo(name)} is a RINEX file ({kind}), which noisevar does not read: export one "
        "observable per epoch (e.g. a satellite's pseudorange C1C, carrier phase L1C or "
        "SNR S1C) as a column of a CSV file, e.g. with georinex, and give that file"
    )


def column_name(table: LoadedTable, column: str | int | None = None) -> str:
    """The name of the data column ``column`` (a name, an index among the data columns, or None
    for the first), or a :class:`NoisevarError` listing the columns."""
    data_cols = table.data_columns
    if not data_cols:
        raise NoisevarError(f"{echo(table.name)} has no data column (only a time column)")
    if column is None:
        cname = table.first_signal or data_cols[0]
    elif isinstance(column, (int, np.integer)) and not isinstance(column, bool):
        if not 0 <= int(column) < len(data_cols):
            raise NoisevarError(
                f"column index {column} is out of range: {echo(table.name)} has "
                f"{len(data_cols)} data columns"
            )
        cname = data_cols[int(column)]
    else:
        cname = str(column)
        if cname not in table.columns:
            if (
                cname.isascii()
                and cname.isdigit()
                and len(cname) < 10
                and int(cname) < len(data_cols)
            ):
                cname = data_cols[int(cname)]
            else:
                cols = list(table.columns)
                listed = ", ".join(echo(c, 40) for c in cols[:20])
                more = f" and {len(cols) - 20} more" if len(cols) > 20 else ""
                raise NoisevarError(
                    f"no column {echo(column)!r} in {echo(table.name)}; columns: {listed}{more}"
                )
    return cname


def column_values(table: LoadedTable, column: str | int | None = None) -> NDArray:
    """One column as floats over its rows (a run's: ``LoadedTable.rows_of``), non-finite
    cells kept (the estimators treat them as gaps)."""
    cname = column_name(table, column)
    return np.asarray(table.columns[cname][table.rows_of(cname)], dtype=float)


def record_times(table: LoadedTable, column: str | int | None = None) -> NDArray | None:
    """A channel's sample times as :func:`noisevar.estimate` takes them (``t=``), or None.

    ``column``: the channel (default the first signal), whose clock is its run's when the
    table holds one per run (``LoadedTable.clock_of``). None when the table has no time
    column, or its times are not finite and strictly increasing (the loader's note says
    why; the samples are then taken as uniform).

    Notes
    -----
    Every path that estimates a table's channel (``noisevar estimate``, ``--columns``,
    ``noisevar batch``, the dashboard) passes these times, so that a record with gaps is
    split at them in each, not spliced in some: one record, one answer.
    """
    cname = column_name(table, column) if table.data_columns else None
    t = table.time(cname)
    if t is None:
        return None
    t = np.asarray(t, dtype=float)
    if t.size != table.n_rows_of(cname) or not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
        return None
    return t


def channel_record(
    table: LoadedTable, column: str | int | None = None, *, drop_nonfinite: bool = False
) -> tuple[NDArray, NDArray | None]:
    """One column and its sample times, as every estimating path reads a table's channel.

    Non-finite cells are kept for the estimator to treat as gaps when ``drop_nonfinite``
    (refused, naming the first, otherwise); the times are :func:`record_times`.
    """
    if drop_nonfinite:
        z = column_values(table, column)
    else:
        z = np.asarray(pick_column(table, column), dtype=float)
    return z, record_times(table, column)


#: What a refusal of empty cells tells users to do, where dropping them is right.
DROP_THEM = "clean the file, or drop them (CLI: --drop-nonfinite)"


def pick_column(
    table: LoadedTable,
    column: str | int | None = None,
    *,
    drop_nonfinite: bool = False,
    fix: str = DROP_THEM,
) -> NDArray:
    """One column of a table as a signal for :func:`noisevar.estimate`.

    Parameters
    ----------
    table : LoadedTable
        A loaded file.
    column : str or int, optional
        Column name, or index among :attr:`LoadedTable.data_columns`
        (default: :attr:`LoadedTable.first_signal`, the first data column that varies).
    drop_nonfinite : bool
        Drop empty/NaN cells instead of refusing them.
    fix : str
        What the refusal of empty cells tells users to do (:data:`DROP_THEM`; an analysis
        that needs every sample in its place says so instead).

    Returns
    -------
    ndarray of float, shape (n,)

    Raises
    ------
    NoisevarError
        Unknown column, or a column with empty/NaN cells (unless dropped).
    """
    cname = column_name(table, column)
    z = np.asarray(table.columns[cname][table.rows_of(cname)], dtype=float)
    bad = ~np.isfinite(z)
    if bad.any():
        if not drop_nonfinite:
            first = int(np.argmax(bad))
            kind = EmptyCells if fix == DROP_THEM else NoisevarError
            raise kind(
                f"column {echo(cname)!r} of {echo(table.name)} has {int(bad.sum())} empty or NaN "
                "values "
                f"(the first at data row {first + 1}): {fix}"
            )
        z = z[~bad]
    return z
