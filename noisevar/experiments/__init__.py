"""Experiments that the CLI exposes as ``noisevar experiment NAME``.

Each experiment is one module in this package that defines a module-level
``EXPERIMENT = Experiment(...)``. Modules are discovered automatically, so a
new experiment is one new file: no registry to edit.

Every experiment's ``run(args)`` returns a JSON-serialisable ``dict``; the CLI
prints it as JSON (``--format json``) or as a readable table
(``--format table``, via ``format_table`` when the experiment provides one).
Common options (``--runs``, ``--seed``, ``--format``) are added by the CLI;
``add_arguments`` adds the experiment's own.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Experiment:
    """One CLI experiment.

    Parameters
    ----------
    name : str
        Sub-command name, e.g. ``"monte-carlo"``.
    help : str
        One-line description shown by ``noisevar experiment --help``.
    run : callable
        ``run(args: argparse.Namespace) -> dict``; JSON-serialisable result.
    add_arguments : callable, optional
        ``add_arguments(parser)`` adds experiment-specific options.
    default_runs : int
        Default for ``--runs``.
    format_table : callable, optional
        ``format_table(result: dict) -> str`` for ``--format table``.
    """

    name: str
    help: str
    run: Callable[[argparse.Namespace], dict[str, Any]]
    add_arguments: Callable[[argparse.ArgumentParser], None] | None = None
    default_runs: int = 100
    format_table: Callable[[dict[str, Any]], str] | None = None


def discover() -> dict[str, Experiment]:
    """Import every module of this package and collect its ``EXPERIMENT``.

    Returns
    -------
    dict
        Experiment name to :class:`Experiment`, sorted by name.
    """
    found: dict[str, Experiment] = {}
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        exp = getattr(module, "EXPERIMENT", None)
        if isinstance(exp, Experiment):
            found[exp.name] = exp
    return dict(sorted(found.items()))
