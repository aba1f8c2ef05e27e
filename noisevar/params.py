"""Parameter specifications: one home for each parameter's type, range, default and help.

A :class:`ParamSpec` validates a value (from Python, a config file, a URL or the
command line) and describes itself to the CLI and the dashboard, so that
estimators, adaptive strategies and experiments state each parameter once.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError

#: Value kinds a parameter can have.
KINDS = ("float", "int", "bool", "str", "floats", "array")


@dataclass(frozen=True)
class ParamSpec:
    """One parameter: its name, kind, range, default and help.

    Parameters
    ----------
    name : str
        Python keyword (``h_smooth``); the CLI flag is ``--h-smooth``.
    kind : {"float", "int", "bool", "str", "floats", "array"}
        Value kind; ``"floats"`` is a number or a sequence of numbers; ``"array"`` is
        data passed through unchanged (checked by its user, never a CLI flag).
    default : object
        Default value (``None``: chosen by the method).
    help : str
        One line for ``--help`` and the dashboard.
    lo, hi : float, optional
        Bounds of the open-closed interval ``(lo, hi]`` (``lo_closed`` makes it ``[lo, hi]``).
    lo_closed : bool
        Whether ``lo`` itself is allowed.
    choices : tuple of str, optional
        Allowed values of a ``"str"`` parameter.
    check : callable, optional
        Extra check ``check(value) -> value`` run after the range test.
    cli : bool
        Whether the CLI offers a flag for it (arrays such as ``reference`` are not flags).
    finite : bool
        Whether infinite numbers are refused (``trim=inf`` means "no trimming").
    """

    name: str
    kind: str
    default: Any = None
    help: str = ""
    lo: float | None = None
    hi: float | None = None
    lo_closed: bool = False
    choices: tuple[str, ...] | None = None
    check: Callable[[Any], Any] | None = None
    cli: bool = True
    finite: bool = True

    @property
    def flag(self) -> str:
        """The command-line flag, e.g. ``--h-smooth``."""
        return "--" + self.name.replace("_", "-")

    def validate(self, value: Any) -> Any:
        """Return ``value`` converted to this parameter's kind, or raise :class:`NoisevarError`."""
        if value is None:
            return None
        if self.kind == "array":
            return value
        if self.kind == "floats" and not isinstance(value, str | bytes):
            try:
                items = list(value)
            except TypeError:
                items = None
            if items is not None:
                if not items:
                    raise NoisevarError(f"{self.name} must not be empty")
                out = tuple(self._number(v) for v in items)
                return self.check(out) if self.check else out
        converted = self._convert(value)
        return self.check(converted) if self.check else converted

    def _convert(self, value: Any) -> Any:
        if self.kind == "bool":
            if isinstance(value, bool | np.bool_):
                return bool(value)
            raise NoisevarError(f"{self.name} must be true or false, got {value!r}")
        if self.kind == "str":
            if not isinstance(value, str) or (self.choices and value not in self.choices):
                allowed = f": one of {', '.join(self.choices)}" if self.choices else ""
                raise NoisevarError(f"{self.name} must be a string{allowed}, got {value!r}")
            return value
        return self._number(value)

    def _number(self, value: Any) -> float | int:
        if isinstance(value, bool | np.bool_):
            raise NoisevarError(f"{self.name} must be a number, got {value!r}")
        try:
            v = float(value)
        except (TypeError, ValueError, OverflowError):
            raise NoisevarError(f"{self.name} must be a number, got {value!r}") from None
        if math.isnan(v) or (self.finite and not math.isfinite(v)):
            raise NoisevarError(f"{self.name} must be finite, got {value!r}")
        if self.kind == "int":
            if not math.isfinite(v) or v != int(v):
                raise NoisevarError(f"{self.name} must be an integer, got {value!r}")
            # an integer stays exact (through a float, a seed above 2**53 would be rounded)
            v = int(value) if isinstance(value, int | np.integer) else int(v)
        self._check_range(v, value)
        return v

    def _check_range(self, v: float, raw: Any) -> None:
        low_bad = self.lo is not None and (v < self.lo if self.lo_closed else v <= self.lo)
        if low_bad or (self.hi is not None and v > self.hi):
            left = "[" if self.lo_closed else "("
            lo = "-inf" if self.lo is None else f"{self.lo:g}"
            hi = "inf" if self.hi is None else f"{self.hi:g}"
            raise NoisevarError(
                f"{self.name}={raw} is out of range: it must be in {left}{lo}, {hi}]"
            )

    def add_to(self, parser: argparse.ArgumentParser, default: Any = None) -> None:
        """Add this parameter's flag to an argparse parser (default ``None``: not given)."""
        kwargs: dict[str, Any] = {"dest": self.name, "default": default, "help": self.help}
        if self.kind == "bool":
            kwargs["action"] = argparse.BooleanOptionalAction
        elif self.kind == "int":
            kwargs["type"] = int
        elif self.kind == "str":
            kwargs["type"] = str
            if self.choices:
                kwargs["choices"] = self.choices
        elif self.kind == "floats":
            kwargs["type"] = float
            kwargs["nargs"] = "+"
        else:
            kwargs["type"] = float
        parser.add_argument(self.flag, **kwargs)


def by_name(specs: Iterable[ParamSpec]) -> dict[str, ParamSpec]:
    """Map names to specs, refusing duplicates."""
    out: dict[str, ParamSpec] = {}
    for spec in specs:
        if spec.name in out:
            raise ValueError(f"parameter {spec.name!r} is specified twice")
        out[spec.name] = spec
    return out


def validate_params(
    owner: str, specs: Mapping[str, ParamSpec], params: Mapping[str, Any]
) -> dict[str, Any]:
    """Validate keyword parameters against specs; an unknown name is an error.

    The error names the unknown parameters and the known ones, in the owner's order.
    """
    unknown = sorted(set(params) - set(specs))
    if unknown:
        known = ", ".join(specs) or "none"
        raise NoisevarError(
            f"{owner} does not take parameter(s) {', '.join(unknown)}; its parameters: {known}"
        )
    return {k: specs[k].validate(v) for k, v in params.items()}
