"""Helpers shared by the CLI's sub-commands: one-line errors, JSON output, loading a column."""

from __future__ import annotations

import argparse
import json
import math
import os
from typing import TYPE_CHECKING, Any, NoReturn

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

if TYPE_CHECKING:
    import numpy as np

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


def load_signal(
    path: str, column: str | None, drop_nonfinite: bool = False
) -> tuple[np.ndarray, int]:
    """One column of a data file as floats, and how many non-finite cells were dropped.

    Empty/NaN/Inf cells are refused (naming the first row) unless
    ``drop_nonfinite``.
    """
    import numpy as np

    from noisevar.io import load_table, pick_column

    table = load_table(path, os.path.basename(path))
    z = np.asarray(pick_column(table, column, drop_nonfinite=drop_nonfinite), dtype=float)
    return z, table.n_rows - z.size


def load_record(
    path: str, column: str | None, drop_nonfinite: bool = False
) -> tuple[np.ndarray, np.ndarray | None, list[str]]:
    """One column of a data file with its sample times (if the file has a time column).

    Returns the values (non-finite cells kept when ``drop_nonfinite``, for the estimator
    to treat as gaps; refused otherwise), the times or None, and the loader's notes.
    """
    import numpy as np

    from noisevar.io import load_table, pick_column
    from noisevar.io.load import column_values

    table = load_table(path, os.path.basename(path))
    if drop_nonfinite:
        z = column_values(table, column)
    else:
        z = np.asarray(pick_column(table, column), dtype=float)
    t = table.time()
    if t is not None:
        t = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
            t = None  # the loader's note says why; the samples are taken as uniform
    return z, t, list(table.notes)


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


def units_of(given: str | None, out: str | None) -> tuple[float, str]:
    """The factor to apply to the data and the unit the results are in (``"u"``: none).

    Bad or mismatched units: ``NoisevarError`` naming the unit (exit 2).
    """
    from noisevar.units import UNKNOWN, factor, parse_unit

    unit, target = parse_unit(given), parse_unit(out)
    if target is not None and unit is None:
        raise NoisevarError("--unit-out needs --unit: the unit the data are in")
    if target is None:
        return 1.0, unit.text if unit else UNKNOWN
    return factor(unit.text, target.text), target.text
