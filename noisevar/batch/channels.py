"""Which channels of a table to estimate: ``"all"``, a list, or the first data column.

Shared by ``noisevar batch`` and ``noisevar estimate --columns``: the ``columns`` argument
(a string from the command line or a config, or a list from Python) is parsed once by
:func:`parse_columns`, then resolved against each loaded table by :func:`table_channels`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from noisevar.errors import NoisevarError

if TYPE_CHECKING:
    from noisevar.io import LoadedTable

__all__ = ["parse_columns", "table_channels"]


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
    """The channel names of ``table`` that :func:`parse_columns`'s result selects.

    Parameters
    ----------
    table : LoadedTable
        A loaded file (:func:`noisevar.io.load_table`).
    columns : "all", list of str or None
        From :func:`parse_columns`.

    Returns
    -------
    list of str or None
        Every data column for ``"all"``; the first data column for None (``[None]`` when
        the table has none: the reader then picks or refuses); the names as given
        otherwise (a missing one is refused when it is read).

    Raises
    ------
    NoisevarError
        ``"all"`` of a table with no data column.
    """
    if columns == "all":
        names: list[str | None] = list(table.data_columns)
        if not names:
            raise NoisevarError(f"{table.name} has no data column (only a time column)")
        return names
    if columns is None:
        return [table.data_columns[0]] if table.data_columns else [None]
    return list(columns)
