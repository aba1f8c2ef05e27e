"""``noisevar topics LOG``: what a log holds (topics or messages, fields, counts, rates, units)."""

from __future__ import annotations

import argparse
import os
from typing import Any

from noisevar.cli._common import print_json
from noisevar.io.limits import echo
from noisevar.io.logs import log_kinds


def _rate(rate: float | None) -> str:
    return f"{rate:.4g}" if rate is not None else "-"


def _cmd_topics(args: argparse.Namespace) -> int:
    from pathlib import Path

    from noisevar.io.logs import list_topics, reader_of
    from noisevar.io.logs.spec import collecting

    name = os.path.basename(os.path.normpath(args.log))
    reader = reader_of(Path(args.log), name)
    notes: list[str] = []  # what the reader says of the file (a bag cut short...)
    with collecting(notes):
        topics = list_topics(args.log, name)
    if args.format == "json":
        listed = [t.to_dict() for t in topics]
        print_json({"file": args.log, "format": reader.name, "topics": listed, "notes": notes})
        return 0
    print(f"log       {echo(args.log, 200)} ({reader.title}, {len(topics)} topics)")
    for note in notes:
        print(f"note      {note}")
    width = max([len("topic"), *(len(echo(t.name)) for t in topics)])
    mwidth = max([len("message"), *(len(echo(t.message)) for t in topics)])
    print(f"{'topic':<{width}}  {'message':<{mwidth}}  {'count':>9}  {'rate_hz':>9}")
    for t in topics:
        row = f"{echo(t.name):<{width}}  {echo(t.message):<{mwidth}}  {t.count:>9}"
        print(f"{row}  {_rate(t.rate):>9}")
        shown = [f"{echo(f)} [{t.units[f]}]" if f in t.units else echo(f) for f in t.fields]
        if shown:
            print(f"    fields: {', '.join(shown)}")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``topics`` on the sub-command set ``sub``."""
    p = sub.add_parser(
        "topics",
        help=f"list a log's topics: fields, counts, rates, units ({log_kinds()})",
    )
    p.add_argument("log", help="the log (a ROS 2 bag may be its directory)")
    p.add_argument(
        "--format",
        choices=("table", "json"),
        default="table",
        help="table (default) or json, as every other command",
    )
    p.add_argument(
        "--json",
        dest="format",
        action="store_const",
        const="json",
        help="the same as --format json",
    )
    p.set_defaults(func=_cmd_topics)
