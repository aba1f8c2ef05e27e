"""Loading measured signals from files: CSV/TSV, ``.npy``, NMEA 0183 (GGA/RMC) and logs.

One entry point, :func:`load_table`, turns a file (a path or its bytes) into a
:class:`LoadedTable`: named float columns, the time column if there is one,
and the sample period it implies. :func:`pick_column` then gives one signal
for :func:`noisevar.estimate`. The CLI and the dashboard share these two
functions, so a file that loads in one loads in the other.

Every failure raises :class:`~noisevar.errors.NoisevarError` with one message
that says what is wrong and where (row, column, line), never a parser
traceback.

Hostile files are refused early: a file over :data:`~noisevar.io.load.MAX_BYTES` before
it is read, a table over :data:`~noisevar.io.text.MAX_COLUMNS` columns before it is
parsed; a file given by path is streamed (text) or memory-mapped (``.npy``). Fields
echoed in messages are escaped and shortened (:func:`echo`).

Formats
-------
CSV / TSV / whitespace-separated text
    The delimiter is detected (tab, comma, semicolon, else whitespace). The
    first row is a header when any of its fields is not a number; otherwise
    the columns are named ``col0, col1, ...``. Lines starting with ``#`` are
    comments. Unquoted thousands separators in a one-column table (``4,867.69``) and a
    decimal comma with ``;`` or tab separators (``1,5`` or ``1.234,5``) are recognised.
    Integers beyond 2**53 are refused (precision lost), except in a time column, which is
    then taken relative to its first value. A cell that is not a number is refused with
    its row and column; an empty cell or ``NaN`` becomes NaN (refused later by
    :func:`pick_column` for the column actually used, unless asked to drop).
    A column named like a time (``t``, ``time``, ``time_s``, ``timestamp``,
    ``seconds``...) gives the sample period (median step), in the unit its name states,
    else the one the user states (``load_table(..., time_unit="d")``, ``--time-unit``),
    else seconds; ISO date-times in it are converted to seconds from the first. A column
    named ``datetime`` or ``date`` is the time column when it holds date-times, or dates
    written as digits (``19580329``, read as dates, not seconds; a column named
    ``AAAAMMJJ`` or ``YYYYMMDD`` too).
    An OpenSignals file (PLUX, BITalino) takes its column names from its JSON header.
``.npy``
    Read with ``np.load(allow_pickle=False)`` only (a pickled object array is
    refused: loading it could run code). A 1-D array is one column
    ``value``; a 2-D array ``(n, k)`` gives columns ``col0..``; a structured
    array gives one column per field.
NMEA 0183
    GGA and RMC sentences (any talker: GP, GN, GL...) with a valid fix are
    merged by epoch. Positions become local east/north/up metres from the
    first fix (WGS-84, exact ECEF to local ENU rotation); RMC gives speed
    (m/s) and course (degrees). A sentence with a wrong or missing checksum
    makes the whole file refused, naming the line: a corrupted log should not
    silently feed an estimator. Other sentence types are ignored.
Logs: ROS 1/2 bags, PX4 ULog, ArduPilot DataFlash, Parquet, HDF5
    One topic at a time (``load_table(path, topic=...)``; :func:`log_topics` lists them),
    with the log's own timestamps as the time column and the fields' units where the
    format defines them (:attr:`LoadedTable.units`); several topics of one log at once,
    each column on its own topic's time base, by :func:`load_topics`. See
    :mod:`noisevar.io.logs`.
"""

from typing import TYPE_CHECKING

from noisevar._lazy import lazy_names

if TYPE_CHECKING:
    from noisevar.io.limits import echo
    from noisevar.io.load import load_table, log_topics, pick_column
    from noisevar.io.logs.record import TopicsRecord, load_topics
    from noisevar.io.nmea import geodetic_to_enu
    from noisevar.io.table import (
        NMEA_EXTENSIONS,
        SAMPLE_PERIOD_RANGE,
        TABLE_EXTENSIONS,
        TIME_NAMES,
        UNIFORM_TOLERANCE,
        LoadedTable,
        content_digest,
        drop_nonfinite_rows,
        signal_summary,
        table_from_arrays,
    )

__all__ = [
    "NMEA_EXTENSIONS",
    "TABLE_EXTENSIONS",
    "TIME_NAMES",
    "UNIFORM_TOLERANCE",
    "SAMPLE_PERIOD_RANGE",
    "LoadedTable",
    "TopicsRecord",
    "channel_record",
    "content_digest",
    "drop_nonfinite_rows",
    "echo",
    "geodetic_to_enu",
    "load_table",
    "log_topics",
    "load_topics",
    "pick_column",
    "record_times",
    "signal_summary",
    "table_from_arrays",
]

#: Public names, loaded on first use (pandas and NumPy only when a file is read).
_SOURCES = {
    "echo": "noisevar.io.limits",
    "load_table": "noisevar.io.load",
    "pick_column": "noisevar.io.load",
    "channel_record": "noisevar.io.load",
    "record_times": "noisevar.io.load",
    "log_topics": "noisevar.io.load",
    "geodetic_to_enu": "noisevar.io.nmea",
    "load_topics": "noisevar.io.logs.record",
    "TopicsRecord": "noisevar.io.logs.record",
    **{
        name: "noisevar.io.table"
        for name in __all__
        if name
        not in {
            "echo",
            "load_table",
            "log_topics",
            "pick_column",
            "channel_record",
            "record_times",
            "geodetic_to_enu",
            "load_topics",
            "TopicsRecord",
        }
    },
}
__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
