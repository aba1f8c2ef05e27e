"""Exports of a tuned filter: a filterpy snippet, and its entry in the JSON config.

The config carries the filter under one key, ``"kalman"``, and the column it was fitted on::

    {"column": "Gyr_Z",
     "kalman": {"model": "cv", "rate": 10.0, "q": 0.02, "r": 4.0, "method": "mle",
                "unit": "rad/s", "F": [[...]], "H": [[...]], "Q": [[...]], "R": [[4.0]],
                "regimes": "all", "notes": [...]}}

``q`` and ``r`` are the parameters; ``F``, ``H``, ``Q`` and ``R`` are written for
readers of the file and checked against them when it is read. ``method`` is the fit's
method (``mle`` ...), ``unit`` the signal's unit as the user declared it (empty: none),
``regimes`` which of the record's regimes the fit used (``"all"`` or ``"still"``) and
``notes`` which stretch. One command reads it: :data:`APPLY_COMMAND`; ``noisevar estimate``
refuses it (:func:`noisevar.config.require_estimator_config`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes
from noisevar.format import eng
from noisevar.noise_model.kalman_fit import METHODS, MODELS, KalmanTuning, kinematic_model

#: The config key that holds the tuned filter.
CONFIG_KEY = "kalman"
#: The one command that applies a tuned filter's config to a record.
APPLY_COMMAND = "noisevar fit FILE --config CONFIG"
_KEYS = ("model", "rate", "q", "r", "method", "unit", "F", "H", "Q", "R", "regimes", "notes")
#: Longest unit text a config carries.
_MAX_UNIT = 40


def _literal(a: np.ndarray) -> str:
    """A numpy array as exact Python source (``repr`` of floats round-trips)."""
    return f"np.array({np.asarray(a, float).tolist()!r})"


def filterpy_snippet(tuning: KalmanTuning) -> str:
    """Python source that builds the tuned filter as filterpy's ``KalmanFilter``.

    Parameters
    ----------
    tuning : KalmanTuning

    Returns
    -------
    str
        Source defining ``kf`` (state ``x`` and covariance ``P`` after the first
        ``start`` samples of the fitted record); run it on ``z[start:]`` with
        ``kf.predict(); kf.update(z_k)``.
    """
    n = tuning.F.shape[0]
    t = f"{tuning.dt!r} s" if tuning.rate is not None else "1 sample"
    return "\n".join(
        [
            "import numpy as np",
            "from filterpy.kalman import KalmanFilter",
            "",
            f"# noisevar fit: model {tuning.model!r}, method {tuning.method!r}, T = {t}",
            f"# {_regimes_said(tuning)}",
            f"# q = {tuning.q!r} {tuning.units.get('q', '')}",
            f"# r = {tuning.r!r} {tuning.units.get('r', '')},  h = q T^k / r = {tuning.h!r}",
            f"kf = KalmanFilter(dim_x={n}, dim_z=1)",
            f"kf.F = {_literal(tuning.F)}",
            f"kf.H = {_literal(tuning.H)}",
            f"kf.Q = {_literal(tuning.Q)}",
            f"kf.R = {_literal(tuning.R)}",
            f"# the estimate after the first {tuning.start} samples (exact diffuse start)",
            f"kf.x = {_literal(np.asarray(tuning.x0)[:, None])}",
            f"kf.P = {_literal(tuning.P0)}",
            f"# for z_k in z[{tuning.start}:]:",
            "#     kf.predict()",
            "#     kf.update(z_k)",
            "",
        ]
    )


def _regimes_said(tuning: KalmanTuning) -> str:
    """The regime choice of a fit and, for the still regimes, the stretch it ran on."""
    said = [n for n in tuning.notes if n.startswith("regimes=")]
    return said[0] if said else f"regimes={tuning.regimes!r}: fitted on the whole record"


def to_config(
    tuning: KalmanTuning,
    config: Mapping[str, Any] | None = None,
    *,
    column: str | None = None,
    unit: str = "",
) -> dict[str, Any]:
    """A config with the tuned filter under ``"kalman"`` and the column it was fitted on.

    Parameters
    ----------
    tuning : KalmanTuning
    config : mapping, optional
        Other config keys to extend. Without it, the filter's entry (and column) alone:
        the file that :data:`APPLY_COMMAND` reads.
    column : str, optional
        The data column fitted (``noisevar fit --config`` refuses another).
    unit : str
        The signal's unit as declared (empty: none).

    Returns
    -------
    dict
    """
    out = dict(config) if config is not None else {}
    if column is not None:
        out["column"] = str(column)
    out[CONFIG_KEY] = {
        "model": tuning.model,
        "rate": tuning.rate,
        "q": float(tuning.q),
        "r": float(tuning.r),
        "method": tuning.method,
        "unit": str(unit or ""),
        "F": tuning.F.tolist(),
        "H": tuning.H.tolist(),
        "Q": tuning.Q.tolist(),
        "R": tuning.R.tolist(),
        "regimes": tuning.regimes,
        "notes": list(tuning.notes),
    }
    return out


def _positive(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise NoisevarError(f"config key 'kalman.{name}' must be a finite number, got {value!r}")
    if value <= 0:
        raise NoisevarError(f"config key 'kalman.{name}' must be positive, got {value!r}")
    return float(value)


def check_kalman_config(value: Any) -> dict[str, Any]:
    """Validate the ``"kalman"`` entry of a config; return it normalised.

    Raises
    ------
    NoisevarError
        Not an object, unknown key, unknown model, a non-positive ``q``, ``r`` or
        ``rate``, matrices that disagree with ``model``, ``rate``, ``q``, ``r``, an
        unknown ``regimes`` or ``notes`` that are not a list of text.
    """
    if not isinstance(value, Mapping):
        raise NoisevarError("config key 'kalman' must be an object with model, q and r")
    extra = sorted(set(value) - set(_KEYS))
    if extra:
        raise NoisevarError(f"unknown key 'kalman.{extra[0]}'; known: {', '.join(_KEYS)}")
    model = value.get("model")
    if model not in MODELS:
        raise NoisevarError(
            f"config key 'kalman.model' must be one of {', '.join(MODELS)}, got {model!r}"
        )
    for key in ("q", "r"):
        if key not in value:
            raise NoisevarError(f"config key 'kalman' has no {key!r}")
    rate = value.get("rate")
    out = {"model": model, "rate": None if rate is None else _positive(rate, "rate")}
    out["q"], out["r"] = _positive(value["q"], "q"), _positive(value["r"], "r")
    F, h, Q1 = kinematic_model(model, 1.0 / out["rate"] if out["rate"] else 1.0)
    expected = {"F": F, "H": h[None, :], "Q": out["q"] * Q1, "R": np.array([[out["r"]]])}
    for key, mat in expected.items():
        if key in value:
            try:
                given = np.asarray(value[key], dtype=float)
            except (TypeError, ValueError):
                raise NoisevarError(f"config key 'kalman.{key}' must be a numeric matrix") from None
            if given.shape != mat.shape or not np.allclose(given, mat, rtol=1e-9, atol=0):
                raise NoisevarError(
                    f"config key 'kalman.{key}' disagrees with its model, rate, q and r: "
                    "edit q and r, not the matrices"
                )
        out[key] = mat.tolist()
    out.update(_regimes_entry(value))
    out.update(_fit_entry(value))
    return out


def _fit_entry(value: Mapping[str, Any]) -> dict[str, Any]:
    """``method`` (the fit's, absent in older files) and ``unit`` of a ``"kalman"`` entry."""
    out: dict[str, Any] = {}
    method = value.get("method")
    if method is not None:
        known = (*METHODS, "given")  # "given": q and r applied, not fitted
        if method not in known:
            raise NoisevarError(
                f"config key 'kalman.method' must be one of {', '.join(known)}, got {method!r}"
            )
        out["method"] = method
    unit = value.get("unit", "")
    if not isinstance(unit, str) or len(unit) > _MAX_UNIT:
        raise NoisevarError(f"config key 'kalman.unit' must be a short text, got {unit!r}")
    out["unit"] = unit
    return out


def _regimes_entry(value: Mapping[str, Any]) -> dict[str, Any]:
    """``regimes`` (default ``"all"``) and ``notes`` of a ``"kalman"`` entry, checked."""
    try:
        regimes = check_regimes(value.get("regimes", DEFAULT_REGIMES))
    except NoisevarError as exc:
        raise NoisevarError(f"config key 'kalman.regimes': {exc}") from None
    notes = value.get("notes", [])
    if not isinstance(notes, list) or not all(isinstance(n, str) for n in notes):
        raise NoisevarError("config key 'kalman.notes' must be a list of text")
    return {"regimes": regimes, "notes": list(notes)}


def from_config(config: Mapping[str, Any]) -> dict[str, Any]:
    """The tuned filter of a config: ``{"model", "rate", "q", "r", "F", "H", "Q", "R", ...}``.

    ``regimes`` and ``notes`` too (``"all"`` and none when the file has none).

    Raises
    ------
    NoisevarError
        If the config has no ``"kalman"`` entry or it is invalid.
    """
    if CONFIG_KEY not in config:
        raise NoisevarError(
            "the config has no 'kalman' entry: export one from the Noise model page "
            "or with 'noisevar fit FILE --save-config'"
        )
    return check_kalman_config(config[CONFIG_KEY])


#: Names of the kinematic states, in the order of the state vector (and of the gain).
STATE_NAMES = ("level", "rate", "acceleration")


def gain_text(tuning: KalmanTuning) -> str:
    """The steady-state gain, each entry named by its state (``"level 0.382, rate 0.1459"``)."""
    gains = np.ravel(tuning.gain)
    return ", ".join(f"{name} {eng(g)}" for name, g in zip(STATE_NAMES, gains, strict=False))
