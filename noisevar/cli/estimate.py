"""``noisevar estimate FILE``: the noise variance of one signal."""

from __future__ import annotations

import argparse
from typing import Any

from noisevar.cli._common import load_signal, print_json
from noisevar.errors import NoisevarError
from noisevar.io.table import echo
from noisevar.params import ParamSpec


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


def _estimate_params(args: argparse.Namespace) -> tuple[str, dict[str, Any]]:
    from noisevar.config import load_config

    params: dict[str, Any] = {}
    method = "auto"
    if args.config:
        cfg = load_config(args.config)
        method = cfg.pop("method", method)
        params.update(cfg)
    if args.method is not None:
        method = args.method
    for spec in _estimate_specs():
        value = getattr(args, spec.name)
        if spec.kind == "floats" and value is not None and len(value) == 1:
            value = value[0]  # one --h-smooth is a number, several a list
        if value is not None:
            params[spec.name] = value
    return method, params


def _cmd_estimate(args: argparse.Namespace) -> int:
    import noisevar

    method, params = _estimate_params(args)
    drop = bool(params.get("drop_nonfinite", False))
    z, dropped = load_signal(args.file, args.column, drop)
    if method == "somd-redundant":
        if not args.reference_column:
            raise NoisevarError(
                "method somd-redundant needs --reference-column: the second sensor's column"
            )
        params["reference"], _ = load_signal(args.file, args.reference_column, drop)
    result = noisevar.estimate(z, method=method, **params)
    if dropped:
        result.notes.insert(0, f"dropped {dropped} non-finite samples of {args.file}")
    out = result.to_dict()
    out["file"] = args.file
    out["column"] = args.column
    if args.format == "json":
        print_json(out)
    else:
        lo, hi = result.ci95
        column = f"  column {echo(args.column)}" if args.column else ""
        print(f"file      {echo(args.file, 200)}{column}")
        print(f"method    {result.method}")
        print(f"variance  {result.variance:.6g}   (95 % CI {lo:.6g} .. {hi:.6g})")
        print(f"std       {result.std:.6g}")
        print(f"samples   {result.n_used} used of {result.n_total}")
        shown = {k: v for k, v in result.params.items() if k != "method" and v is not None}
        if shown:
            print("params    " + ", ".join(f"{k}={v}" for k, v in shown.items()))
        for note in result.notes:
            print(f"note      {echo(note, 500)}")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``estimate`` on the sub-command set ``sub``."""
    from noisevar.estimators import methods

    p = sub.add_parser("estimate", help="estimate the noise variance of one signal")
    p.add_argument("file", help="CSV/TSV (with or without header), .npy, or NMEA file")
    p.add_argument("--column", help="column name or 0-based index (default: the only/first)")
    p.add_argument("--method", choices=methods(), help="estimator (default auto)")
    for spec in _estimate_specs():
        spec.add_to(p)
    p.add_argument("--reference-column", help="second sensor's column (somd-redundant)")
    p.add_argument("--config", help="tuned-parameter JSON exported by the dashboard")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_estimate)
