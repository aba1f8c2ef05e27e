"""``noisevar experiment NAME``: run a seeded experiment."""

from __future__ import annotations

import argparse
from typing import Any

from noisevar.cli._common import Parser, print_json


def _cmd_experiment(args: argparse.Namespace) -> int:
    exp = args.experiment_obj
    # a flag not given is None: the experiment's default applies
    given = {p.name: getattr(args, p.name) for p in exp.parameters}
    result = exp.run(**{k: v for k, v in given.items() if v is not None})
    if args.format == "json" or exp.table is None:
        print_json(result.to_dict())
    else:
        print(exp.format_table(result))
    return 0


def add_parser(sub: Any) -> None:
    """Register ``experiment`` (one sub-command per discovered experiment) on ``sub``."""
    from noisevar.experiments import discover

    p = sub.add_parser("experiment", help="run a seeded experiment")
    esub = p.add_subparsers(dest="experiment", required=True, parser_class=Parser)
    for name, exp in discover().items():
        ep = esub.add_parser(name, help=exp.help, description=exp.help)
        for spec in exp.common_params:
            spec.add_to(ep)
        ep.add_argument("--format", choices=["table", "json"], default="table")
        for spec in exp.params:
            spec.add_to(ep)
        ep.set_defaults(func=_cmd_experiment, experiment_obj=exp)
