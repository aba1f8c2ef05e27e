"""``noisevar methods``: list the estimators."""

from __future__ import annotations

import argparse
from typing import Any

from noisevar.cli._common import print_json


def _cmd_methods(args: argparse.Namespace) -> int:
    from noisevar.estimators import describe_methods

    desc = describe_methods()
    if args.format == "json":
        print_json({"methods": desc})
    else:
        width = max(map(len, desc))
        for name, text in desc.items():
            print(f"{name:<{width}}  {text}")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``methods`` on the sub-command set ``sub``."""
    p = sub.add_parser("methods", help="list the estimators")
    p.add_argument("--format", choices=["table", "json"], default="table")
    p.set_defaults(func=_cmd_methods)
