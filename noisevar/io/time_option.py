"""The unit of a record's times, as the user states it: one option on every surface.

``load_table(..., time_unit="d")``, ``noisevar estimate|fit|allan|imu|batch FILE
--time-unit d``, a config's ``time_unit`` key and the Signal page's control
(:data:`TIME_UNIT_CONTROL`) are this one spec, :data:`TIME_UNIT` (docs/algorithms.md §E8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo
from noisevar.params import ParamSpec

if TYPE_CHECKING:
    from noisevar.io.table import LoadedTable

#: Time units offered and named in messages (any unit of time pint reads is taken).
TIME_UNIT_EXAMPLES = ("s", "ms", "us", "ns", "min", "h", "d")
#: The Signal page's control that states the unit (beside its uploader).
TIME_UNIT_CONTROL = "Time column's unit"


def check_time_unit(text: str) -> str:
    """``text`` stripped when it is a unit of time pint reads (``d``, ``ms``, ``0.5 s``);
    a :class:`NoisevarError` in one line saying what is accepted otherwise."""
    from noisevar.units import parse_unit

    accepted = f"give one pint reads, e.g. {', '.join(TIME_UNIT_EXAMPLES)}"
    try:
        unit = parse_unit(text)
    except NoisevarError:
        unit = None
    if unit is None or unit.si != "second":
        raise NoisevarError(
            f"time unit {echo(text)!r} (--time-unit, config key time_unit) is not a unit of "
            f"time: {accepted}"
        )
    return unit.text


#: The option: ``--time-unit``, the config key and the keyword ``time_unit``.
TIME_UNIT = ParamSpec(
    "time_unit",
    "str",
    None,
    "unit of the time column's values when nothing in the file states it (e.g. "
    f"{', '.join(TIME_UNIT_EXAMPLES)}; default: its name's unit, else seconds); a name that "
    "states another unit is refused",
    check=check_time_unit,
)


def how_to_state(unit: str = "d") -> str:
    """How a note tells the user to state the unit (the CLI flag, the dashboard control)."""
    return f"{TIME_UNIT.flag} {unit} (Signal page: {TIME_UNIT_CONTROL})"


@dataclass(frozen=True)
class StatedTime:
    """A time unit the user stated.

    Attributes
    ----------
    unit : str
        As given (``"d"``).
    seconds : float
        Seconds per unit (86400).
    """

    unit: str
    seconds: float

    def times(
        self, t: NDArray, name: str, named: tuple[str, float, str] | None, notes: list[str]
    ) -> NDArray:
        """The time column ``t`` (called ``name``) in seconds, read in this unit.

        ``named``: the unit the file states for it (its name, a units row, date-times),
        its seconds and where it is stated, or None. A different one is refused in one
        line (neither is guessed right); the same one is read as before.
        """
        if named is not None and not math.isclose(named[1], self.seconds, rel_tol=1e-9):
            raise NoisevarError(
                f"time column {echo(name)!r} states its unit, {named[0]} ({named[2]}), not "
                f"{self.unit}: give {TIME_UNIT.flag} {named[0]} or leave it out"
            )
        if named is None:
            notes.append(
                f"times read from column {echo(name)!r} in {self.unit} (the time unit given), "
                "as seconds"
            )
        return t * self.seconds

    def step(self, key: str, value: float) -> tuple[float, str]:
        """A step a log declares without a unit (an HDF5 dataset's ``dx``), read in this
        unit: the period (seconds) and the note that says so."""
        period = value * self.seconds
        return period, (
            f"its datasets declare {key} = {value:.6g}, read in {self.unit} (the time unit "
            f"given) as the sample period: {period:.6g} s ({1.0 / period:.6g} Hz)"
        )


def stated_time(text: str | None) -> StatedTime | None:
    """The time unit ``text`` (:data:`TIME_UNIT`'s check), None when not given (empty)."""
    if text is None or not str(text).strip():
        return None
    from noisevar.units import parse_unit

    unit = parse_unit(TIME_UNIT.validate(str(text).strip()))
    return StatedTime(unit.text, unit.scale)


def unused_note(told: StatedTime, why: str) -> str:
    """The note that a stated time unit was not used, and ``why``."""
    return f"the time unit given ({told.unit}) is not used: {why}"


def without_clock(table: LoadedTable, told: StatedTime | None) -> LoadedTable:
    """``table``, with a note when a time unit was stated and it has no time column."""
    if told is not None and table.time_column is None:
        table.notes.append(unused_note(told, f"{echo(table.name)} has no time column"))
    return table


def say_if_counting(t: NDArray, name: str, notes: list[str]) -> bool:
    """A note when a time column read in seconds steps by a whole 100 or more: it may count
    microseconds or milliseconds from boot (PX4's ``ulog2csv`` writes ``timestamp`` in
    microseconds), which its values cannot tell from a slow logger's seconds; for a column
    whose unit nothing states (``noisevar.io.table._clock_unit``). Whether it said so."""
    if t.size < 2 or not np.all(np.isfinite(t[:1000])):
        return False
    step = float(np.median(np.diff(t[:1000])))
    if step >= 100 and np.all(t[:1000] == np.round(t[:1000])):
        notes.append(
            f"time column {echo(name)!r} steps by {step:g}, read as seconds ({1 / step:.3g} "
            "Hz): if it counts microseconds or milliseconds (PX4's ulog2csv writes "
            f"microseconds since boot), state its unit ({how_to_state('us')}; or in its "
            "name: timestamp_us) or give the sample rate"
        )
        return True
    return False
