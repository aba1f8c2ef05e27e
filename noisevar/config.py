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
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators import METHODS, methods
from noisevar.estimators.params import PARAMS
from noisevar.io.series_option import READING, how_read
from noisevar.io.table import echo
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
            raise NoisevarError(
                f"config key {echo(repr(key))} must be true or false, got {echo(repr(value))}"
            )
        return
    numbers = value if spec.kind == "floats" and isinstance(value, list | tuple) else [value]
    if isinstance(value, np.ndarray):
        numbers = list(value.ravel())
    for v in numbers:
        if not spec.finite and v in INFINITIES:
            continue  # strict JSON has no infinity: "inf" stands for it where it is allowed
        if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
            raise NoisevarError(
                f"config key {echo(repr(key))} must be a number, got {echo(repr(value))}"
            )


#: How an infinite parameter (``trim``) is written in strict JSON, and read back.
INFINITIES = ("inf", "-inf")


def json_value(value: Any) -> Any:
    """A config value as strict JSON: ``inf`` becomes the string ``"inf"`` (see INFINITIES)."""
    if isinstance(value, float) and math.isinf(value):
        return INFINITIES[value < 0]
    if isinstance(value, list):
        return [json_value(v) for v in value]
    return value


def _check_value(key: str, spec: ParamSpec, value: Any) -> Any:
    """Validate one parameter with its spec; JSON-ready Python types."""
    _strict_json_type(key, spec, value)
    try:
        v = spec.validate(value)
    except NoisevarError as exc:
        raise NoisevarError(f"config key {echo(repr(key))}: {exc}") from None
    if isinstance(v, tuple):
        return list(v) if len(v) > 1 else v[0]
    return v


#: Keys that name data columns, not parameters (the dashboard exports the column).
CHANNEL_KEYS = ("column", "columns")
#: The record's answer when the file was written (verdict, R, regime warning, other still
#: levels): for the reader, never applied; validated and dropped when a config is read.
RECORD_KEY = "record"
_RECORD_FIELDS = ("verdict", "answer", "regime_warning", "other_still_levels")


def record_value(value: Any) -> dict[str, str]:
    """A config's ``record`` entry: at most the verdict, the answer, the regime warning and
    the other still levels, each a string (bounded)."""
    ok = isinstance(value, Mapping) and set(value) <= set(_RECORD_FIELDS)
    if not ok or not all(isinstance(v, str) and len(v) <= 4000 for v in value.values()):
        raise NoisevarError(
            f"config key 'record' must map {', '.join(_RECORD_FIELDS)} to text, "
            f"got {echo(repr(value))[:200]}"
        )
    return {k: value[k] for k in _RECORD_FIELDS if k in value}


def _channel_value(key: str, value: Any) -> str | list[str]:
    """A ``column`` (a name) or ``columns`` (a list of names, or ``"all"``) config value."""
    ok = isinstance(value, str) or (
        key == "columns" and isinstance(value, list) and all(isinstance(v, str) for v in value)
    )
    if not ok or len(str(value)) > 10_000:
        raise NoisevarError(f"config key {key!r} must name data columns, got {echo(repr(value))}")
    return value


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
        ``None`` values are dropped (they mean "the method's default"); ``time_unit`` and
        ``series`` (how the file was read, :data:`READING`) are kept for the commands that
        read the file.

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
    if "method" not in config and "kalman" in config:
        return _filter_config(config)
    if "method" not in config:
        raise NoisevarError(f"the config has no 'method' key; give one of: {', '.join(methods())}")
    method = config["method"]
    if method not in methods():
        raise NoisevarError(
            f"unknown method {echo(repr(method))} in the config; choose one of: "
            f"{', '.join(methods())}"
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
        if key in CHANNEL_KEYS:  # which data column(s) the parameters were tuned on
            out[key] = _channel_value(key, value)
            continue
        if key == RECORD_KEY:  # the record's answer, for the reader: checked, not applied
            record_value(value)
            continue
        if key in READING:  # how the file was read (the Signal page's unit, its series)
            if value is not None:
                out[key] = READING[key].validate(value)
            continue
        if key == "kalman":  # a tuned filter's Q and R (noisevar.noise_model.export)
            from noisevar.noise_model.export import check_kalman_config

            out[key] = check_kalman_config(value)
            continue
        if key not in known:
            raise NoisevarError(
                f"unknown config key {echo(repr(key))}; known keys: method, {', '.join(known)}"
            )
        if key not in specs:
            raise NoisevarError(
                f"config key {echo(repr(key))} is not a parameter of method {echo(repr(method))}; "
                f"its parameters: {', '.join(specs)}"
            )
        if value is None:
            continue
        out[key] = _check_value(key, specs[key], value)
    return out


def _filter_config(config: Mapping[str, Any]) -> dict[str, Any]:
    """A tuned filter's config (no estimator ``method``): its ``kalman`` entry and column."""
    from noisevar.noise_model.export import check_kalman_config

    extra = sorted(set(config) - {"kalman", RECORD_KEY, *READING, *CHANNEL_KEYS})
    if extra:
        raise NoisevarError(
            f"config key {echo(repr(extra[0]))} does not belong in a tuned filter's config "
            f"(kalman, column, {', '.join(READING)} and record only)"
        )
    if RECORD_KEY in config:
        record_value(config[RECORD_KEY])
    out: dict[str, Any] = {k: _channel_value(k, config[k]) for k in CHANNEL_KEYS if k in config}
    out.update({k: spec.validate(config[k]) for k, spec in READING.items() if config.get(k)})
    out["kalman"] = check_kalman_config(config["kalman"])
    return out


def require_estimator_config(config: Mapping[str, Any], source: str = "the config") -> None:
    """Refuse a tuned filter's config where an estimator's is expected (``noisevar estimate``).

    Raises
    ------
    NoisevarError
        One line naming the command that reads it (``noisevar fit``).
    """
    if "kalman" in config:
        raise NoisevarError(
            f"{source} holds a tuned Kalman filter (Q and R), which 'noisevar estimate' does "
            f"not apply: run 'noisevar fit FILE --config {source}'"
        )


def filter_config_json(
    tuning: Any,
    column: str | None = None,
    unit: str = "",
    record: Mapping[str, str] | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> str:
    """A tuned filter's config file, as the Noise model page downloads it and ``--save-config``
    writes it (``noisevar fit FILE --config`` reads it).

    Parameters
    ----------
    tuning : KalmanTuning
        The fitted (or applied) filter.
    column : str, optional
        The data column fitted.
    unit : str
        The signal's declared unit.
    record : mapping, optional
        The record's answer (:meth:`~noisevar.estimators.answer.RecordAnswer.summary`),
        written for the reader under ``record``.
    time_unit : str, optional
        The unit the file's times were read in (``--time-unit``), applied when the file is
        read again (``noisevar fit FILE --config``).
    series : str, optional
        The series read of a file that stacks several (``--series``), read again so.

    Returns
    -------
    str
        Indented JSON, validated.
    """
    from noisevar.noise_model.export import to_config

    told = how_read(time_unit, series)
    config = validate_config({**to_config(tuning, column=column, unit=unit), **told})
    if record:
        config[RECORD_KEY] = record_value(record)
    return json.dumps(config, indent=2, allow_nan=False) + "\n"


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


def config_to_json(
    config: Mapping[str, Any],
    column: str | None = None,
    record: Mapping[str, str] | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> str:
    """Serialise a config (validated first) as indented JSON text.

    Parameters
    ----------
    config : mapping
        A config.
    column : str, optional
        The data column the parameters were tuned on (``noisevar estimate`` reads it).
    record : mapping, optional
        The record's answer (:meth:`~noisevar.estimators.answer.RecordAnswer.summary`),
        written for the reader under ``record`` (not applied when read).
    time_unit : str, optional
        The unit the file's times were read in (the Signal page's control), applied when
        the file is read again (``noisevar estimate FILE --config``).
    series : str, optional
        The series read of a file that stacks several (the Signal page's picker), read
        again so.

    Returns
    -------
    str
    """
    told = how_read(time_unit, series)
    cfg = {k: json_value(v) for k, v in validate_config({**config, **told}).items()}
    if column:
        cfg["column"] = column
    if record:
        cfg[RECORD_KEY] = record_value(record)
    return json.dumps(cfg, indent=2, allow_nan=False) + "\n"


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
    if len(text) > MAX_CONFIG_BYTES:
        raise NoisevarError(
            f"{source} is {len(text):,} bytes, over the {MAX_CONFIG_BYTES:,}-byte limit of a "
            "config (a method and a few parameters)"
        )
    try:
        data = json.loads(
            text, parse_constant=_refuse_constant, parse_float=_finite_float, parse_int=_json_int
        )
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        where = f" (line {exc.lineno}, column {exc.colno})" if hasattr(exc, "lineno") else ""
        raise NoisevarError(f"{source} is not valid JSON{where}: {exc.args[0]}") from None
    except NoisevarError as exc:
        raise NoisevarError(f"{source}: {exc}") from None
    except RecursionError:
        raise NoisevarError(f"{source} is nested too deeply: a config is one flat object") from None
    except ValueError as exc:
        raise NoisevarError(f"{source} is not valid JSON: {str(exc)[:200]}") from None
    return validate_config(data)


#: Largest config text accepted (a config is a method and a few parameters).
MAX_CONFIG_BYTES = 1 << 20
#: Most digits of a JSON integer in a config.
_MAX_INT_DIGITS = 20


def _refuse_constant(token: str) -> float:
    raise NoisevarError(f"{token} is not a number JSON allows: give a finite number")


def _finite_float(token: str) -> float:
    value = float(token)
    if not math.isfinite(value):
        raise NoisevarError(
            f"{token[:40]} is beyond the floating-point range: give a finite number"
        )
    return value


def _json_int(token: str) -> int:
    if len(token.lstrip("-")) > _MAX_INT_DIGITS:
        raise NoisevarError(
            f"an integer of {len(token.lstrip('-')):,} digits is out of range for any parameter"
        )
    return int(token)


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
    try:
        if not p.is_file():
            raise NoisevarError(f"no such config file: {echo(str(p))}")
        if p.stat().st_size > MAX_CONFIG_BYTES:
            raise NoisevarError(
                f"{echo(p.name)} is {p.stat().st_size:,} bytes, over the "
                f"{MAX_CONFIG_BYTES:,}-byte limit of a config"
            )
        text = p.read_bytes()
    except OSError as exc:
        raise NoisevarError(f"cannot read {echo(str(p))}: {exc.strerror or exc}") from None
    return parse_config(text, echo(p.name))


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
