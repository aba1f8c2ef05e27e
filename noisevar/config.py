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
estimate. Every value is checked when a config is made or read (the same
ranges :func:`noisevar.estimate` enforces), so a bad file is refused at once
with a message naming the key, not later in the middle of a run. Arrays
(``reference``) cannot be stored in a config: they are data, not parameters.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators import KNOWN_PARAMS, methods
from noisevar.filters.abg import check_h
from noisevar.filters.selection import ANGLES

#: Parameters a config may hold (``reference`` is data and is refused).
CONFIG_PARAMS = tuple(sorted(KNOWN_PARAMS - {"reference"}))


def _number(key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise NoisevarError(f"config key {key!r} must be a number, got {value!r}")
    v = float(value)
    if math.isnan(v):
        raise NoisevarError(f"config key {key!r} is NaN")
    return v


def _in_range(key: str, value: Any, lo: float, hi: float, lo_open: bool = True) -> float:
    v = _number(key, value)
    ok = (v > lo if lo_open else v >= lo) and v <= hi
    if not ok:
        left = "(" if lo_open else "["
        raise NoisevarError(f"config key {key!r}={value} is out of range {left}{lo}, {hi}]")
    return v


def _integer(key: str, value: Any, lo: int, hi: int | None = None) -> int:
    v = _number(key, value)
    if v != int(v):
        raise NoisevarError(f"config key {key!r} must be an integer, got {value!r}")
    iv = int(v)
    if iv < lo or (hi is not None and iv > hi):
        bound = f"between {lo} and {hi}" if hi is not None else f"at least {lo}"
        raise NoisevarError(f"config key {key!r}={iv} must be {bound}")
    return iv


def _boolean(key: str, value: Any) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise NoisevarError(f"config key {key!r} must be true or false, got {value!r}")


def _h_value(key: str, value: Any) -> float:
    return check_h(_number(key, value), key)


def _check_value(key: str, value: Any) -> Any:
    """Validate and normalise one parameter (JSON-ready Python types)."""
    if key == "h_smooth":
        if isinstance(value, (list, tuple, np.ndarray)):
            hs = [_h_value(key, h) for h in value]
            if not hs:
                raise NoisevarError("config key 'h_smooth' is an empty list")
            return hs if len(hs) > 1 else hs[0]
        return _h_value(key, value)
    if key == "h_track":
        return _h_value(key, value)
    if key == "track_ratio":
        return _in_range(key, value, 1.0, 1e4)
    if key == "window":
        return _integer(key, value, 8)
    if key == "gamma_amp":
        return _in_range(key, value, 0.0, 1.0)
    if key == "gamma_ang":
        return _in_range(key, value, 0.0, 90.0)
    if key == "angle":
        if value not in ANGLES:
            raise NoisevarError(f"config key 'angle' must be one of {list(ANGLES)}, got {value!r}")
        return str(value)
    if key in ("select", "drop_nonfinite"):
        return _boolean(key, value)
    if key == "reference_variance":
        return _in_range(key, value, 0.0, math.inf, lo_open=False)
    if key == "wavelet":
        if not isinstance(value, str) or not value:
            raise NoisevarError(f"config key 'wavelet' must be a wavelet name, got {value!r}")
        return value
    if key == "span":
        span = _integer(key, value, 3)
        if span % 2 == 0:
            raise NoisevarError(f"config key 'span' must be odd, got {span}")
        return span
    if key == "order":
        return _integer(key, value, 1, 6)
    if key == "trim":
        v = _number(key, value)
        if not v > 1.0:
            raise NoisevarError(f"config key 'trim' must be above 1 (standard deviations), got {v}")
        return v
    raise NoisevarError(  # pragma: no cover - callers check the key first
        f"unknown config key {key!r}"
    )


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
        Not a mapping, missing or unknown method, unknown key, a value of the
        wrong type or out of range.
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
    for key in sorted(k for k in config if k != "method"):
        value = config[key]
        if key == "reference":
            raise NoisevarError(
                "a config cannot hold the 'reference' signal (it is data, not a parameter): "
                "give the second sensor as a column instead (CLI: --reference-column)"
            )
        if key not in CONFIG_PARAMS:
            raise NoisevarError(
                f"unknown config key {key!r}; known keys: method, {', '.join(CONFIG_PARAMS)}"
            )
        if value is None:
            continue
        out[key] = _check_value(key, value)
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


def config_to_json(config: Mapping[str, Any]) -> str:
    """Serialise a config (validated first) as indented JSON text.

    Parameters
    ----------
    config : mapping
        A config.

    Returns
    -------
    str
    """
    return json.dumps(validate_config(config), indent=2) + "\n"


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
