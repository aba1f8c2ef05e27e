"""Command line: ``python -m noisevar`` (also installed as ``noisevar``).

Sub-commands::

    noisevar estimate FILE [--column C] [--method M] [--h-smooth H ...] [--h-track H]
                           [--window M] [--gamma-amp G] [--gamma-ang DEG] [--span S]
                           [--order K] [--trim T] [--config tuned.json] [--format table|json]
    noisevar methods
    noisevar scan-h FILE [--column C] [--window M]
    noisevar experiment NAME [--runs N] [--seed S] [--format table|json] ...

Every error is one line on stderr and a non-zero exit status (2 for bad input,
3 for an internal error); no traceback (``NOISEVAR_DEBUG=1`` shows it).
The ``--config`` file is the JSON the dashboard exports: command-line flags
given explicitly override its values. The parameter flags of ``estimate`` are made
from the parameter specs (:data:`noisevar.estimators.params.PARAMS`); a flag the
chosen method does not take is an error.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.params import ParamSpec

EXIT_ERROR = 2


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line, like every other error."""

    def error(self, message: str) -> NoReturn:
        raise NoisevarError(f"{message} (see '{self.prog} --help')")


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def _print_json(data: dict) -> None:
    print(json.dumps(data, indent=2, default=_json_default, allow_nan=True))


def _load_signal(
    path: str, column: str | None, drop_nonfinite: bool = False
) -> tuple[np.ndarray, int]:
    """One column of a data file as floats, and how many non-finite cells were dropped.

    Empty/NaN/Inf cells are refused (naming the first row) unless
    ``drop_nonfinite``.
    """
    from noisevar.io import load_table, pick_column

    table = load_table(path, os.path.basename(path))
    z = np.asarray(pick_column(table, column, drop_nonfinite=drop_nonfinite), dtype=float)
    return z, table.n_rows - z.size


# --------------------------------------------------------------------------- estimate
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
    z, dropped = _load_signal(args.file, args.column, drop)
    if method == "somd-redundant":
        if not args.reference_column:
            raise NoisevarError(
                "method somd-redundant needs --reference-column: the second sensor's column"
            )
        params["reference"], _ = _load_signal(args.file, args.reference_column, drop)
    result = noisevar.estimate(z, method=method, **params)
    if dropped:
        result.notes.insert(0, f"dropped {dropped} non-finite samples of {args.file}")
    out = result.to_dict()
    out["file"] = args.file
    out["column"] = args.column
    if args.format == "json":
        _print_json(out)
    else:
        lo, hi = result.ci95
        print(f"file      {args.file}" + (f"  column {args.column}" if args.column else ""))
        print(f"method    {result.method}")
        print(f"variance  {result.variance:.6g}   (95 % CI {lo:.6g} .. {hi:.6g})")
        print(f"std       {result.std:.6g}")
        print(f"samples   {result.n_used} used of {result.n_total}")
        shown = {k: v for k, v in result.params.items() if k != "method" and v is not None}
        if shown:
            print("params    " + ", ".join(f"{k}={v}" for k, v in shown.items()))
        for note in result.notes:
            print(f"note      {note}")
    return 0


# ---------------------------------------------------------------------------- methods
def _cmd_methods(args: argparse.Namespace) -> int:
    from noisevar.estimators import describe_methods

    desc = describe_methods()
    if args.format == "json":
        _print_json({"methods": desc})
    else:
        width = max(map(len, desc))
        for name, text in desc.items():
            print(f"{name:<{width}}  {text}")
    return 0


# ----------------------------------------------------------------------------- scan-h
def _cmd_scan_h(args: argparse.Namespace) -> int:
    from noisevar.filters.envelope import scan_h

    z, _ = _load_signal(args.file, args.column)
    scan = scan_h(z, window=args.window)
    if args.format == "json":
        _print_json(scan.to_dict())
    else:
        print(f"band      {scan.band[0]:.3g} .. {scan.band[1]:.3g} (|V1|/|V2|, eq. 14)")
        print(f"h range   {scan.h_min:.3g} .. {scan.h_max:.3g}")
        print(f"h chosen  {scan.h_chosen:.3g}")
        print("h          ratio")
        for h, r in zip(scan.h, scan.ratio, strict=True):
            mark = "  *" if scan.band[0] <= r <= scan.band[1] else ""
            print(f"{h:<10.3g} {r:.4f}{mark}")
    return 0


# ------------------------------------------------------------------------- experiment
def _cmd_experiment(args: argparse.Namespace) -> int:
    exp = args.experiment_obj
    # a flag not given is None: the experiment's default applies
    given = {p.name: getattr(args, p.name) for p in exp.parameters}
    result = exp.run(**{k: v for k, v in given.items() if v is not None})
    if args.format == "json" or exp.table is None:
        _print_json(result.to_dict())
    else:
        print(exp.format_table(result))
    return 0


# ----------------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The ``noisevar`` argument parser (sub-commands estimate, methods, scan-h, experiment).

    Returns
    -------
    argparse.ArgumentParser
    """
    from noisevar.estimators import methods
    from noisevar.experiments import discover

    parser = _Parser(
        prog="noisevar",
        description="Measurement-noise variance of a signal, for the Kalman filter that uses it.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

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

    p = sub.add_parser("methods", help="list the estimators")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_methods)

    p = sub.add_parser("scan-h", help="h range of eq. 14 (smoothing strength)")
    p.add_argument("file")
    p.add_argument("--column")
    p.add_argument("--window", type=int, default=40)
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_scan_h)

    p = sub.add_parser("experiment", help="run a seeded experiment")
    esub = p.add_subparsers(dest="experiment", required=True, parser_class=_Parser)
    for name, exp in discover().items():
        ep = esub.add_parser(name, help=exp.help, description=exp.help)
        for spec in exp.common_params:
            spec.add_to(ep)
        ep.add_argument("--format", choices=["table", "json"], default="table")
        for spec in exp.params:
            spec.add_to(ep)
        ep.set_defaults(func=_cmd_experiment, experiment_obj=exp)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the exit status (0 on success, 2 on any error).

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
    """
    try:
        args = build_parser().parse_args(argv)
        return int(args.func(args))
    except NoisevarError as exc:
        print(f"noisevar: error: {exc}", file=sys.stderr)
    except FileNotFoundError as exc:
        print(f"noisevar: error: no such file: {exc.filename}", file=sys.stderr)
    except (IsADirectoryError, PermissionError) as exc:
        print(f"noisevar: error: cannot read {exc.filename}: {exc.strerror}", file=sys.stderr)
    except KeyboardInterrupt:
        print("noisevar: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader went away (e.g. `noisevar ... | head`): stop quietly, like other tools
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except Exception as exc:  # noqa: BLE001 - a bug of ours: still one line, never a traceback
        if os.environ.get("NOISEVAR_DEBUG"):
            raise
        print(
            f"noisevar: internal error ({type(exc).__name__}: {exc}); "
            "rerun with NOISEVAR_DEBUG=1 for the traceback and please report it",
            file=sys.stderr,
        )
        return 3
    return EXIT_ERROR


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
