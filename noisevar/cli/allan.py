"""``noisevar allan FILE --rate HZ``: the Allan deviation of one column (docs/algorithms.md §E4)."""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any

import numpy as np

from noisevar.cli._common import (
    add_regimes_flag,
    add_series_flag,
    add_time_unit_flag,
    add_topic_flag,
    add_unit_flags,
    load_file,
    print_json,
    regimes_of,
    sample_rate,
    units_of,
)
from noisevar.errors import NoisevarError
from noisevar.io.limits import echo


def sampling_note(t: np.ndarray | None, rate: float) -> list[str]:
    """A note when the times ``t`` are not uniform and the samples were taken as uniform
    at ``rate`` (not placed on a grid of whole periods: :func:`noisevar.allan`'s ``t``)."""
    from noisevar.diagnostics.segments import off_period

    if t is None or t.size < 3:
        return []
    steps = off_period(t)
    off = int(np.count_nonzero(steps))
    if not off:
        return []
    return [
        f"{off} of {steps.size} steps of the times are not the median one and are not whole "
        f"multiples of one period (jitter, or --rate given): the Allan variance takes the "
        f"samples as uniform at {rate:g} Hz, so its taus are in samples at that rate, not "
        "in the record's seconds"
    ]


#: The refusal of empty cells by the commands that need every sample in its place.
EVERY_SAMPLE = (
    "fill them, or cut the record there: the Allan deviation and the noise terms need every "
    "sample in its place (dropping cells would close the gaps)"
)


def load_columns(
    path: str,
    columns: list[str] | None,
    rate: float | None,
    topic: str | None = None,
    time_unit: str | None = None,
    series: str | None = None,
):
    """The chosen columns of a data file or of a log's ``topic`` (its signals by default:
    :attr:`noisevar.io.LoadedTable.signals`), the sample rate, each column's unit as the
    file declares it (or None), and the sample times every estimating path takes
    (:func:`noisevar.io.record_times`), and the loader's notes; ``time_unit``: the unit
    of the time column's values (``--time-unit``); ``series``: the series read of a file
    that stacks several (``--series``)."""
    from noisevar.io import pick_column, record_times

    table = load_file(path, topic, time_unit, series)
    # by default every signal: not a log's constant fields, counters or second clock
    names = columns or table.signals or list(table.data_columns)
    if not columns and names:  # a table of runs (PASCO's): the first run's
        names = [c for c in names if table.clock_of(c) == table.clock_of(names[0])]
    clocks = {table.clock_of(c) for c in names}
    if len(clocks) > 1:  # PASCO's runs: one clock each
        raise NoisevarError(
            f"the columns {echo(', '.join(names))} have {len(clocks)} clocks (one per run): "
            "give the columns of one run (--column)"
        )
    data = {c: np.asarray(pick_column(table, c, fix=EVERY_SAMPLE), dtype=float) for c in names}
    declared = {c: table.units.get(c) for c in names}
    rate = sample_rate(rate, table.period_of(names[0]) if names else table.sample_period)
    return data, rate, declared, record_times(table, names[0] if names else None), list(
        table.notes
    )


def _cmd_allan(args: argparse.Namespace) -> int:
    from noisevar.noise_model import allan
    from noisevar.noise_model.allan import default_data
    from noisevar.noise_model.allan_gaps import gap_grid

    wanted = [args.column] if args.column else None
    data, rate, declared, times, loaded = load_columns(
        args.file, wanted, args.rate, args.topic, args.time_unit, args.series
    )
    name, z = next(iter(data.items()))
    scale, unit = units_of(args.unit, args.unit_out, declared[name])
    kind_of_data = args.data or default_data(unit)
    # times whose steps are whole periods (samples dropped): rate data on that grid
    t = None if args.rate is not None else times  # --rate: the samples as uniform at it
    res = allan(z * scale, rate, kind_of_data, args.kind, t=t, **regimes_of(args))
    if gap_grid(t, kind_of_data, args.kind, **regimes_of(args)) is None:
        res = dataclasses.replace(res, notes=(*res.notes, *sampling_note(times, rate)))
    if args.data is None:
        other = "rate" if kind_of_data == "phase" else "phase"
        said = (
            f"{kind_of_data} data: the default for unit {unit} (--data {other} otherwise: "
            "phase is a time error or an angle, rate a gyro's rate, a specific force or a "
            "fractional frequency)"
        )
        res = dataclasses.replace(res, notes=(said, *res.notes))
    # rate data: the deviation is in the data's unit; phase data: the phase's unit per second
    dev_unit = unit if kind_of_data == "rate" else f"{unit}/s"
    if args.format == "json":
        print_json({"column": name, "unit": dev_unit, **res.to_dict(), "file_notes": loaded})
        return 0
    for note in loaded:  # how the file was read: its clock, its unit, columns left out
        print(f"file note: {note}")
    print(
        f"{res.kind} of {name} ({kind_of_data} data, {res.n_samples} samples at {res.rate:g} Hz), "
        f"{res.ci:.1%} intervals; deviations in {dev_unit}, tau in s"
    )
    for note in res.notes:
        print(f"note: {note}")
    print(
        f"{'tau (s)':>12} {'deviation':>12} {'low':>12} {'high':>12} {'noise':>6} "
        f"{'slope':>6} {'n':>9}"
    )
    for i, tau in enumerate(res.taus):
        print(
            f"{tau:12.5g} {res.deviation[i]:12.5g} {res.interval[0][i]:12.5g} "
            f"{res.interval[1][i]:12.5g} {res.noise_type[i] or '-':>6} {res.slope[i]:6.2f} "
            f"{res.n[i]:9d}"
        )
    return 0


def add_parser(sub: Any) -> None:
    """Register ``allan`` on the sub-command set ``sub``."""
    from noisevar.noise_model.allan import DATA_KINDS, KINDS

    p = sub.add_parser("allan", help="Allan deviation with intervals and noise types (§E4)")
    p.add_argument("file")
    p.add_argument("--rate", type=float, help="sample rate in Hz (default: the time column's)")
    p.add_argument(
        "--data",
        choices=DATA_KINDS,
        help="phase (a time error, an angle) or rate (a gyro's rate, a specific force, a "
        "fractional frequency); default: phase for a unit of time, else rate",
    )
    p.add_argument("--kind", choices=list(KINDS), default="oadev")
    p.add_argument("--column")
    add_unit_flags(p)
    add_topic_flag(p)
    add_time_unit_flag(p)
    add_series_flag(p)
    add_regimes_flag(p)
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_allan)
