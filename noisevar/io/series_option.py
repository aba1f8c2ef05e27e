"""One series of a file that stacks several (the long format), by its label: one option on
every surface.

``load_table(..., series="Subject 2")``, ``noisevar estimate|fit|allan|imu|batch FILE
--series 'Subject 2'``, a config's ``series`` key and the Signal page's picker
(:data:`SERIES_CONTROL`, offered when a load fails with
:class:`~noisevar.errors.StackedSeries`) are this one spec, :data:`SERIES`
(docs/algorithms.md §E8, *One series by its label*).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.io.time_option import TIME_UNIT
from noisevar.params import ParamSpec

if TYPE_CHECKING:
    import pandas as pd

#: Labels a :class:`~noisevar.errors.StackedSeries` keeps (the picker's choices) and,
#: fewer, those a message lists.
MAX_LABELS = 200
#: Labels a refusal of an unknown label lists.
LISTED = 10
#: The Signal page's control that picks the series (under its uploader).
SERIES_CONTROL = "Series to read"


def check_series(text: str) -> str:
    """``text`` stripped; an empty label is refused in one line."""
    label = text.strip()
    if not label:
        raise NoisevarError("series (--series, config key series) is empty: give a label")
    return label


#: The option: ``--series``, the config key and the keyword ``series``.
SERIES = ParamSpec(
    "series",
    "str",
    None,
    "for a file that stacks several series (a text column naming each row's series, the "
    "time falling back or repeating where it changes): the label of the one to read",
    check=check_series,
)


def kept_labels(column: str, labels: list) -> tuple[str, tuple[str, ...], int]:
    """The arguments of :class:`~noisevar.errors.StackedSeries` after its message: the
    column, its first :data:`MAX_LABELS` labels (as text) and how many it holds."""
    return column, tuple(str(v) for v in labels[:MAX_LABELS]), len(labels)


def _listed(labels: list, n: int) -> str:
    shown = ", ".join(repr(echo(str(v), 20)) for v in labels[:n])
    return f"{shown}{', ...' if len(labels) > n else ''}"


def stacked_message(name: str, column: str, labels: list) -> str:
    """The refusal of a file ``name`` that stacks ``labels``' series on ``column``: it
    names the way to read one (:data:`SERIES`, the Signal page's picker, a file of its own)."""
    col = repr(echo(column))
    first = repr(echo(str(labels[0]), 20))
    return (
        f"{echo(name)} stacks {len(labels)} series, one per value of column {col} "
        f"({_listed(labels, 3)}), its time falling back or repeating where the value "
        f"changes: give one series: {SERIES.flag} {first} (Signal page: {SERIES_CONTROL}), "
        f"or the rows of one {col} saved as their own file"
    )


def not_stacked(name: str, series: str | None, what: str = "") -> None:
    """Refuse a label ``series`` given for a file ``name`` that holds one series (``what``:
    why, e.g. ``" (a log)"``), in one line; nothing when none was given."""
    if series is not None:
        raise NoisevarError(
            f"{echo(name)} holds one series{what}: leave {SERIES.flag} ({echo(series, 40)!r}) out"
        )


def series_rows(
    key: pd.Series, label: str, column: str, name: str, notes: list[str]
) -> NDArray[np.bool_]:
    """Which rows of the stacking column ``key`` (called ``column``) hold ``label``, with
    the note that says which were read; an absent label is refused in one line that lists
    some of those present (echo-bounded: they are the file's)."""
    text = key.map(lambda v: str(v).strip()).to_numpy()
    rows = text == label
    labels = list(dict.fromkeys(text.tolist()))
    if not rows.any():
        raise NoisevarError(
            f"{echo(name)}: no row has {echo(column)!r} = {echo(label, 40)!r} "
            f"({SERIES.flag}); its {len(labels)} series: {_listed(labels, LISTED)}"
        )
    notes.append(
        f"read the rows of {echo(column)} = {echo(label, 40)!r} (1 of {len(labels)} series, "
        f"{int(rows.sum()):,} of {rows.size:,} rows), in file order"
    )
    return rows


def checked_series(series: str | None) -> str | None:
    """``series`` as :data:`SERIES` takes it, None when not given (None or empty)."""
    if series is None or not str(series).strip():
        return None
    return SERIES.validate(str(series))


#: How a file was read, kept in a config (for the commands that read it again: not
#: estimator parameters) and in batch's resume key: the time unit stated and the series picked.
READING = {TIME_UNIT.name: TIME_UNIT, SERIES.name: SERIES}


def how_read(time_unit: str | None, series: str | None) -> dict[str, str]:
    """The :data:`READING` keys given (not empty), as a config carries them."""
    return {k: v for k, v in zip(READING, (time_unit, series), strict=True) if v}
