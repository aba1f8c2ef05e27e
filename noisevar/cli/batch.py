"""``noisevar batch 'logs/**/*.csv' --out noise.parquet``: every channel of many files."""

from __future__ import annotations

import argparse
import re
import sys
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.io.limits import echo

#: A scheduler address: ``[scheme://]host:port`` (tcp://, tls://, ws://, inproc://...).
_ADDRESS = re.compile(r"^([a-z][a-z0-9+.-]*://)?[^\s/:]+(:\d+)?(/\S*)?$", re.IGNORECASE)


def _client(address: str) -> Any:
    """A ``dask.distributed`` client of the scheduler at ``address`` (one clear error if none)."""
    if not _ADDRESS.match(address) or ("://" not in address and ":" not in address):
        raise NoisevarError(
            f"--scheduler {echo(address)!r} is not a scheduler address: give one like "
            "tcp://host:8786"
        )
    try:
        from distributed import Client
    except ImportError:
        raise NoisevarError(
            "--scheduler needs dask.distributed: pip install 'noisevar[scale]'"
        ) from None
    try:
        return Client(address, timeout="10s")
    except (OSError, TimeoutError, ValueError, TypeError) as exc:  # ValueError: not an address
        raise NoisevarError(
            f"cannot reach the Dask scheduler at {echo(address)}: {echo(exc, 200)} "
            "(give its address, e.g. tcp://host:8786)"
        ) from None


def _summary(frame: Any, out: str | None) -> str:
    files = frame["file"].nunique() if len(frame) else 0
    from noisevar.batch.channels import left_out_rows

    left = sum(left_out_rows(frame["error"])) if len(frame) else 0
    bad = int(frame["error"].notna().sum()) - left if len(frame) else 0
    where = f"; written to {out}" if out else ""
    said = f", {left} left out (flags, codes, clock times)" if left else ""
    return f"{files} files, {len(frame)} rows, {bad} with an error{said}{where}"


def _cmd_batch(args: argparse.Namespace) -> int:
    from noisevar.batch import batch, check_jobs
    from noisevar.cli._common import series_of, time_unit_of
    from noisevar.cli.estimate import estimate_params

    method, params = estimate_params(args)
    jobs, cut = check_jobs(args.jobs)
    if cut and not args.scheduler:
        print(f"noisevar: {cut}", file=sys.stderr)
    columns = args.columns if args.columns is not None else params.pop("columns", "all")
    params.pop("column", None)
    time_unit = time_unit_of(args, params)
    series = series_of(args, params)
    client = _client(args.scheduler) if args.scheduler else None
    try:
        frame = batch(
            args.paths,
            columns=columns,
            method=method,
            out=args.out,
            jobs=jobs,
            client=client,
            resume=not args.no_resume,
            progress=not args.quiet,
            topic=args.topic,
            time_unit=time_unit,
            series=series,
            **params,
        )
    finally:
        if client is not None:
            client.close()
    if args.out is None:
        frame.to_csv(sys.stdout, index=False)
    print(_summary(frame, args.out), file=sys.stderr)
    return 0


def add_parser(sub: Any) -> None:
    """Register ``batch`` on the sub-command set ``sub``."""
    from noisevar.cli._common import add_series_flag, add_time_unit_flag, add_topic_flag
    from noisevar.cli.estimate import add_estimate_flags

    p = sub.add_parser("batch", help="estimate every channel of many files (one row each)")
    p.add_argument("paths", nargs="+", help="files, folders or quoted globs ('logs/**/*.csv')")
    p.add_argument("--columns", help="'all' (default) or a,b,c")
    add_topic_flag(p)
    add_time_unit_flag(p)
    add_series_flag(p)
    p.add_argument("--out", help=".parquet or .csv output (default: CSV on stdout)")
    p.add_argument(
        "--jobs",
        type=int,
        default=1,
        help="local worker processes (default 1; at most the machine's CPUs: more is cut to that)",
    )
    p.add_argument("--scheduler", help="a dask.distributed scheduler (tcp://host:8786)")
    p.add_argument("--no-resume", action="store_true", help="redo files already in --out")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_estimate_flags(p)
    p.set_defaults(func=_cmd_batch)
