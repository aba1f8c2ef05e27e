"""``noisevar estimate FILE``: the noise variance of one signal, or of several channels."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from noisevar.cli._common import (
    add_series_flag,
    add_time_unit_flag,
    add_topic_flag,
    add_unit_flags,
    load_file,
    print_json,
    series_of,
    time_unit_of,
    units_of,
)
from noisevar.errors import NoisevarError
from noisevar.io.limits import MAX_BYTES, check_bytes, check_size, echo

if TYPE_CHECKING:  # the module stays light: precheck runs before NumPy is imported
    from noisevar.params import ParamSpec


def precheck(argv: list[str]) -> None:
    """Refuse FILE (the first argument) if missing or unreadable, or over the size cap
    unless it may be streamed (``--stream``, ``--dtype``, or a ``.npy`` for a method
    with a chunked path: :func:`_may_stream`).

    Run by :func:`noisevar.cli.main` before the parser is built, so that a 5 GB file
    is refused before NumPy and the estimators are imported. Only a ``.npy`` over the
    cap asks the method registry (which imports them) whether its method streams.
    """
    if not argv or argv[0].startswith("-"):
        return
    words = [w for arg in argv[1:] for w in arg.split("=", 1)]  # --method=x: --method, x
    if "--topic" in words:
        return  # a log (a ROS 2 bag may be a directory) is streamed: its reader checks it
    size = check_size(argv[0], max_bytes=None)
    if "--stream" in words or "--dtype" in words or size <= MAX_BYTES:
        return
    if not (argv[0].lower().endswith(".npy") and _may_stream(words)):
        check_bytes(size, Path(argv[0]).name)


def _may_stream(words: list[str]) -> bool:
    """Whether the method of the command line (``--method``, else the default) has a
    chunked path; ``--config`` may still choose another, refused once it is read."""
    from noisevar.estimators import DEFAULT_METHOD, METHODS

    method = words[words.index("--method") + 1] if "--method" in words[:-1] else DEFAULT_METHOD
    spec = METHODS.get(method)
    return spec is not None and spec.chunked is not None


def _streaming_methods() -> list[str]:
    """The registered methods with a chunked path (``--stream``)."""
    from noisevar.estimators import METHODS

    return [m for m, spec in METHODS.items() if spec.chunked is not None]


def _estimate_specs() -> list[ParamSpec]:
    """The estimate flags: every registered method's parameters that have a flag."""
    from noisevar.estimators import METHODS
    from noisevar.estimators.params import PARAMS

    specs: dict[str, ParamSpec] = {}
    for method in METHODS.values():
        for name, spec in method.param_specs.items():
            if spec.cli:
                specs.setdefault(name, spec)
    order = list(PARAMS)
    return sorted(specs.values(), key=lambda p: order.index(p.name) if p.name in order else 99)


def read_config(path: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """A config file's validated ``{"method", **params}`` and its channel keys (``column(s)``).

    Anything wrong with the file is reported by :func:`noisevar.config.load_config`.
    """
    from noisevar.config import CHANNEL_KEYS, load_config, require_estimator_config

    cfg = load_config(path)  # safe parsing and validation, channel keys included
    require_estimator_config(cfg, echo(os.path.basename(path)))  # a tuned filter: noisevar fit
    return cfg, {k: cfg.pop(k) for k in CHANNEL_KEYS if k in cfg}


def estimate_params(args: argparse.Namespace) -> tuple[str, dict[str, Any]]:
    """Method and parameters from ``--config`` (with its ``column``/``columns``) and the flags."""
    from noisevar.estimators import DEFAULT_METHOD

    params: dict[str, Any] = {}
    method = DEFAULT_METHOD
    if args.config:
        cfg, channels = read_config(args.config)
        method = cfg.pop("method", method)
        params.update(cfg)
        params.update(channels)
    if args.method is not None:
        method = args.method
    for spec in _estimate_specs():
        value = getattr(args, spec.name)
        if spec.kind == "floats" and value is not None and len(value) == 1:
            value = value[0]  # one --h-smooth is a number, several a list
        if value is not None:
            params[spec.name] = value
    return method, params


def _diagnostics_lines(result: Any) -> list[str]:
    """The estimate's verdict (a short record's too, without diagnostics), when it has one."""
    verdict = getattr(result, "verdict", "")
    if not verdict:
        return []
    # the diagnostics' notes are among the estimate's notes, printed after
    return [f"verdict   {echo(verdict, 500)}"]


def _units(args: argparse.Namespace, declared: str | None = None) -> tuple[float, str]:
    """The factor to apply to the data and the unit the results are in: ``--unit-out``,
    else ``--unit``, else the unit the file declares for the channel, else ``u``."""
    return units_of(getattr(args, "unit", None), getattr(args, "unit_out", None), declared)


def _unit(args: argparse.Namespace, declared: str | None = None) -> str:
    """The unit the results are in (:func:`_units`)."""
    return _units(args, declared)[1]


def _print_one(args: argparse.Namespace, column: Any, result: Any, unit: str) -> None:
    from noisevar.units import variance_label

    lo, hi = result.ci95
    u = unit
    print(f"file      {echo(args.file, 200)}" + (f"  column {echo(column)}" if column else ""))
    print(f"method    {result.method}")
    from noisevar.format import eng, eng_range

    v_unit = variance_label(u)  # the page's formatter: 106.8×10⁻²⁴ s² on both
    print(f"variance  {eng(result.variance, v_unit)}   (95 % CI {eng_range(lo, hi, v_unit)})")
    print(f"std       {eng(result.std, u)}")
    print(f"samples   {result.n_used} used of {result.n_total}")
    shown = {k: v for k, v in result.params.items() if k != "method" and v is not None}
    if shown:
        print("params    " + ", ".join(f"{k}={v}" for k, v in shown.items()))
    for line in _diagnostics_lines(result):
        print(line)
    for note in result.notes:
        print(f"note      {echo(note, 500)}")


def _as_json(args: argparse.Namespace, column: Any, result: Any, unit: str) -> dict[str, Any]:
    """The estimate's :meth:`~noisevar.estimators.results.VarianceEstimate.to_dict`, and where;
    a channel that could not be estimated: its ``error``."""
    if isinstance(result, str):
        return {"file": args.file, "column": column, "unit": unit, "error": result}
    return {**result.to_dict(), "file": args.file, "column": column, "unit": unit}


def _print_csv(args: argparse.Namespace, rows: list[tuple[Any, Any, str]]) -> None:
    """One row per channel: ``file``, ``channel``, ``unit`` and the estimate's row (the one
    schema, as ``noisevar batch`` writes it), or its ``error``."""
    from noisevar.batch import KEY_COLUMNS
    from noisevar.estimators.results import rows_frame

    out = [
        dict(
            zip(KEY_COLUMNS, (args.file, c, u), strict=True),
            **({"error": r} if isinstance(r, str) else r.to_row()),
        )
        for c, r, u in rows
    ]
    tail = ("error",) if any(isinstance(r, str) for _, r, _ in rows) else ()
    rows_frame(out, lead=KEY_COLUMNS, tail=tail).to_csv(sys.stdout, index=False)


def _print_table(args: argparse.Namespace, rows: list[tuple[Any, Any, str]]) -> None:
    print(f"file      {args.file}")
    done = [(c, r, u) for c, r, u in rows if not isinstance(r, str)]
    print(f"method    {done[0][1].method}")
    width = max(7, *(len(str(c)) for c, _, _ in rows))
    units = {u for _, _, u in rows}
    one = units.pop() if len(units) == 1 else None
    if one is not None:
        from noisevar.format import unit_text

        print(f"units     variance {_variance_label(one)}, std {unit_text(one)}")
    head = f"{'channel':<{width}}  {'variance':>11}  {'std':>11}  {'95 % CI':>25}  samples"
    print(head + ("" if one is not None else "  unit (std)"))
    for c, r, u in rows:
        if isinstance(r, str):
            print(f"{c!s:<{width}}  not estimated: {echo(r, 300)}")
            continue
        ci = f"{r.ci95[0]:.5g} .. {r.ci95[1]:.5g}"
        print(
            f"{c!s:<{width}}  {r.variance:>11.6g}  {r.std:>11.6g}  {ci:>25}  {r.n_used}/{r.n_total}"
            + ("" if one is not None else f"  {u}")
        )
    for c, r, _ in done:
        for line in _diagnostics_lines(r) + [f"note      {n}" for n in r.notes]:
            print(f"[{c}] {line}")


def _variance_label(unit: str) -> str:
    from noisevar.units import variance_label

    return variance_label(unit)


def _channels(args: argparse.Namespace, params: dict[str, Any]) -> tuple[Any, list | None]:
    """The one column (``--column``) or the channel list (``--columns``) to estimate."""
    from noisevar.batch.channels import parse_columns

    cfg_column, cfg_columns = params.pop("column", None), params.pop("columns", None)
    if args.column is not None and args.columns is not None:
        raise NoisevarError("give --column (one channel) or --columns (several), not both")
    if cfg_column is not None and args.column is not None and str(args.column) != cfg_column:
        # the page's config is for the column it was tuned on (issue 28: a wrong column
        # is refused, as `noisevar fit` refuses a tuned filter's)
        raise NoisevarError(
            f"the config was tuned on column {echo(repr(cfg_column))}, not "
            f"{echo(repr(str(args.column)))}: drop --column or tune that column"
        )
    if args.column is not None or (args.columns is None and cfg_columns is None):
        return (args.column if args.column is not None else cfg_column), None
    return None, parse_columns(args.columns if args.columns is not None else cfg_columns)


def _estimate_many(
    args: argparse.Namespace,
    columns: Any,
    method: str,
    params: dict,
    time_unit: str | None,
    series: str | None = None,
) -> int:
    """Several channels of one table, each with the table's times and its declared unit (as
    ``noisevar batch`` reads them: one answer); a channel that cannot be estimated is a row
    with its reason, the others go on (all failing: the first reason and the first of
    another kind, exit 2)."""
    from noisevar.batch.channels import (
        all_refused,
        channel_estimates,
        channels_and_left_out,
        skipped_note,
    )
    from noisevar.estimators import method_spec
    from noisevar.io.load import column_name

    if method_spec(method).needs_reference:
        raise NoisevarError(f"method {method} takes one --column and a --reference-column")
    table = load_file(args.file, args.topic, time_unit, series)
    names, skipped = channels_and_left_out(table, columns)
    for name in names:
        column_name(table, name)  # a name that is not in the file: the user's typo, exit 2
    results = channel_estimates(table, names, method, params)
    if all(isinstance(r, str) for r in results):
        raise NoisevarError(all_refused(names, results))
    names, results = [*names, *skipped], [*results, *map(skipped_note, skipped.values())]
    rows = [
        (c, r, _unit(args, table.units.get(c) if c is not None else None))
        for c, r in zip(names, results, strict=True)
    ]
    if args.format == "json":
        channels = [_as_json(args, c, r, u) for c, r, u in rows]
        print_json({"file": args.file, "method": method, "channels": channels})
    elif args.format == "csv":
        _print_csv(args, rows)
    else:
        _print_table(args, rows)
    return 0


def _streamed(args: argparse.Namespace) -> bool:
    """Read the file in chunks as asked (``--stream``, or a raw binary file: ``--dtype``);
    a large file is streamed without a flag too (:func:`_by_default`)."""
    return bool(args.stream or args.dtype)


def _by_default(args: argparse.Namespace, column: Any, method: str, params: dict) -> bool:
    """Whether a file over :data:`noisevar.stream.STREAM_BYTES` is streamed with no flag:
    one channel, a method with a chunked path and parameters it takes, a file the streamed
    path reads as memory would (:func:`noisevar.stream.same_column`)."""
    from noisevar.estimators import method_spec
    from noisevar.stream import STREAM_BYTES, same_column

    spec = method_spec(method)
    own = {getattr(p, "name", p) for p in spec.params}
    if (
        args.columns is not None
        or spec.chunked is None
        or not set(params) <= own
        or os.path.getsize(args.file) <= STREAM_BYTES
    ):
        return False
    return same_column(args.file, column)[0]


def _estimate_streamed(args: argparse.Namespace, column: Any, method: str, params: dict) -> Any:
    """The estimate of a record read in chunks, by a method whose spec has a chunked path."""
    from noisevar.estimators import method_spec
    from noisevar.stream import estimate_file

    if args.topic is not None:
        raise NoisevarError(
            "a log's topic is read from the log in chunks already: drop --stream and --dtype"
        )
    spec = method_spec(method)
    if spec.chunked is None or args.columns is not None:
        raise NoisevarError(
            "a streamed record (--stream, --dtype, or a .npy over the memory limit) is "
            f"estimated by method {' or '.join(_streaming_methods())}, one --column at a time"
        )
    own = [getattr(p, "name", p) for p in spec.params]  # its parameters, drop_nonfinite not
    extra = set(params) - set(own)
    if extra:
        raise NoisevarError(
            f"a streamed record takes {', '.join(own)}, not {', '.join(sorted(extra))}"
        )
    return estimate_file(
        args.file, column=column, dtype=args.dtype, method=method, workers=args.workers, **params
    )


def _cmd_estimate(args: argparse.Namespace) -> int:
    method, params = estimate_params(args)
    column, columns = _channels(args, params)
    time_unit = time_unit_of(args, params)  # the times are not read by a streamed estimate
    series = series_of(args, params)  # nor its rows picked: read in memory
    if series is not None and _streamed(args):
        raise NoisevarError(
            "--series reads the rows of one series in memory: drop --stream and --dtype"
        )
    if args.unit_out and (columns is not None or _streamed(args)):
        if not args.unit or units_of(args.unit, args.unit_out)[0] != 1.0:
            raise NoisevarError(
                "--unit-out converts one column read in memory: drop --columns/--stream"
            )
    in_memory = columns is not None or bool(args.unit_out) or series is not None
    if _streamed(args) or (not in_memory and _by_default(args, column, method, params)):
        from noisevar.stream import streamed_column

        if args.topic is None and columns is None:  # (their own messages, below)
            _, column, declared = streamed_column(args.file, column, args.dtype)
        else:
            declared = None
        result = _estimate_streamed(args, column, method, params)  # bounded memory
        _print(args, column, result, _unit(args, declared))
        return 0
    if columns is not None:
        return _estimate_many(args, columns, method, params, time_unit, series)
    from noisevar.io.load import column_name

    table = load_file(args.file, args.topic, time_unit, series)
    # say which one was read: the first, or the one an index names (text columns left out
    # of the count, an index is not the file's column number)
    if column is None or str(column) not in table.columns:  # one column too (pvanalytics')
        column = column_name(table, column)
    scale, unit = _units(args, table.units.get(column_name(table, column)))
    result = _estimate_one(args, table, column, method, params, scale)
    _print(args, column, result, unit)
    return 0


def _estimate_one(
    args: argparse.Namespace, table: Any, column: Any, method: str, params: dict, scale: float
) -> Any:
    """One column of a table: with its times and the loader's notes (gaps split, not
    spliced), or with the second sensor's column for a method that needs one."""
    import numpy as np

    from noisevar.estimators import estimate, method_spec
    from noisevar.estimators.answer import declared_note, record_answer
    from noisevar.io import channel_record, pick_column
    from noisevar.io.load import column_name

    drop = bool(params.get("drop_nonfinite", False))
    if not method_spec(method).needs_reference:
        z, t = channel_record(table, column, drop_nonfinite=drop)
        result = estimate(z * scale, method=method, t=t, **params)
        result.notes[:0] = [n for n in table.notes if n not in result.notes]
        cname = column_name(table, column)
        declared = table.declared_variance.get(cname)
        if declared is not None and result.diagnostics is not None:  # a ROS message's own R
            unit = _unit(args, table.units.get(cname))
            result.notes.append(declared_note(record_answer(result), declared * scale**2, unit))
        return result
    if not args.reference_column:
        raise NoisevarError(f"method {method} needs --reference-column: the second sensor's column")
    z = np.asarray(pick_column(table, column, drop_nonfinite=drop), dtype=float)
    reference = np.asarray(pick_column(table, args.reference_column, drop_nonfinite=drop))
    params["reference"] = reference * scale
    result = estimate(z * scale, method=method, **params)
    if table.n_rows - z.size:
        result.notes.insert(0, f"dropped {table.n_rows - z.size} non-finite samples of {args.file}")
    return result


def _print(args: argparse.Namespace, column: Any, result: Any, unit: str) -> None:
    if args.format == "json":
        print_json(_as_json(args, column, result, unit))
    elif args.format == "csv":
        _print_csv(args, [(column, result, unit)])
    else:
        _print_one(args, column, result, unit)


def add_estimate_flags(p: argparse.ArgumentParser) -> None:
    """The method, its parameter flags and ``--config`` (shared with ``noisevar batch``)."""
    from noisevar.estimators import DEFAULT_METHOD, methods

    p.add_argument("--method", choices=methods(), help=f"estimator (default {DEFAULT_METHOD})")
    for spec in _estimate_specs():
        spec.add_to(p)
    p.add_argument("--config", help="tuned-parameter JSON exported by the dashboard")


def add_parser(sub: Any) -> None:
    """Register ``estimate`` on the sub-command set ``sub``."""
    p = sub.add_parser("estimate", help="estimate the noise variance of one signal")
    p.add_argument("file", help="CSV/TSV (with or without header), .npy, or NMEA file")
    p.add_argument("--column", help="column name or 0-based index (default: the only/first)")
    p.add_argument("--columns", help="several channels: 'all' or a,b,c (one row each)")
    add_topic_flag(p)
    add_time_unit_flag(p)
    add_series_flag(p)
    add_estimate_flags(p)
    from noisevar.estimators import METHODS

    takes = ", ".join(m for m, spec in METHODS.items() if spec.needs_reference)
    p.add_argument("--reference-column", help=f"second sensor's column ({takes})")
    add_unit_flags(p)
    p.add_argument("--format", choices=["table", "json", "csv"], default="table")
    p.add_argument(
        "--stream",
        action="store_true",
        help=f"read the file in chunks ({', '.join(_streaming_methods())} only; bounded memory; "
        ".npy, raw binary, CSV)",
    )
    p.add_argument("--dtype", help="a headerless binary file of this sample type (e.g. <f4)")
    p.add_argument("--workers", type=int, default=2, help="threads of a streamed estimate")
    p.set_defaults(func=_cmd_estimate)
