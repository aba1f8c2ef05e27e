"""The tuned-parameter JSON: what the dashboard exports and ``noisevar estimate --config`` reads.

A config is one flat JSON object: ``"method"`` plus estimator parameters named
exactly as the keyword arguments of :func:`noisevar.estimate`, for example::

    {
      "method": "somd",
      "h_smooth": [1.5e-05, 3e-05],
      "h_track": 0.00045,
      "window": 40,
      "gamma_amp": 0.5,
      "gamma_ang": 10.0,
      "angle": "scaled",
      "select": true
    }

so that ``noisevar.estimate(z, **load_config(path))`` reproduces the tuned
estimate. Every value is checked, when a config is made or read, by the parameter
specs :func:`noisevar.estimate` uses (:data:`noisevar.estimators.params.PARAMS`), so a
bad file is refused at once with a message naming the key. Arrays (``reference``)
cannot be stored in a config: they are data, not parameters.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators import METHODS, methods
from noisevar.estimators.params import PARAMS
from noisevar.params import ParamSpec


def config_params() -> tuple[str, ...]:
    """Parameters a config may hold: every registered method's, except data (``reference``)."""
    names = {
        name
        for spec in METHODS.values()
        for name, p in spec.param_specs.items()
        if p.kind != "array"
    }
    return tuple(sorted(names))


#: Parameters a config may hold with the built-in methods (``reference`` is data).
CONFIG_PARAMS = tuple(sorted(name for name, p in PARAMS.items() if p.kind != "array"))


def _strict_json_type(key: str, spec: ParamSpec, value: Any) -> None:
    """Refuse a JSON value of the wrong type (``"40"`` for a number), before the spec converts."""
    if spec.kind == "str":
        return
    if spec.kind == "bool":
        if not isinstance(value, bool | np.bool_):
            raise NoisevarError(f"config key {key!r} must be true or false, got {value!r}")
        return
    numbers = value if spec.kind == "floats" and isinstance(value, list | tuple) else [value]
    if isinstance(value, np.ndarray):
        numbers = list(value.ravel())
    for v in numbers:
        if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
            raise NoisevarError(f"config key {key!r} must be a number, got {value!r}")


def _check_value(key: str, spec: ParamSpec, value: Any) -> Any:
    """Validate one parameter with its spec; JSON-ready Python types."""
    _strict_json_type(key, spec, value)
    try:
        v = spec.validate(value)
    except NoisevarError as exc:
        raise NoisevarError(f"config key {key!r}: {exc}") from None
    if isinstance(v, tuple):
        return list(v) if len(v) > 1 else v[0]
    return v


def validate_config(config: Mapping[str, Any]) -> dict[str, Any]:
    """Check a config mapping and return it normalised (a new dict).

    Parameters
    ----------
    config : mapping
        ``"method"`` plus estimator parameters.

    Returns
    -------
    dict
        ``{"method": ..., <params in sorted order>}`` with JSON-ready values;
        ``None`` values are dropped (they mean "the method's default").

    Raises
    ------
    NoisevarError
        Not a mapping, missing or unknown method, unknown key, a key the method
        does not take, a value of the wrong type or out of range.
    """
    if not isinstance(config, Mapping):
        raise NoisevarError(
            f"a config must be a JSON object (method and parameters), got {type(config).__name__}"
        )
    if "method" not in config:
        raise NoisevarError(f"the config has no 'method' key; give one of: {', '.join(methods())}")
    method = config["method"]
    if method not in methods():
        raise NoisevarError(
            f"unknown method {method!r} in the config; choose one of: {', '.join(methods())}"
        )
    out: dict[str, Any] = {"method": str(method)}
    specs = METHODS[method].param_specs
    known = config_params()
    for key in sorted(k for k in config if k != "method"):
        value = config[key]
        if key == "reference":
            raise NoisevarError(
                "a config cannot hold the 'reference' signal (it is data, not a parameter): "
                "give the second sensor as a column instead (CLI: --reference-column)"
            )
        if key not in known:
            raise NoisevarError(
                f"unknown config key {key!r}; known keys: method, {', '.join(known)}"
            )
        if key not in specs:
            raise NoisevarError(
                f"config key {key!r} is not a parameter of method {method!r}; "
                f"its parameters: {', '.join(specs)}"
            )
        if value is None:
            continue
        out[key] = _check_value(key, specs[key], value)
    return out


def params_to_config(method: str, params: Mapping[str, Any]) -> dict[str, Any]:
    """The config for a method and its parameters (for example ``estimate.params``).

    Parameters
    ----------
    method : str
        Estimator name (see :func:`noisevar.methods`).
    params : mapping
        Parameters, typically :attr:`VarianceEstimate.params` (its ``"method"``
        key, if any, is ignored in favour of ``method``). Keys that
        :func:`noisevar.estimate` does not take are refused.

    Returns
    -------
    dict
        A validated config, ready for :func:`config_to_json`.

    Examples
    --------
    >>> params_to_config("somd", {"h_smooth": 1.5e-5, "window": 40})
    {'method': 'somd', 'h_smooth': 1.5e-05, 'window': 40}
    """
    cfg = {k: v for k, v in params.items() if k != "method"}
    cfg["method"] = method
    return validate_config(cfg)


def config_to_json(config: Mapping[str, Any], column: str | None = None) -> str:
    """Serialise a config (validated first) as indented JSON text.

    Parameters
    ----------
    config : mapping
        A config.
    column : str, optional
        The data column the parameters were tuned on (``noisevar estimate`` reads it).

    Returns
    -------
    str
    """
    out = {**validate_config(config), **({"column": column} if column else {})}
    return json.dumps(out, indent=2) + "\n"


def parse_config(text: str | bytes, source: str = "config") -> dict[str, Any]:
    """Parse and validate config JSON text.

    Parameters
    ----------
    text : str or bytes
        JSON text.
    source : str
        Name used in error messages.

    Returns
    -------
    dict
    """
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        where = f" (line {exc.lineno}, column {exc.colno})" if hasattr(exc, "lineno") else ""
        raise NoisevarError(f"{source} is not valid JSON{where}: {exc.args[0]}") from None
    return validate_config(data)


def load_config(path: str | os.PathLike) -> dict[str, Any]:
    """Read a tuned-parameter JSON file (as written by the dashboard's export).

    Parameters
    ----------
    path : str or path
        The JSON file.

    Returns
    -------
    dict
        ``{"method": ..., **params}``: call ``noisevar.estimate(z, **config)``.

    Raises
    ------
    NoisevarError
        Missing file, invalid JSON, or an invalid config (see
        :func:`validate_config`).
    """
    p = Path(path)
    if not p.is_file():
        raise NoisevarError(f"no such config file: {p}")
    try:
        text = p.read_bytes()
    except OSError as exc:
        raise NoisevarError(f"cannot read {p}: {exc.strerror or exc}") from None
    return parse_config(text, p.name)


def split_config(config: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """``(method, params)`` of a config, for ``noisevar.estimate(z, method, **params)``.

    Parameters
    ----------
    config : mapping
        A config.

    Returns
    -------
    (str, dict)
    """
    cfg = validate_config(config)
    method = cfg.pop("method")
    return method, cfg
