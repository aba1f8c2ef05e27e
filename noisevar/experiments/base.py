"""The :class:`Experiment` type, its common parameters and the result base class.

An experiment states its parameters once (:class:`noisevar.params.ParamSpec`);
``run(**kwargs)`` validates them and returns a frozen dataclass whose
``to_dict()`` is the JSON the CLI prints. The CLI builds the flags from the
same specs.
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.params import ParamSpec, by_name, validate_params


def _plain(value: Any) -> Any:
    """``value`` with results, dataclasses, tuples and numpy values as plain JSON types."""
    if callable(getattr(value, "to_dict", None)):
        return _plain(value.to_dict())
    if dataclasses.is_dataclass(value):
        return _fields(value)
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


@dataclass(frozen=True)
class ExperimentResult:
    """Base of every experiment's result: a frozen dataclass with :meth:`to_dict`.

    The fields of a subclass are the top-level keys of its JSON, in order.
    """

    def to_dict(self) -> dict[str, Any]:
        """The JSON structure ``noisevar experiment NAME --format json`` prints."""
        return _fields(self)


def _fields(obj: Any) -> dict[str, Any]:
    return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}


# ----------------------------------------------------------------- parameter kinds
def at_least(flag: str, lo: int, unit: str = "") -> Callable[[int], int]:
    """A ``ParamSpec.check`` refusing values below ``lo``, naming the flag."""

    def check(value: int) -> int:
        if value < lo:
            raise NoisevarError(f"{flag} must be at least {lo}{unit}, got {value}")
        return value

    return check


@dataclass(frozen=True)
class ListParam(ParamSpec):
    """A list-valued parameter (kind ``"floats"`` or ``"strs"``), possibly empty.

    On the command line it is one text split at ``sep`` (``--sweep 25,30``;
    empty items dropped for numbers) or, with ``sep=None``, several words
    (``--methods a b``). From Python, a sequence or that same text.
    """

    sep: str | None = ","

    def validate(self, value: Any) -> Any:
        """Return a tuple of floats or strings, or raise :class:`NoisevarError`."""
        if value is None:
            return None
        if isinstance(value, str):
            value = self._split(value)
        try:
            items = list(value)
        except TypeError:
            raise NoisevarError(f"{self.name} must be a list, got {value!r}") from None
        if self.kind == "floats":
            out = tuple(self._number(v) for v in items)
        else:
            out = tuple(self._string(v) for v in items)
        return self.check(out) if self.check else out

    def _split(self, text: str) -> list[str]:
        if self.sep is None:
            return text.split()
        if self.kind == "floats":
            return [v for v in text.split(self.sep) if v.strip()]
        return [v.strip() for v in text.split(self.sep)] if text else []

    def _string(self, value: Any) -> str:
        if not isinstance(value, str) or (self.choices and value not in self.choices):
            allowed = f": each one of {', '.join(self.choices)}" if self.choices else ""
            raise NoisevarError(f"{self.name} must be strings{allowed}, got {value!r}")
        return value

    def add_to(self, parser: argparse.ArgumentParser, default: Any = None) -> None:
        """Add the flag: one text (``sep``) or several words (``nargs="+"``)."""
        kwargs: dict[str, Any] = {"dest": self.name, "default": default, "help": self.help}
        if self.sep is None:
            kwargs["nargs"] = "+"
            kwargs["type"] = float if self.kind == "floats" else str
            if self.choices:
                kwargs["choices"] = self.choices
        else:
            kwargs["type"] = self._parse_text
        parser.add_argument(self.flag, **kwargs)

    def _parse_text(self, text: str) -> Any:
        """The flag's text, validated as the parser reads it (a usage error if bad)."""
        try:
            return self.validate(text)
        except NoisevarError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None


@dataclass(frozen=True)
class SwitchParam(ParamSpec):
    """A boolean parameter whose flag only switches it on (``--data-bits``)."""

    kind: str = "bool"
    default: Any = False

    def add_to(self, parser: argparse.ArgumentParser, default: Any = None) -> None:
        """Add the ``store_true`` flag."""
        parser.add_argument(
            self.flag, dest=self.name, action="store_true", default=default, help=self.help
        )


def strategy_param(strategy: str, param: str, help: str, name: str | None = None) -> ParamSpec:
    """An adaptive strategy's parameter, default and range from the strategy registry.

    Parameters
    ----------
    strategy, param : str
        Registry name (``"sage-husa"``) and its parameter (``"forgetting"``).
    help : str
        The experiment's help line.
    name : str, optional
        The experiment's name for it (``"somd_every"``; default ``param``).
    """
    from noisevar.kalman.strategies import strategy_spec

    spec = by_name(strategy_spec(strategy).params)[param]
    return dataclasses.replace(spec, name=name or param, help=help)


#: Parameters every experiment takes (``runs`` gets the experiment's default).
RUNS = ParamSpec("runs", "int", None, "Monte Carlo runs", check=at_least("--runs", 1))
SEED = ParamSpec("seed", "int", 0, "random seed", lo=0, hi=2**32 - 1, lo_closed=True)
#: Worker processes, for the experiments that run one filter per process.
JOBS = ParamSpec(
    "jobs",
    "int",
    1,
    "worker processes, one filter each (default 1)",
    check=at_least("--jobs", 1),
)


# --------------------------------------------------------------------- experiment
@dataclass(frozen=True)
class Experiment:
    """One experiment: ``noisevar experiment NAME`` and ``EXPERIMENT.run(**kwargs)``.

    Parameters
    ----------
    name : str
        Sub-command name, e.g. ``"monte-carlo"``.
    help : str
        One-line description shown by ``noisevar experiment --help``.
    compute : callable
        ``compute(**params) -> ExperimentResult`` with every parameter validated.
    params : tuple of ParamSpec
        The experiment's own parameters (``runs`` and ``seed`` are common).
    default_runs : int
        Default of ``runs``.
    table : callable, optional
        ``table(result_dict) -> str`` for ``--format table`` (default: JSON).
    """

    name: str
    help: str
    compute: Callable[..., ExperimentResult]
    params: tuple[ParamSpec, ...] = ()
    default_runs: int = 100
    table: Callable[[dict[str, Any]], str] | None = None

    @property
    def common_params(self) -> tuple[ParamSpec, ParamSpec]:
        """``runs`` (with this experiment's default) and ``seed``."""
        runs = dataclasses.replace(
            RUNS, default=self.default_runs, help=f"Monte Carlo runs ({self.default_runs})"
        )
        return runs, SEED

    @property
    def parameters(self) -> tuple[ParamSpec, ...]:
        """Every parameter: the common ones, then the experiment's own."""
        return (*self.common_params, *self.params)

    def defaults(self) -> dict[str, Any]:
        """Default value of every parameter."""
        return {p.name: p.default for p in self.parameters}

    def validate(self, **kwargs: Any) -> dict[str, Any]:
        """Every parameter, validated, with defaults for those not given.

        Raises
        ------
        NoisevarError
            An unknown parameter or a bad value.
        """
        specs = by_name(self.parameters)
        return validate_params(f"experiment {self.name}", specs, {**self.defaults(), **kwargs})

    def run(self, /, **kwargs: Any) -> ExperimentResult:
        """Run the experiment with keyword parameters; return its result dataclass.

        Parameters
        ----------
        **kwargs
            Parameters by name (see :attr:`parameters`); defaults for the rest.

        Returns
        -------
        ExperimentResult
            The experiment's frozen result; ``to_dict()`` is its JSON.

        Raises
        ------
        NoisevarError
            An unknown parameter or a bad value.
        """
        return self.compute(**self.validate(**kwargs))

    def format_table(self, result: ExperimentResult | dict[str, Any]) -> str:
        """Readable text of a result (or of its ``to_dict()``)."""
        data = result.to_dict() if isinstance(result, ExperimentResult) else result
        if self.table is None:
            import json

            return json.dumps(data, indent=2)
        return self.table(data)
