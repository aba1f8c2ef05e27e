"""Experiments that the CLI exposes as ``noisevar experiment NAME``.

Each experiment is one module in this package that defines a module-level
``EXPERIMENT = Experiment(...)``; :func:`discover` finds it, so a new
experiment is one new file. ``EXPERIMENT.run(**params)`` returns a frozen
dataclass whose ``to_dict()`` is the JSON the CLI prints.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.experiments.base import (
    JOBS,
    RUNS,
    SEED,
    Experiment,
    ExperimentResult,
    ListParam,
    SwitchParam,
    at_least,
    strategy_param,
)

__all__ = [
    "JOBS",
    "RUNS",
    "SEED",
    "Experiment",
    "ExperimentResult",
    "ListParam",
    "SwitchParam",
    "at_least",
    "discover",
    "run",
    "strategy_param",
]


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


def run(name: str, **params: Any) -> ExperimentResult:
    """Run the experiment ``name`` with keyword parameters.

    Parameters
    ----------
    name : str
        Experiment name, e.g. ``"latency"``.
    **params
        Its parameters (see ``discover()[name].parameters``); defaults for the rest.

    Returns
    -------
    ExperimentResult
        The experiment's frozen result; ``.to_dict()`` is its JSON.
    """
    experiments = discover()
    if name not in experiments:
        raise NoisevarError(f"unknown experiment {name!r}; choose one of: {', '.join(experiments)}")
    return experiments[name].run(**params)
