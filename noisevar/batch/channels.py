"""Which channels of a table to estimate: ``"all"``, a list, or the first data column.

Shared by ``noisevar batch``, ``noisevar estimate --columns`` and the dashboard's channel
tables: the ``columns`` argument (a string from the command line or a config, or a list from
Python) is parsed once by :func:`parse_columns`, then resolved against each loaded table by
:func:`table_channels`; :func:`channel_estimates` estimates them as every path does.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from noisevar.errors import NoisevarError
from noisevar.io.column_kinds import not_measured
from noisevar.io.table import is_time_column

if TYPE_CHECKING:
    from noisevar.estimators.results import VarianceEstimate
    from noisevar.io import LoadedTable

__all__ = [
    "LEFT_OUT",
    "all_refused",
    "channel_estimates",
    "channels_and_left_out",
    "left_out_rows",
    "parse_columns",
    "skipped_columns",
    "skipped_note",
    "table_channels",
]


def parse_columns(columns: str | Sequence[str] | None) -> str | list[str] | None:
    """``"all"``, ``None`` (the first data column) or a list of column names.

    Parameters
    ----------
    columns : str, sequence of str or None
        ``"all"``, a comma-separated list ``"a,b,c"``, a list of names, or None.

    Returns
    -------
    "all", list of str or None

    Raises
    ------
    NoisevarError
        An empty list of names.
    """
    if columns is None:
        return None
    if isinstance(columns, str):
        if columns.strip().lower() == "all":
            return "all"
        names = [c.strip() for c in columns.split(",") if c.strip()]
    else:
        names = [str(c) for c in columns]
    if not names:
        raise NoisevarError("no column given: name the columns (a,b,c) or say 'all'")
    return names


def table_channels(table: LoadedTable, columns: str | list[str] | None) -> list[str | None]:
    """The channel names of ``table`` that :func:`parse_columns`'s result selects
    (:func:`channels_and_left_out`'s first part)."""
    return channels_and_left_out(table, columns)[0]


def channels_and_left_out(
    table: LoadedTable, columns: str | list[str] | None
) -> tuple[list[str | None], dict[str, str]]:
    """The channel names of ``table`` that :func:`parse_columns`'s result selects, and the
    columns ``"all"`` left out with why.

    Parameters
    ----------
    table : LoadedTable
        A loaded file (:func:`noisevar.io.load_table`).
    columns : "all", list of str or None
        From :func:`parse_columns`.

    Returns
    -------
    names : list of str or None
        Every data column for ``"all"`` but one named like a time (a second clock) and
        those :func:`skipped_columns` leaves out; the
        first that varies for None (``[None]`` when the table has none: the reader then
        picks or refuses); the names as given otherwise (a missing one is refused when it
        is read).
    left_out : dict of str to str
        For ``"all"``, :func:`skipped_columns`; empty otherwise.

    Raises
    ------
    NoisevarError
        ``"all"`` of a table with no data column, or none but flags, codes and clock times.

    Notes
    -----
    ``"all"`` leaves out flags, codes and clock times; ``noisevar estimate`` and
    ``noisevar batch`` give each a row with its reason (:func:`skipped_note`).
    """
    if columns == "all":  # not a second clock (PASCO's "Time (s) Run #2"): no signal
        names: list[str | None] = [c for c in table.data_columns if not is_time_column(c)]
        if not names:
            raise NoisevarError(f"{table.name} has no data column (only a time column)")
        skip = skipped_columns(table)
        if all(c in skip for c in names):
            said = "; ".join(f"{c!r}: {why}" for c, why in skip.items())
            raise NoisevarError(f"{table.name} has no measured column ({said}): name one")
        return [c for c in names if c not in skip], skip
    if columns is None:
        return ([table.first_signal] if table.data_columns else [None]), {}
    return list(columns), {}


def skipped_columns(table: LoadedTable) -> dict[str, str]:
    """The data columns ``"all"`` leaves out, each with why: flags, codes and clock times
    (:func:`noisevar.io.column_kinds.not_measured`), which the dashboard's channel picker
    leaves out too (``LoadedTable.signals``).

    Parameters
    ----------
    table : LoadedTable

    Returns
    -------
    dict of str to str
        Column name -> reason, in the table's order.
    """
    import numpy as np

    out = {}
    for c in table.data_columns:
        z = table.columns[c]
        if c in table.side_columns:  # the file's format says what it is
            out[c] = f"{table.side_columns[c]}, not a measured signal"
        elif (why := not_measured(z[np.isfinite(z)])) is not None:
            out[c] = why
    return out


#: How a left-out column's row begins (:func:`skipped_note`), that a count can tell it from
#: a channel that failed.
LEFT_OUT = "left out by --columns all"


def left_out_rows(errors: Sequence[Any]) -> list[bool]:
    """Which rows of a batch table's ``error`` column are columns ``"all"`` left out
    (:func:`skipped_note`), not channels that failed."""
    return [isinstance(e, str) and e.startswith(LEFT_OUT) for e in errors]


def skipped_note(why: str) -> str:
    """A column's row where ``"all"`` left it out (:func:`skipped_columns`'s reason ``why``):
    said in its place, as a refused channel's reason is, with how to read it anyway."""
    return f"{LEFT_OUT}: {why}; name the column to estimate it"


def channel_estimates(
    table: LoadedTable,
    names: Sequence[str | None],
    method: str | None = None,
    params: Mapping[str, Any] | None = None,
) -> list[VarianceEstimate | str]:
    """Each channel's estimate, with the table's times, or the reason it has none.

    Parameters
    ----------
    table : LoadedTable
        A loaded file.
    names : sequence of str or None
        Its channels (:func:`table_channels`).
    method : str, optional
        Estimator (default :data:`noisevar.estimators.DEFAULT_METHOD`).
    params : mapping, optional
        Its parameters (``drop_nonfinite`` keeps non-finite cells as gaps).

    Returns
    -------
    list of VarianceEstimate or str
        In the order of ``names``; a channel that cannot be estimated (constant, too short,
        empty cells, unknown) gives its error message instead.

    Notes
    -----
    Each channel is read by :func:`noisevar.io.channel_record` (the table's times: a
    record with gaps is split at them), so that it gets the same answer as alone. The
    channels are estimated in one 2-D call when they all can be (vectorised where the
    method allows), else one by one.
    """
    import numpy as np

    from noisevar.estimators import DEFAULT_METHOD, estimate
    from noisevar.io import channel_record

    method = method or DEFAULT_METHOD
    kw = dict(params or {})
    drop = bool(kw.get("drop_nonfinite", False))
    read: list[Any] = []
    for name in names:
        try:
            read.append(channel_record(table, name, drop_nonfinite=drop))
        except NoisevarError as exc:
            read.append(str(exc))
    ok = [r for r in read if not isinstance(r, str)]
    # one 2-D estimate for two channels or more (one row of 2-D is one signal: estimate
    # returns it alone, not a list)
    if len(ok) > 1 and len(ok) == len(read) and len({z.size for z, _ in ok}) == 1:
        try:
            stacked = np.stack([z for z, _ in ok])
            return list(estimate(stacked, method=method, t=ok[0][1], **kw))
        except NoisevarError:
            pass  # one channel refused: each on its own, to say which
    out: list[VarianceEstimate | str] = []
    for r in read:
        try:
            out.append(r if isinstance(r, str) else estimate(r[0], method=method, t=r[1], **kw))
        except NoisevarError as exc:
            out.append(str(exc))
    return out


#: A reason's kind: its quoted names and numbers masked
_NAMES_NUMBERS = re.compile(r"'[^']*'|\d[\d.,]*")


def all_refused(names: Sequence[str], reasons: Sequence[str]) -> str:
    """The refusal when every channel of ``names`` is refused: the first reason, and the
    first of another kind after it (one line).

    Notes
    -----
    An Actiware export cut to its epoch table (pyActigraphy's French file) starts with a
    line counter and a seconds counter; its measured columns hold a few NaN. With
    ``--columns all`` the refusal gave only the counter's reason, not that
    ``--drop-nonfinite`` reads the others.
    """
    first = f"column {names[0]!r}: {reasons[0]}"
    kind = _NAMES_NUMBERS.sub("#", reasons[0])
    other = next(((n, r) for n, r in zip(names, reasons, strict=True)
                  if _NAMES_NUMBERS.sub("#", r) != kind), None)  # fmt: skip
    if other is None:
        return first
    return f"no column could be estimated: {first}; column {other[0]!r}: {other[1]}"
