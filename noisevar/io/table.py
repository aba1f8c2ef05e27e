"""The loaded table, its time column and sample period."""

from __future__ import annotations

import hashlib
import io
import re
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import steps_evenly
from noisevar.errors import NoisevarError
from noisevar.io.column_kinds import bookkeeping, time_steps
from noisevar.io.limits import ECHO_LIMIT, echo  # noqa: F401 - their home is io.limits
from noisevar.io.period import clock_period, rounded_period
from noisevar.io.time_option import StatedTime, how_to_state, say_if_counting
from noisevar.units import sensor_of

#: Names (lower case, units in brackets stripped) recognised as a time column.
TIME_NAMES = ("t", "time", "time_s", "times", "timestamp", "seconds", "sec", "secs", "s", "epoch",
              "elapsed", "seconds_elapsed", "millis", "micros")  # fmt: skip
#: Time names that state their unit by themselves: an Arduino's ``millis()`` and ``micros()``.
NAMED_TIME_UNITS = {"millis": "ms", "micros": "us"}
#: Names of a column that is the time column when it holds date-times (``2016-11-24
#: 13:58:58.081``) or dates written as digits (``19580329``: read as dates, never seconds).
DATE_NAMES = ("datetime", "date", "date_time")
#: File extensions read as text tables.
TABLE_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".tab")
#: File extensions read as NMEA 0183 logs (content is also sniffed).
NMEA_EXTENSIONS = (".nmea", ".nma", ".gps", ".log", ".ubx.nmea")
#: Relative spread of the time steps above which the sampling counts as not uniform.
UNIFORM_TOLERANCE = 0.01
#: Sample periods (seconds) taken from a time column; a step outside is a unit mistake
#: (milliseconds, nanoseconds) more often than a real rate.
SAMPLE_PERIOD_RANGE = (1e-9, 1e6)
#: Calendar steps of date-times, in days: a month, a quarter, a year differ in length.
CALENDAR_STEPS = {"month": (28, 31), "quarter": (89, 92), "year": (365, 366)}
_NPY_MAGIC = b"\x93NUMPY"
_NA_TOKENS = ["", "nan", "NaN", "NAN", "na", "NA", "n/a", "N/A", "null", "NULL", "None", "-"]


@dataclass
class LoadedTable:
    """Columns of numbers read from one file.

    Attributes
    ----------
    name : str
        File name (for messages and titles).
    columns : dict of str to ndarray
        Column name to float samples, all of the same length; NaN marks an
        empty cell.
    kind : str
        The format the file was read as: ``csv``, ``tsv``, ``text``, ``npy``, ``nmea``,
        ``generated``, or a log reader's name (:data:`noisevar.io.logs.READERS`).
    time_column : str or None
        The column holding the sample times (seconds), if any.
    sample_period : float or None
        Median time step of ``time_column`` (seconds), if any.
    notes : list of str
        Plain-language remarks (non-uniform sampling, skipped sentences...).
    units : mapping of str to str
        Column name to its unit (pint syntax, e.g. ``rad/s``, ``m/s**2``), for the columns
        whose unit the file defines (a log's message definitions); empty otherwise.
    declared_variance : mapping of str to float
        Column name to the noise variance the log declares for it (a ROS message's
        covariance diagonal, its median over the messages; in the column's unit squared),
        for the columns whose messages declare a known one; empty otherwise.
    side_columns : mapping of str to str
        Columns the file's format says are no measured signal (a solution's quality flag,
        its own standard deviations), each with what it is: left out of :attr:`signals`
        and of ``--columns all``, read when named.
    """

    name: str
    columns: dict[str, NDArray]
    kind: str
    time_column: str | None = None
    sample_period: float | None = None
    notes: list[str] = field(default_factory=list)
    units: Mapping[str, str] = field(default_factory=dict)
    declared_variance: Mapping[str, float] = field(default_factory=dict)
    side_columns: Mapping[str, str] = field(default_factory=dict)

    @property
    def n_rows(self) -> int:
        """Number of samples per column."""
        return int(next(iter(self.columns.values())).size) if self.columns else 0

    @property
    def data_columns(self) -> list[str]:
        """Column names other than the time column (the candidate signals)."""
        return [c for c in self.columns if c != self.time_column]

    @property
    def first_signal(self) -> str | None:
        """The column read when none is named: the first data column that is a signal.

        Not a log's second clock (``rostopic echo -p``'s ``%time`` beside the message's own
        stamp), a counter (``field.header.seq``: :func:`noisevar._arrays.steps_evenly`, or
        one that wraps: BITalino's ``nSeq``), a digital line of 0s and 1s (BITalino's
        outputs ``O1``, ``O2``) or a constant field (an orientation the log does not fill, a
        covariance of -1), which come first in ROS messages; each can still be named. A
        signal in a sensor's unit (an angular rate, an acceleration:
        :func:`noisevar.units.sensor_of`) comes first (a ROS Imu message's
        ``angular_velocity.x``, not the orientation an AHRS fills); then one without
        empty/NaN cells before one with them; with no signal, the first data column without
        them, else the first; None when there is no data column.
        """
        cols = self.data_columns
        whole = [c for c in cols if np.all(np.isfinite(self.columns[c]))]
        signals = self.signals
        sensed = [c for c in signals if c in whole and sensor_of(self.units.get(c))]
        order = sensed + [c for c in signals if c in whole] + signals + whole + cols
        return next(iter(order), None)

    @property
    def signals(self) -> list[str]:
        """The data columns that are signals (:attr:`first_signal`'s rule), in order: what
        ``noisevar imu`` fits when no column is named."""
        return [c for c in self.data_columns if self._is_signal(c)]

    def _is_signal(self, name: str) -> bool:
        z = self.columns[name]
        finite = z[np.isfinite(z)]
        varies = finite.size > 1 and finite.max() > finite.min()
        clock = self.clock_of(name)  # its steps (a dt column: time_steps) are no signal
        return (
            varies
            and name not in self.side_columns
            and not is_time_column(name)
            and not steps_evenly(finite)
            and not bookkeeping(finite)  # a digital line, a flag, a code: column_kinds
            and not (clock not in (None, name) and time_steps(z, self.columns[clock]))
        )

    def clock_of(self, column: str | None) -> str | None:
        """The time column of ``column``: its own run's, when the table holds one clock per
        run (PASCO Capstone's ``Time (s) Run #2`` beside ``Position (m) Run #2``), else
        :attr:`time_column`."""
        run = run_of(column or "")
        if run is not None and run_of(self.time_column or "") != run:
            own = [c for c in self.columns if run_of(c) == run and is_time_column(c)]
            if own:
                return own[0]
        return self.time_column

    def rows_of(self, column: str | None) -> slice:
        """The rows of ``column``: for a run's column, up to its clock's last value (a
        shorter run's cells below are blank, not missing samples); else every row."""
        clock = self.clock_of(column)
        if clock is None or run_of(column or "") is None:
            return slice(None)
        finite = np.flatnonzero(np.isfinite(self.columns[clock]))
        return slice(0, int(finite[-1]) + 1 if finite.size else 0)

    def n_rows_of(self, column: str | None) -> int:
        """How many rows :meth:`rows_of` gives ``column``."""
        return len(range(*self.rows_of(column).indices(self.n_rows)))

    def period_of(self, column: str | None) -> float | None:
        """The sample period of ``column`` (seconds): its run's clock's median step, else
        :attr:`sample_period`."""
        if self.clock_of(column) == self.time_column:
            return self.sample_period
        t = self.time(column)
        steps = np.diff(t[np.isfinite(t)]) if t is not None else np.zeros(0)
        step = float(f"{np.median(steps):.12g}") if steps.size else 0.0  # 0.05, not 0.04999..
        return step if np.isfinite(step) and step > 0 else None

    def time(self, column: str | None = None) -> NDArray | None:
        """The time column (seconds) or None; ``column``: that column's clock
        (:meth:`clock_of`) over its rows (:meth:`rows_of`), in seconds."""
        clock = self.clock_of(column)
        if clock is None:
            return None
        t = self.columns[clock][self.rows_of(column)]
        if clock == self.time_column:  # scaled to seconds when read
            return t
        return t * time_scale(clock, float(t[0]) if t.size else None)

    def digest(self) -> str:
        """Content hash of all columns (names and values): a cache key."""
        h = hashlib.blake2b(digest_size=16)
        for name, col in self.columns.items():
            h.update(name.encode())
            h.update(np.ascontiguousarray(col, dtype=float).tobytes())
        return h.hexdigest()

    def to_csv(self) -> str:
        """The table as CSV text with a header row."""
        names = list(self.columns)
        data = np.column_stack([self.columns[c] for c in names]) if names else np.empty((0, 0))
        buf = io.StringIO()
        buf.write(",".join(names) + "\n")
        np.savetxt(buf, data, delimiter=",", fmt="%.10g")
        return buf.getvalue()


def content_digest(data: bytes | ArrayLike) -> str:
    """Short content hash of bytes or of an array's values (a cache key).

    Parameters
    ----------
    data : bytes or array_like
        File bytes, or samples (hashed as contiguous float64 plus shape).

    Returns
    -------
    str
        32 hex characters (BLAKE2b, 16 bytes).
    """
    h = hashlib.blake2b(digest_size=16)
    if isinstance(data, (bytes, bytearray, memoryview)):
        h.update(bytes(data))
    else:
        arr = np.ascontiguousarray(np.asarray(data, dtype=float))
        h.update(str(arr.shape).encode())
        h.update(arr.tobytes())
    return h.hexdigest()


def time_key(name: str) -> str:
    """A column name as the time names are written: lower case, units in brackets dropped
    (and the ``%`` of ``rostopic echo -p``'s ``%time``)."""
    base = re.sub(r"[\[\(].*?[\]\)]", "", name).strip().lower().replace(" ", "_")
    return base.lstrip("%")


def _is_stamp(base: str) -> bool:
    """A ROS message's own time (``field.header.stamp``): when the sensor sampled."""
    return base == "stamp" or base.endswith((".stamp", "_stamp"))


def _is_time_name(name: str) -> bool:
    base = time_key(name)
    return (
        base in TIME_NAMES or base.startswith("time_") or base.endswith("_time") or _is_stamp(base)
    )


def pick_time_column(names: list[str]) -> int | None:
    """The index of the record's time column among ``names`` (None: there is none).

    The first time column, except that a message's own stamp (``field.header.stamp``)
    comes before the time a logger received it (``rostopic echo -p``'s ``%time``).
    """
    times = [i for i, c in enumerate(names) if is_time_column(c)]
    stamps = [i for i in times if _is_stamp(time_key(names[i]))]
    return (stamps or times or [None])[0]


def is_time_column(name: str) -> bool:
    """A text or ``.npy`` column read as the time column: a time name, or ``timestamp_us``,
    ``t_ms`` (a time word with its unit; :func:`time_in_seconds` scales them)."""
    base = time_key(name)
    # a time word with its unit: timestamp_us, t_ms, SensorLog's accelerometerTimestamp(s)
    worded = base.startswith(("timestamp_", "t_", "time")) or "timestamp" in base
    days = _DAY_NAME.fullmatch(base) is not None  # BJD, MJD, Kepler's BKJD, TESS's BTJD, days
    return _is_time_name(name) or days or (worded and time_unit(name) is not None)


#: Time units a time column's name may state, as a suffix (``time_ns``, ``timestamp_us``,
#: ``t_ms``) or in brackets (``time [ms]``): seconds per unit.
TIME_UNITS = {"ns": 1e-9, "nsec": 1e-9, "us": 1e-6, "usec": 1e-6, "µs": 1e-6, "ms": 1e-3,
              "msec": 1e-3, "s": 1.0, "sec": 1.0}  # fmt: skip
#: Days, which a time column states in brackets (``time (d)``, ``t [days]``) or by its name
#: (astronomers' Julian dates: ``BJD``, ``MJD``, ``HJD``, Kepler's ``BKJD``, TESS's
#: ``BTJD``; ``days``), never as a bare suffix (``t_d`` may be a dew point): seconds per day.
DAY = {"d": 86400.0}
_DAY_WORDS = ("d", "day", "days")
_DAY_NAME = re.compile(r"(?:[bhm]|bk|bt)?jd(?:_.*)?|days|time_days|time_d")
#: Seconds per unit of every unit a time column is read in.
SECONDS_PER = {**TIME_UNITS, **DAY}
#: Names that say their values are seconds (``seconds_elapsed``): no note that none is stated.
_SECONDS_NAMES = ("seconds", "sec", "secs", "s", "seconds_elapsed", "elapsed_seconds")


#: A run's suffix on a column's name (PASCO Capstone's ``Position (m) Run #2``).
_RUN = re.compile(r"\s*\brun\s*#?\s*(\d+)\s*$", re.IGNORECASE)


def run_of(name: str) -> str | None:
    """The run a column's name ends with (``Time (s) Run #2``: ``"2"``), else None."""
    m = _RUN.search(name)
    return None if m is None else m[1]


def time_unit(name: str) -> str | None:
    """The time unit a column's name states (``time_ns``: ``"ns"``; ``t [ms]``;
    ``Time (ms) Run #1``), else None."""
    name = _RUN.sub("", name)
    m = re.search(r"[\[\(]\s*([^\[\]\(\)]{1,8}?)\s*[\]\)]\s*$", name)
    key = name.strip().lower().replace(" ", "_")  # AndroSensor's "Time since start in ms"
    word = m[1] if m else key.rpartition("_")[2] if "_" in key else ""
    if word in TIME_UNITS:
        return word
    if (m and m[1].strip().lower() in _DAY_WORDS) or _DAY_NAME.fullmatch(time_key(name)):
        return "d"
    # a time word with its unit glued on or next: ArduPilot's TimeUS, autoflpy's Time_US_GPS_..
    if glued := _GLUED_UNIT.match(time_key(name)):
        return glued[1]
    return NAMED_TIME_UNITS.get(time_key(name))


#: ``time``/``timestamp`` followed by a time unit (``timeus``, ``time_us_gps``).
_GLUED_UNIT = re.compile(r"(?:time|timestamp)_?(ns|nsec|us|usec|µs|ms|msec)(?:_|$)")


def _clock_unit(name: str, first: float | None, stated: str | None) -> tuple[str | None, str]:
    """The unit of a time column called ``name`` whose first value is ``first``, and why.

    The unit its name states (or ``stated``, a units row's cell); else the unit in which
    ``first`` is a Unix time of 2000-2100 (:func:`epoch_unit`); else None (seconds).
    """
    if (unit := time_unit(name)) is not None:
        return unit, "its name"
    if stated in TIME_UNITS:
        return stated, "the units row"
    if first is not None and np.isfinite(first):
        return epoch_unit(float(first)), "its values are Unix times in that unit"
    return None, ""


def time_scale(name: str, first: float | None = None, stated: str | None = None) -> float:
    """Seconds per unit of a time column called ``name`` whose first value is ``first``
    (:func:`_clock_unit`; 1 when it has none)."""
    unit = _clock_unit(name, first, stated)[0]
    return 1.0 if unit is None else SECONDS_PER[unit]


#: Unix times from 2000-01-01 to 2100-01-01, in seconds: a time column whose name states no
#: unit is read in the unit (ms, us, ns) that puts its first value in this span.
EPOCH_SPAN = (946_684_800.0, 4_102_444_800.0)


def epoch_unit(first: float) -> str | None:
    """The unit in which ``first`` is a Unix time of 2000-2100 (``"ms"``, ``"us"``, ``"ns"``).

    None when it is none of them (seconds since 1970 need no scaling; a clock from 0 has
    no unit to read off its values).
    """
    lo, hi = EPOCH_SPAN
    for unit in ("ms", "us", "ns"):
        if lo <= first * TIME_UNITS[unit] < hi:
            return unit
    return None


def time_in_seconds(
    columns: dict[str, NDArray],
    time_column: str,
    notes: list[str],
    first: float | None = None,
    stated: str | None = None,
    told: StatedTime | None = None,
    dated: bool = False,
) -> None:
    """Scale ``columns[time_column]`` to seconds (in place, with a note).

    In the unit its name states (``time_ns`` in nanoseconds); a name that states none
    (Kalibr's and EuRoC's ``timestamp``) in the unit in which its first value is a Unix
    time of 2000-2100 (:func:`epoch_unit`: 1.4e18 is nanoseconds). ``first``: the column's
    first value when the column was taken relative to it; ``stated``: the unit a row under
    the header gives it; ``told``: the unit the user states (over the values' Unix time;
    refused against another that the name, the units row or ``dated`` date-times state).
    """
    t = columns[time_column]
    if told is not None:
        named = ("s", 1.0, "date-times") if dated else _named_unit(time_column, stated)
        columns[time_column] = told.times(t, time_column, named, notes)
        return
    raw = first if first is not None else (float(t[0]) if t.size else None)
    unit, why = _clock_unit(time_column, raw, stated)
    if unit is None:
        if not say_if_counting(t, time_column, notes):
            _say_no_unit(raw, time_column, notes)
        return
    if SECONDS_PER[unit] == 1.0:
        return
    columns[time_column] = t * SECONDS_PER[unit]
    notes.append(f"time column {echo(time_column)!r} read in {unit} ({why}), as seconds")


def _named_unit(name: str, stated: str | None) -> tuple[str, float, str] | None:
    """The unit the time column ``name`` states (its name, else the units row's ``stated``),
    its seconds and where it is stated; None when neither does."""
    unit, why = (time_unit(name), "its name") if time_unit(name) else (stated, "the units row")
    if unit not in SECONDS_PER and time_key(name) in _SECONDS_NAMES:
        unit, why = "s", "its name"
    return (unit, SECONDS_PER[unit], why) if unit in SECONDS_PER else None


#: The note on a time column whose unit nothing states, read in seconds.
NO_UNIT_NOTE = (
    "times read from column {!r} as seconds: no unit stated (if they are in another unit, "
    f"state it: {how_to_state()}; or name the column with it: time (ms), time (d), BJD; "
    "or give the sample rate)"
)


def _say_no_unit(first: float | None, name: str, notes: list[str]) -> None:
    """The note that the time column ``name`` is read in seconds with no unit stated: not
    for a name that says seconds (``seconds``, ``time_s``) nor for Unix times in seconds
    (``first`` in :data:`EPOCH_SPAN`), which their values state."""
    lo, hi = EPOCH_SPAN
    if time_key(name) in _SECONDS_NAMES or (first is not None and lo <= first < hi):
        return
    notes.append(NO_UNIT_NOTE.format(echo(name)))


def calendar_step(dt: NDArray) -> str | None:
    """The calendar unit every step of ``dt`` (seconds) is one of (``"month"``: 28-31
    days; :data:`CALENDAR_STEPS`), or None."""
    days = np.asarray(dt, float) / 86400.0
    for unit, (lo, hi) in CALENDAR_STEPS.items():
        if days.size and np.all((days >= lo) & (days <= hi)):
            return unit
    return None


def _period_from_time(t: NDArray, notes: list[str], dated: bool = False) -> float | None:
    """The sample period of the time column ``t`` (seconds), or None (with a note).

    Notes
    -----
    ``dated``: ``t`` was read from date-times, so it is in seconds whatever its step (a
    monthly series' 2.6e6 s is no unit mistake), and steps of a calendar month, quarter or
    year (:func:`calendar_step`) are one period, said, not non-uniform sampling.
    """
    if t.size < 2 or not np.all(np.isfinite(t)):
        notes.append("the time column has missing values: sample period not taken from it")
        return None
    dt = np.diff(t)
    back = dt <= 0
    if np.any(back):
        first = int(np.argmax(back)) + 1
        k = int(np.count_nonzero(back))
        if k > max(1, 0.01 * dt.size):
            notes.append(
                f"the time column is not strictly increasing (row {first}): "
                "sample period not taken from it"
            )
            return None
        # a stamp that repeats or steps back now and then (a logger's clock, a duplicated
        # message): the rate from the other steps; the samples are taken in file order
        notes.append(
            f"the time column repeats or steps back at {k} of {dt.size:,} steps (first at row "
            f"{first}): the samples are taken in file order as if uniform, the sample period "
            "from the other steps"
        )
        dt = dt[~back]  # (t's own decimals still give the stamps' resolution)
    unit = calendar_step(dt) if dated and not np.any(back) else None
    if unit is not None:
        lo_d, hi_d = CALENDAR_STEPS[unit]
        period = float(np.mean(dt))
        notes.append(f"the dates step by a calendar {unit} ({lo_d}-{hi_d} days): one sample a "
                     f"{unit}, taken as uniform (period {period / 86400:.4g} days)")  # fmt: skip
        return period
    clock = None if np.any(back) else clock_period(t, dt)  # stamps rounded: said there
    period = rounded_period(t, float(np.median(dt))) if clock is None else clock[0]
    notes += [] if clock is None else [clock[1]]
    lo, hi = SAMPLE_PERIOD_RANGE
    if not lo <= period <= (np.inf if dated else hi):
        notes.append(
            f"the time column's step ({period:.4g}) is outside {lo:g} s to {hi:g} s: is it in "
            "another unit (milliseconds, nanoseconds)? Sample period not taken from it; set T"
        )
        return None
    spread = float((dt.max() - dt.min()) / period)
    if spread > UNIFORM_TOLERANCE and not np.any(back) and clock is None:  # (else said)
        notes.append(
            f"sampling is not uniform: steps from {dt.min():.4g} s to {dt.max():.4g} s "
            f"(median {period:.4g} s); noise-variance estimates split the record at its gaps "
            "and pool the uniform segments; the Allan deviation places rate samples on their "
            "period when the steps are whole periods (samples dropped), else takes it as "
            "uniform, as the filter fits do"
        )
    return period


def drop_nonfinite_rows(table: LoadedTable) -> LoadedTable:
    """The table without the rows that have an empty, NaN or infinite cell in any column.

    Parameters
    ----------
    table : LoadedTable

    Returns
    -------
    LoadedTable
        A new table (the same one when every cell is finite), with a note saying how many
        rows were dropped; the sample period is kept.
    """
    if not table.columns:
        return table
    keep = np.logical_and.reduce([np.isfinite(c) for c in table.columns.values()])
    dropped = int(keep.size - keep.sum())
    if dropped == 0:
        return table
    if dropped == keep.size:
        raise NoisevarError(f"{echo(table.name)}: every row has an empty or NaN cell")
    cols = {k: v[keep] for k, v in table.columns.items()}
    first = int(np.argmin(keep)) + 1
    note = f"dropped {dropped:,} rows with empty or NaN cells (the first is data row {first})"
    return LoadedTable(
        table.name,
        cols,
        table.kind,
        table.time_column,
        table.sample_period,
        [*table.notes, note],
        dict(table.units),
    )


def signal_summary(z: ArrayLike, sample_period: float | None = None) -> dict[str, float]:
    """A short description of a signal: size, duration, level and spread.

    Parameters
    ----------
    z : array_like, shape (n,)
        Samples.
    sample_period : float, optional
        Seconds per sample (duration is NaN without it).

    Returns
    -------
    dict
        ``n``, ``duration_s``, ``mean``, ``std``, ``min``, ``max``,
        ``n_nonfinite``.
    """
    z = np.asarray(z, dtype=float)
    fin = z[np.isfinite(z)]
    if fin.size == 0:
        raise NoisevarError("the signal has no finite sample")
    return {
        "n": int(z.size),
        "duration_s": float((z.size - 1) * sample_period) if sample_period else float("nan"),
        "mean": float(fin.mean()),
        "std": float(fin.std()),
        "min": float(fin.min()),
        "max": float(fin.max()),
        "n_nonfinite": int(z.size - fin.size),
    }


def table_from_arrays(
    name: str,
    columns: dict[str, ArrayLike],
    sample_period: float | None = None,
    kind: str = "generated",
    notes: list[str] | None = None,
) -> LoadedTable:
    """Wrap arrays already in memory (a generated signal) as a :class:`LoadedTable`.

    Parameters
    ----------
    name : str
        Title of the table.
    columns : dict of str to array_like
        Equal-length columns.
    sample_period : float, optional
        Seconds per sample.
    kind : str
        Recorded in :attr:`LoadedTable.kind`.
    notes : list of str, optional
        Remarks.

    Returns
    -------
    LoadedTable
    """
    cols = {k: np.asarray(v, dtype=float).ravel() for k, v in columns.items()}
    sizes = {v.size for v in cols.values()}
    if len(sizes) != 1:
        raise NoisevarError(f"columns of {name} have different lengths: {sorted(sizes)}")
    return LoadedTable(name, cols, kind, None, sample_period, list(notes or []))
