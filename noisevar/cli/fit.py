"""``noisevar fit FILE --model rw|cv|ca [--rate HZ]``: Q and R of a kinematic Kalman filter."""

from __future__ import annotations

import argparse
import inspect
import os
from pathlib import Path
from typing import Any

from noisevar.cli._common import (
    add_drop_flag,
    add_regimes_flag,
    add_series_flag,
    add_time_unit_flag,
    add_topic_flag,
    add_unit_flags,
    load_file,
    print_json,
    regimes_of,
    sample_rate,
    series_of,
    time_unit_of,
    units_of,
)
from noisevar.errors import NoisevarError
from noisevar.format import eng, eng_range, pvalue
from noisevar.io.limits import echo
from noisevar.units import UNKNOWN, in_data_unit


def _print_table(t: Any, args: argparse.Namespace, column: str, unit: str = "u") -> None:
    def iv(pair: tuple[float, float]) -> str:
        return f"(95 % {eng_range(*pair)})"

    print(f"file      {echo(args.file, 200)}  column {echo(column)}")
    print(f"model     {t.model}   method {t.method}   samples {t.n}   regimes {t.regimes}")
    # the page's formatter (noisevar.format.eng): the same digits on both
    print(f"q         {eng(t.q)} {in_data_unit(t.units['q'], unit)}  {iv(t.q_interval)}")
    print(f"r         {eng(t.r)} {in_data_unit(t.units['r'], unit)}  {iv(t.r_interval)}")
    print(f"h         {eng(t.h)} (q T^k / r)  {iv(t.h_interval)}")
    from noisevar.noise_model.export import gain_text

    print(f"gain      {gain_text(t)}")
    lo, hi = t.nis_band
    print(f"NIS mean  {t.nis_mean:.4g}   (95 % band {lo:.4g} .. {hi:.4g})")
    white = "white" if t.innovations_white else "NOT white"
    print(f"innov.    {white} (Ljung-Box {pvalue(t.ljung_box_p)})   loglik {t.loglik:.6g}")
    print(f"tails     {t.tails_text(f'{t.innovations_kurtosis:.3g}')}")
    _print_record(t.record, in_data_unit("u²", unit))
    for note in t.notes:
        print(f"note      {note}")


def _print_record(c: Any, var_unit: str) -> None:
    """The record's answer beside r (``KalmanTuning.record``): R, its interval, the R to use."""
    if c is None:
        return
    where = "inside" if c.agrees else "OUTSIDE"
    print(
        f"record R  {eng(c.variance)} {var_unit}  (95 % {eng_range(*c.ci95)}; method auto "
        f"over {c.where}): r is {c.ratio:.3g}x, {where} its interval"
    )
    use = "none (no still stretch measures it)" if c.use is None else f"{eng(c.use)} {var_unit}"
    print(f"R to use  {use}")
    for broken in c.broken:
        print(f"not met   the fit's assumption of {broken}")


def _load(
    args: argparse.Namespace, config: dict[str, Any] | None
) -> tuple[Any, int, str, float | None, str | None, Any]:
    """The record's column, the non-finite cells dropped, the column's name, the table's
    sample period (None without a time column), the unit the file declares for it (or None),
    and the kept samples' times (None without a time column: the record's answer is
    ``estimate``'s on them).

    With a tuned filter's config, the column it was fitted on and no other: another
    ``--column``, a file without that column, or (for a config naming none) a file of
    several columns without ``--column`` is refused.
    """
    import numpy as np

    from noisevar.io import pick_column
    from noisevar.io.load import column_name, column_values, record_times

    said = dict(config or {})  # how the config's file was read: its time unit, its series
    table = load_file(args.file, args.topic, time_unit_of(args, said), series_of(args, said))
    named = None if config is None else config.get("column")
    column = args.column
    if named is not None:
        if named not in table.data_columns:
            raise NoisevarError(
                f"the config was fitted on column {echo(repr(named))}, which "
                f"{echo(os.path.basename(args.file))} does not have (columns: "
                f"{echo(', '.join(table.data_columns), 300)})"
            )
        if column is not None and column_name(table, column) != named:
            raise NoisevarError(
                f"the config was fitted on column {echo(repr(named))}, not "
                f"{echo(repr(column_name(table, column)))}: drop --column or fit that column"
            )
        column = named
    elif config is not None and column is None and len(table.data_columns) > 1:
        raise NoisevarError(
            "the config names no column and the file has several: give --column (the one "
            "the filter was fitted on)"
        )
    z = np.asarray(pick_column(table, column, drop_nonfinite=args.drop_nonfinite), dtype=float)
    name = column_name(table, column)
    t = record_times(table, name)
    if t is not None and t.size != z.size:  # the non-finite cells dropped: their times too
        t = t[np.isfinite(np.asarray(column_values(table, name), dtype=float))]
    t = None if t is None or t.size != z.size else t
    return z, table.n_rows_of(name) - z.size, name, table.period_of(name), table.units.get(name), t


def _cmd_fit(args: argparse.Namespace) -> int:
    from noisevar.config import filter_config_json, load_config
    from noisevar.estimators.answer import record_answer
    from noisevar.noise_model import evaluate_kalman, fit_kalman
    from noisevar.noise_model.export import from_config
    from noisevar.noise_model.kalman_record import record_estimate

    if args.rate is not None and not args.rate > 0:
        raise NoisevarError(
            f"--rate must be a positive number of samples per second, got {args.rate}"
        )
    config = load_config(args.config) if args.config else None
    kal = from_config(config) if config is not None else None  # refused before the data load
    z, dropped, column, period, declared, t = _load(args, config)
    scale, unit = units_of(args.unit, args.unit_out, declared)  # as estimate reads it
    z = z * scale
    answer = record_estimate(z, t)  # the record's answer on its times, as `estimate` gives it
    record = None if isinstance(answer, str) else answer
    if kal is not None:
        if args.regimes is not None:
            raise NoisevarError(
                "--regimes chooses what a fit runs on: drop it with --config (no fit is made)"
            )
        rate = args.rate if args.rate is not None else kal["rate"]
        model = args.model or kal["model"]
        if model != kal["model"] or rate != kal["rate"]:
            raise NoisevarError(
                f"the config's filter is model {kal['model']!r} at rate {kal['rate']}: "
                "drop --model/--rate or give the same values"
            )
        tuning = evaluate_kalman(z, model, kal["q"], kal["r"], rate=rate, record=record)
    else:
        rate = sample_rate(args.rate, period)  # --rate, else the log's or time column's
        method = {} if args.method is None else {"method": args.method}  # else fit_kalman's
        model = args.model or "cv"
        tuning = fit_kalman(
            z, model=model, rate=rate, **method, **regimes_of(args), record=record
        )
    if args.save_config:
        said = unit if unit != UNKNOWN else (kal.get("unit", "") if kal is not None else "")
        try:  # the record's answer, written for the reader (not applied when read)
            summary = None if record is None else record_answer(record, tuning.regimes)
            written = None if summary is None else summary.summary(said)
        except NoisevarError:  # a record the estimator refuses: the config without it
            written = None
        told = time_unit_of(args, dict(config or {}))  # how the file's times were read
        series = series_of(args, dict(config or {}))  # and which series
        Path(args.save_config).write_text(
            filter_config_json(tuning, column, said, written, told, series), encoding="utf-8"
        )
    if args.format == "json":
        out = tuning.to_dict()
        out.update(file=args.file, column=column, dropped=dropped, unit=unit)
        out["units"] = {k: in_data_unit(v, unit) for k, v in out["units"].items()}
        print_json(out)
    else:
        _print_table(tuning, args, column, unit)
    return 0


def add_parser(sub: Any) -> None:
    """Register ``fit`` on the sub-command set ``sub``."""
    from noisevar.noise_model.kalman_fit import METHODS, MODELS, fit_kalman

    p = sub.add_parser("fit", help="fit Q and R of a kinematic Kalman filter to a record")
    p.add_argument("file", help="CSV/TSV (with or without header), .npy, or NMEA file")
    p.add_argument("--column", help="column name or 0-based index (default: the only/first)")
    add_topic_flag(p)
    add_time_unit_flag(p)
    add_series_flag(p)
    add_drop_flag(p)
    p.add_argument("--model", choices=list(MODELS), help="rw, cv or ca (default cv)")
    p.add_argument(
        "--rate", type=float, help="sample rate in Hz (default: --config's, else the time column's)"
    )
    default = inspect.signature(fit_kalman).parameters["method"].default
    p.add_argument("--method", choices=list(METHODS), help=f"default {default}")
    add_unit_flags(p)
    add_regimes_flag(p)
    p.add_argument("--config", help="apply the Q and R of this config instead of fitting")
    p.add_argument("--save-config", metavar="OUT", help="write the tuned filter as a config")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_fit)
