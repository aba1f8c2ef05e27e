"""Command line: ``python -m noisevar`` (also installed as ``noisevar``).

Sub-commands::

    noisevar estimate FILE [--column C] [--method M] [--h-smooth H ...] [--h-track H]
                           [--window M] [--gamma-amp G] [--gamma-ang DEG] [--span S]
                           [--order K] [--trim T] [--config tuned.json] [--format table|json|csv]
                           [--columns all|a,b,c]
    noisevar batch 'logs/**/*.csv' [--columns all|a,b,c] [--out noise.parquet] [--jobs N]
                   [--scheduler tcp://host:8786] [--method M] [--no-resume]
    noisevar methods
    noisevar scan-h FILE [--column C] [--window M]
    noisevar experiment NAME [--runs N] [--seed S] [--format table|json] ...
    noisevar allan FILE --rate HZ [--data phase|rate] [--kind oadev|mdev|hdev] [--column C]
    noisevar imu FILE --rate HZ [--columns C ...] [--gyro C ...] [--accel C ...]
                     [--kalibr out.yaml] [--inflation F]
    noisevar topics LOG [--json]
    noisevar dashboard [--port P] [--serve-others] [--address A] [--allowed-host NAME ...]

A log or workbook (``noisevar.io.logs.log_kinds``) is read by ``--topic T`` on
estimate, scan-h, allan, imu and fit; ``--column`` then picks the topic's field. ``imu``
takes ``--topic`` several times (PX4's ``sensor_gyro_fifo`` and ``sensor_accel_fifo``):
each column at its own topic's rate, named by field or ``topic/field``.

A command module may also define ``precheck(args)``, run on its raw arguments before
the parser is built (building it imports the estimators): ``estimate`` refuses a
missing, unreadable or oversized FILE there, in a fraction of a second.
Every error is one line on stderr and a non-zero exit status (2 for bad input,
3 for an internal error); no traceback (``NOISEVAR_DEBUG=1`` shows it).
The ``--config`` file is the JSON the dashboard exports: command-line flags
given explicitly override its values. The parameter flags of ``estimate`` are made
from the parameter specs (:data:`noisevar.estimators.params.PARAMS`); a flag the
chosen method does not take is an error.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

from noisevar.cli._common import EXIT_ERROR, Parser, one_line
from noisevar.errors import NoisevarError

#: The sub-commands, in ``--help`` order: each is a module of this package with an
#: ``add_parser(sub)`` function. A new command is one new module plus one line here.
COMMANDS: tuple[str, ...] = (
    "estimate",
    "methods",
    "scan_h",
    "experiment",
    "allan",
    "imu",
    "fit",
    "batch",
    "topics",
    "dashboard",
)


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``noisevar`` argument parser, one sub-command per module of :data:`COMMANDS`.

    Parameters
    ----------
    only : str, optional
        Build this sub-command alone (the one being run: the others' parsers import
        their libraries, e.g. every experiment); default: all of them.

    Returns
    -------
    argparse.ArgumentParser
    """
    parser = Parser(
        prog="noisevar",
        description="Measurement-noise variance of a signal, for the Kalman filter that uses it.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for name in COMMANDS if only is None else (only,):
        importlib.import_module(f"noisevar.cli.{name}").add_parser(sub)
    return parser


def command_module(argv: Sequence[str]) -> str | None:
    """The module of :data:`COMMANDS` that the command line runs (``scan-h``: ``scan_h``)."""
    if not argv or "_" in argv[0]:
        return None
    name = argv[0].replace("-", "_")
    return name if name in COMMANDS else None


def precheck(argv: Sequence[str]) -> None:
    """Run the command's ``precheck(args)``, if it has one, before anything heavy is imported.

    Parameters
    ----------
    argv : sequence of str
        The command line after ``noisevar``.

    Raises
    ------
    NoisevarError
        What the command's check refuses.
    """
    name = command_module(argv)
    if name is None or {"-h", "--help"} & set(argv):
        return
    check = getattr(importlib.import_module(f"noisevar.cli.{name}"), "precheck", None)
    if check is not None:
        check(list(argv[1:]))


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
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        precheck(argv)
        args = build_parser(command_module(argv)).parse_args(argv)
        return int(args.func(args))
    except NoisevarError as exc:
        print(f"noisevar: error: {one_line(str(exc))}", file=sys.stderr)
    except FileNotFoundError as exc:
        print(f"noisevar: error: no such file: {one_line(exc.filename)}", file=sys.stderr)
    except (IsADirectoryError, PermissionError) as exc:
        where = one_line(exc.filename)
        print(f"noisevar: error: cannot read {where}: {exc.strerror}", file=sys.stderr)
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
            f"noisevar: internal error ({type(exc).__name__}: {one_line(str(exc))}); "
            "rerun with NOISEVAR_DEBUG=1 for the traceback and please report it",
            file=sys.stderr,
        )
        return 3
    return EXIT_ERROR


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
