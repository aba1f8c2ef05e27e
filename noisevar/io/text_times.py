"""Time columns written as text: date-times, clocks, and a date column with a clock beside it.

The text-table loader (:mod:`noisevar.io.text`) reads a time column that is not numbers
through :func:`parse_time_strings`, and joins a date column with the clock column after it
(:func:`clock_beside`).
"""

from __future__ import annotations

import re
import warnings
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.io.limits import echo
from noisevar.io.table import DATE_NAMES, time_key

if TYPE_CHECKING:
    import pandas as pd


def parse_time_strings(values: list[str]) -> NDArray | None:
    """Date-times to seconds from the first; None when they are not date-times.

    ISO 8601 first (numpy); else the format pandas guesses from the first value
    (``24-Nov-2023 13:58:58.081`` as MATLAB writes it, ``11/24/2023 13:58:58`` as Excel
    does), with day and month swapped when that format does not read every value.
    """
    try:
        with warnings.catch_warnings():  # "...Z" or "+02:00": numpy converts it to UTC, and
            warnings.simplefilter("ignore", UserWarning)  # says so in a warning to the user
            t = np.array(values, dtype="datetime64[ns]")
    except (ValueError, TypeError, OverflowError):
        t = _guessed_times(values)
        if t is None:
            clock = _clock_times(values)
            return _colon_fraction(values) if clock is None else clock
    if np.any(np.isnat(t)):
        return None
    return (t - t[0]).astype("timedelta64[ns]").astype(float) / 1e9


#: A time of day, ``13:58:58.081`` or, as Physics Toolbox writes it on Android,
#: ``13:58:58:081`` (its milliseconds after a colon); and a minute clock, ``58:58.081``.
_HMS = re.compile(r"(\d{1,2}):(\d{2}):(\d{2})(?:[.:](\d{1,9}))?")
_MS = re.compile(r"(\d{1,3}):(\d{2})\.(\d{1,9})")


def _clock_times(values: list[str]) -> NDArray | None:
    """Times of day (or minute clocks) to seconds from the first; None unless every value is one.

    A clock that steps back by over half its turn has turned (midnight; the hour of a
    minute clock): the turn is added, so the seconds keep rising.
    """
    import pandas as pd

    cells = pd.Series(values, dtype=object).astype(str)
    for pattern, turn in ((_HMS, 86400.0), (_MS, 3600.0)):
        parts = cells.str.extract(f"^(?:{pattern.pattern})$")  # one column per group
        whole = parts.iloc[:, :-1]  # the fraction may be absent; the rest must be there
        if not values or whole.isna().to_numpy().any():
            continue
        clock = whole.astype(int).to_numpy()
        if turn == 3600.0:  # a minute clock: no hours
            clock = np.c_[np.zeros(len(clock), dtype=int), clock]
        fraction = ("0." + parts.iloc[:, -1].fillna("0")).astype(float).to_numpy()
        sec = clock @ np.array([3600.0, 60.0, 1.0]) + fraction
        back = np.diff(sec) < -turn / 2
        sec[1:] += turn * np.cumsum(back)
        return sec - sec[0]
    return None


#: A date-time with its fraction of a second after a colon (``2019-08-06 10:25:50:020``)
_COLON_FRACTION = re.compile(r"(.*\d{1,2}:\d{2}:\d{2}):(\d{1,9})")


def _colon_fraction(values: list[str]) -> NDArray | None:
    """Date-times whose milliseconds follow a colon, read with a point there; None unless
    every value is one.

    Notes
    -----
    GENEActiv's CSV export writes ``2019-08-06 10:25:50:020`` (gaitpy's demo file): the time
    column was refused as "not a number". A time of day alone is :func:`_clock_times`'.
    """
    import pandas as pd

    cells = pd.Series(values, dtype=object).astype(str).str.strip()
    if not values or not cells.str.fullmatch(_COLON_FRACTION.pattern).all():
        return None
    return parse_time_strings(
        cells.str.replace(_COLON_FRACTION.pattern, r"\1.\2", regex=True).tolist()
    )


def _guessed_times(values: list[str]) -> NDArray | None:
    """``values`` in the date-time format pandas guesses from the first or with its day
    and month swapped, as datetime64[ns]; None when neither reads every value.

    Notes
    -----
    When both read every value (no day past the 12th: ``09/01/2016 23:50``,
    ``10/01/2016 00:00``), the reading whose times step back least often, then whose
    largest step is least, is kept: read month-first, brightwind's day-first met-mast file
    stepped 29 days at its first midnight, a gap that is not there.
    """
    import pandas as pd
    from pandas.tseries.api import guess_datetime_format

    if not values:
        return None
    with warnings.catch_warnings():  # "dayfirst=False was specified": the swap is tried next
        warnings.simplefilter("ignore", UserWarning)
        fmt = guess_datetime_format(values[0])
    if fmt is None or "%Y" not in fmt:  # a time of day alone has no date to anchor it
        return None
    swapped = fmt.replace("%m", "\0").replace("%d", "%m").replace("\0", "%d")
    read = []
    for f in dict.fromkeys((fmt, swapped)):
        t = pd.to_datetime(pd.Series(values), format=f, errors="coerce")
        if not t.isna().any():
            read.append(t.dt.tz_localize(None).to_numpy(dtype="datetime64[ns]"))
    return min(read, key=_disorder) if read else None


def _disorder(t: NDArray) -> tuple[int, float]:
    """How far times are from rising evenly: their steps back, then their largest step."""
    steps = np.diff(t.astype("int64")).astype(float)
    return int(np.sum(steps < 0)), float(np.max(steps, initial=0.0))


#: A date column's name with its time zone (Sheffield Solar's ``datetime_gmt``).
_DATE_NAME = re.compile(r"(?:" + "|".join(DATE_NAMES) + r")(?:_(?:utc|gmt|local|tz))?")


def is_date_name(name: str) -> bool:
    """A name of :data:`DATE_NAMES`, perhaps with its time zone (``datetime_gmt``,
    ``Date (UTC)``): the time column when it holds date-times."""
    return _DATE_NAME.fullmatch(time_key(name)) is not None


#: A date with no time of day, its parts split by ``-``, ``/`` or ``.`` (``2000/1/1``).
_DAY = re.compile(r"\d{1,4}[-/.]\d{1,2}[-/.]\d{1,4}")
#: A clock column beside a date column (MIDC's ``DATE (MM/DD/YYYY)``, ``MST``: ``13:58``).
_CLOCK = re.compile(r"\d{1,2}:\d{2}(?::\d{2}(?:\.\d{1,9})?)?")


def clock_beside(
    df: pd.DataFrame, names: list[str], time_idx: int | None
) -> tuple[NDArray, str] | None:
    """The times of a date column joined with the clock column right after it (seconds from
    the first) and a note; None unless the time column holds dates without a time of day
    (named as a date column, or each cell a date: ``2000/1/1``) and the next column a time
    of day in every cell.

    Notes
    -----
    A Mini-Mitter logger's export (pyActigraphy's TAL file) names its columns ``Data`` and
    ``Hora`` (Portuguese): the dates alone were its time, and the file was refused as 1,440
    stacked series, one per time of day.
    """
    if time_idx is None or time_idx + 1 >= len(names):
        return None
    dates, clocks = df[time_idx].astype(str).str.strip(), df[time_idx + 1].astype(str).str.strip()
    if not (is_date_name(names[time_idx]) or dates.str.fullmatch(_DAY.pattern).all()):
        return None
    if not (clocks.str.fullmatch(_CLOCK.pattern).all() and not dates.str.contains(":").any()):
        return None
    times = parse_time_strings((dates + " " + clocks).tolist())
    if times is None:
        return None
    note = (
        f"date column {echo(names[time_idx])!r} and clock column {echo(names[time_idx + 1])!r} "
        "joined into one time"
    )
    return times, note


#: A date column's name that spells its digits' format: ``YYYYMMDD`` (KNMI), ``AAAAMMJJ``
#: (Météo-France), ``JJJJMMTT``, with the hour, minute and second after it (``AAAAMMJJHH``).
_DIGITS_NAME = re.compile(r"(?:yyyy|aaaa|jjjj)mm(?:dd|jj|tt)(?:hh(?:mm(?:ss)?)?)?")
#: A date and time written as digits, by their count (``20250101``, ``2025010113``).
_DIGITS_FORMAT = {8: "%Y%m%d", 10: "%Y%m%d%H", 12: "%Y%m%d%H%M", 14: "%Y%m%d%H%M%S"}


def digit_date_format(name: str, cell: str) -> str | None:
    """The format of a date written as digits (``20250101``: ``%Y%m%d``) when column ``name``
    is a date column (its name spells the format, ``AAAAMMJJ``, or is a date name, ``DATE``)
    and ``cell`` is such a date; else None.

    Notes
    -----
    Météo-France's, KNMI's and ECA&D's daily climate files write their dates this way: read
    as a number, the date was a measured column and the record had no time.
    """
    spelt = _DIGITS_NAME.fullmatch(time_key(name))
    if spelt is None and not is_date_name(name):
        return None
    cell = str(cell).strip().strip('"')
    fmt = _DIGITS_FORMAT.get(len(cell)) if cell.isdigit() else None
    if fmt is None or (spelt is not None and len(spelt.group(0)) != len(cell)):
        return None
    return fmt if digit_dates([cell], fmt) is not None else None


def is_digit_date_name(name: str) -> bool:
    """A column name that spells a date's digits (``AAAAMMJJ``, ``YYYYMMDDHH``)."""
    return _DIGITS_NAME.fullmatch(time_key(name)) is not None


def digit_time_column(col: pd.Series, cname: str, name: str) -> NDArray | None:
    """The time column ``cname`` of file ``name`` in seconds from its first row, when it
    holds dates written as digits (:func:`digit_date_format`, from its first cell); else None.

    Raises
    ------
    NoisevarError
        When a later cell is not such a date (empty, or no calendar day).
    """
    import pandas as pd

    from noisevar.errors import NoisevarError

    if col.empty or not (is_digit_date_name(cname) or is_date_name(cname)):
        return None
    num = pd.to_numeric(col, errors="coerce").to_numpy(dtype=float, na_value=np.nan)
    whole = np.isfinite(num) & (num == np.round(num))  # 20250101.0: pandas' float column
    fmt = digit_date_format(cname, str(int(num[0])) if whole[0] else str(col.iloc[0]))
    if fmt is None:
        return None
    cells = [str(int(n)) if w else str(v).strip() for v, n, w in zip(col, num, whole, strict=True)]
    t = digit_dates(cells, fmt)
    if t is None:
        series = pd.Series(cells)
        read = pd.to_datetime(series, format=fmt, errors="coerce")
        digits = series.str.fullmatch(r"\d+").to_numpy(dtype=bool)  # '-20250101' is none
        wrong = np.flatnonzero(read.isna().to_numpy() | ~whole | ~digits)
        bad = int(wrong[0]) if wrong.size else 0
        raise NoisevarError(
            f"{echo(name)}: column {echo(cname)!r} holds dates written as digits "
            f"({cells[0]}), but data row {bad + 1} holds {echo(cells[bad], 20)!r}: "
            "correct or delete that row"
        )
    return t


def digit_dates(values: list[str], fmt: str) -> NDArray | None:
    """Dates written as digits in ``fmt`` (:func:`digit_date_format`) to seconds from the
    first; None unless every value is one."""
    import pandas as pd

    cells = pd.Series(values, dtype=object).astype(str).str.strip()
    if not values or not cells.str.fullmatch(r"\d+").all():
        return None
    t = pd.to_datetime(cells, format=fmt, errors="coerce")
    if t.isna().any():
        return None
    ns = t.to_numpy(dtype="datetime64[ns]")
    return (ns - ns[0]).astype("timedelta64[ns]").astype(float) / 1e9
