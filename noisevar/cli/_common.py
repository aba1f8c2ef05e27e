"""Helpers shared by the CLI's sub-commands: one-line errors, JSON output, loading a column."""

from __future__ import annotations

import argparse
import json
import math
import os
from typing import TYPE_CHECKING, Any, NoReturn

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.logs import log_kinds

if TYPE_CHECKING:
    import numpy as np

    from noisevar.io import LoadedTable

EXIT_ERROR = 2


class Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line, like every other error."""

    def error(self, message: str) -> NoReturn:
        raise NoisevarError(f"{message} (see '{self.prog} --help')")


#: Longest error line the CLI prints (a backstop: messages already shorten echoed fields).
MAX_LINE = 2000


def json_default(obj: Any) -> Any:
    import numpy as np  # here: the CLI refuses bad input before NumPy is imported

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def strict_json(obj: Any) -> Any:
    """``obj`` as strict JSON: NaN becomes ``None`` (``null``: missing), ±inf ``"inf"``/``"-inf"``.

    Parameters
    ----------
    obj : object
        Dicts, lists, tuples, numbers, NumPy scalars and arrays.

    Returns
    -------
    object
        The same structure, strict-JSON safe.
    """
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): strict_json(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [strict_json(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return strict_json(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and math.isnan(obj):
        return None
    if isinstance(obj, float) and math.isinf(obj):
        return "inf" if obj > 0 else "-inf"  # e.g. trim=inf ("no trimming"), as configs write it
    return obj


def print_json(data: dict) -> None:
    """Print ``data`` as strict JSON: never a bare ``NaN`` or ``Infinity`` token."""
    print(json.dumps(strict_json(data), indent=2, default=json_default, allow_nan=False))


def one_line(message: str) -> str:
    """An error message as one safe terminal line: control characters escaped, length capped."""
    return echo(" ".join(str(message).splitlines()), MAX_LINE)


def add_drop_flag(p: argparse.ArgumentParser) -> None:
    """``--drop-nonfinite``, as ``estimate`` has it (its one spec: ``PARAMS``), for a command
    that reads one channel: the refusal of empty cells tells users to give it."""
    from noisevar.estimators.params import PARAMS

    PARAMS["drop_nonfinite"].add_to(p, default=False)


def add_topic_flag(p: argparse.ArgumentParser) -> None:
    """``--topic T``: the topic of a log to read (its field is chosen by ``--column``)."""
    p.add_argument(
        "--topic",
        help=f"for a log ({log_kinds()}): the topic, message or sheet to read "
        "('noisevar topics LOG' lists them); --column picks its field",
    )


def add_time_unit_flag(p: argparse.ArgumentParser) -> None:
    """``--time-unit U``: the unit of the time column's values (its one spec:
    :data:`noisevar.io.time_option.TIME_UNIT`)."""
    from noisevar.io.time_option import TIME_UNIT

    TIME_UNIT.add_to(p)


def time_unit_of(args: argparse.Namespace, params: dict[str, Any]) -> str | None:
    """``--time-unit``, else the config's ``time_unit`` (taken out of ``params``)."""
    from noisevar.io.time_option import TIME_UNIT

    said = params.pop(TIME_UNIT.name, None)
    return TIME_UNIT.validate(args.time_unit if args.time_unit is not None else said)


def add_series_flag(p: argparse.ArgumentParser) -> None:
    """``--series LABEL``: the series to read of a file that stacks several (its one spec:
    :data:`noisevar.io.series_option.SERIES`)."""
    from noisevar.io.series_option import SERIES

    SERIES.add_to(p)


def series_of(args: argparse.Namespace, params: dict[str, Any]) -> str | None:
    """``--series``, else the config's ``series`` (taken out of ``params``)."""
    from noisevar.io.series_option import SERIES, checked_series

    said = params.pop(SERIES.name, None)
    return checked_series(args.series if args.series is not None else said)


def load_file(
    path: str, topic: str | None = None, time_unit: str | None = None, series: str | None = None
) -> LoadedTable:
    """A data file, or one topic of a log (``topic``), as a table (times in ``time_unit``
    where the file states none; the rows of one ``series`` of a file that stacks several:
    :func:`noisevar.io.load_table`)."""
    from noisevar.io import load_table

    name = os.path.basename(os.path.normpath(path))
    return load_table(path, name, topic=topic, time_unit=time_unit, series=series)


def load_signal(
    path: str,
    column: str | None,
    drop_nonfinite: bool = False,
    topic: str | None = None,
    time_unit: str | None = None,
) -> tuple[np.ndarray, int]:
    """One column of a data file (or of a log's ``topic``) as floats, and how many non-finite
    cells were dropped.

    Empty/NaN/Inf cells are refused (naming the first row) unless
    ``drop_nonfinite``.
    """
    import numpy as np

    from noisevar.io import pick_column

    table = load_file(path, topic, time_unit)
    z = np.asarray(pick_column(table, column, drop_nonfinite=drop_nonfinite), dtype=float)
    return z, table.n_rows - z.size


def load_record(
    path: str, column: str | None, drop_nonfinite: bool = False, topic: str | None = None
) -> tuple[np.ndarray, np.ndarray | None, list[str]]:
    """One column of a data file (or of a log's ``topic``) with its sample times (if the
    file has a time column; a log always has its timestamps) and the loader's notes.

    As every estimating path reads a channel: :func:`noisevar.io.channel_record`.
    """
    from noisevar.io import channel_record

    table = load_file(path, topic)
    z, t = channel_record(table, column, drop_nonfinite=drop_nonfinite)
    return z, t, list(table.notes)


def sample_rate(given: float | None, sample_period: float | None) -> float:
    """The ``--rate`` flag, else the rate of the file's time column; refuse anything else."""
    if given is None:
        if sample_period:
            return 1.0 / sample_period
        raise NoisevarError(
            "give the sample rate with --rate HZ (the file has no time column that gives one)"
        )
    if not (math.isfinite(given) and given > 0):
        raise NoisevarError(f"--rate must be a positive number of Hz, not {given:g}")
    return given


def add_regimes_flag(p: argparse.ArgumentParser) -> None:
    """``--regimes {all,still}``: fit the whole record or its longest still stretch."""
    from noisevar.estimators.regimes import DEFAULT_REGIMES, REGIMES

    p.add_argument(
        "--regimes",
        choices=list(REGIMES),
        help=f"fit the whole record (all) or its longest still stretch (still); default "
        f"{DEFAULT_REGIMES}",
    )


def regimes_of(args: argparse.Namespace) -> dict[str, str]:
    """``{"regimes": ...}`` when ``--regimes`` was given, else nothing (the function's default)."""
    return {} if args.regimes is None else {"regimes": args.regimes}


def add_unit_flags(p: argparse.ArgumentParser) -> None:
    """``--unit U`` (the data's unit) and ``--unit-out U`` (convert every value to it)."""
    from noisevar.units import EXAMPLES

    p.add_argument(
        "--unit",
        help=f"unit of the data, e.g. {', '.join(EXAMPLES[:6])}; raw counts with a scale "
        "factor as '0.00875 deg/s' (default: none, printed as 'u')",
    )
    p.add_argument(
        "--unit-out", help="convert the data to this unit first (e.g. deg/s data to rad/s)"
    )


def units_of(given: str | None, out: str | None, declared: str | None = None) -> tuple[float, str]:
    """The factor to apply to the data and the unit the results are in (``"u"``: none):
    the user's unit ``given``, else the one the file ``declared`` for the column. A declared
    unit pint does not read labels the results as written and is never converted.

    Bad or mismatched units: ``NoisevarError`` naming the unit (exit 2).
    """
    from noisevar.units import UNKNOWN, declared_unit, factor, parse_unit, unit_label

    if not given and out is None:  # the file's unit as written: pint reads it or not
        return 1.0, unit_label(declared) or UNKNOWN
    unit, target = parse_unit(given or declared_unit(declared)), parse_unit(out)
    if target is not None and unit is None:
        said = unit_label(declared)
        raise NoisevarError(
            f"the file's unit {said!r} is not one pint reads: give --unit, the unit the data "
            "are in, to convert them"
            if said
            else "--unit-out needs --unit: the unit the data are in"
        )
    if target is None:
        return 1.0, unit.text if unit else UNKNOWN
    return factor(unit.text, target.text), target.text
