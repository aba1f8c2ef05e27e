"""Noise-variance estimators: :func:`estimate` with a method name from :func:`methods`.

Each method is declared once, as a :class:`~noisevar.estimators.spec.MethodSpec` in
its own module; :data:`REGISTRY` lists them. Adding an estimator is one new module and
one line in :data:`REGISTRY` (or one :func:`register` call from outside the package).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.diagnostics import Segmentation
from noisevar.errors import NoisevarError
from noisevar.estimators import _scale, auto, difference, mle, redundant, somd
from noisevar.estimators._input import as_channels, as_signal, check_samples
from noisevar.estimators._scale import (
    RATE_RANGE,
    check_rate,
    refusing_held,
    scale_back,
    scale_exponent,
)
from noisevar.estimators.auto import auto_estimate, residual_sequence
from noisevar.estimators.difference import HKT_SEQUENCES, sequence_efficiency
from noisevar.estimators.params import PARAMS
from noisevar.estimators.pipeline import InMemory, estimate_record, run_record
from noisevar.estimators.redundant import (
    estimate_redundant,
    redundant_estimate,
    same_quantity_columns,
)
from noisevar.estimators.results import VarianceEstimate, VarianceEstimates
from noisevar.estimators.somd import somd_estimate, somd_variance_records, somd_variance_windows
from noisevar.estimators.spec import MethodSpec

__all__ = [
    "DEFAULT_METHOD",
    "HKT_SEQUENCES",
    "METHODS",
    "PARAMS",
    "RATE_RANGE",
    "REGISTRY",
    "MethodSpec",
    "as_signal",
    "auto_estimate",
    "check_rate",
    "describe_methods",
    "estimate",
    "estimate_chunked",
    "estimate_redundant",
    "methods",
    "redundant_estimate",
    "same_quantity_columns",
    "register",
    "residual_sequence",
    "scale_back",
    "scale_exponent",
    "sequence_efficiency",
    "somd_estimate",
    "somd_variance_records",
    "somd_variance_windows",
    "unregister",
]

#: The built-in estimators, in the order :func:`methods` lists them.
REGISTRY: list[MethodSpec] = [
    auto.AUTO,
    somd.SOMD,
    somd.SOMD_PAPER,
    redundant.SOMD_REDUNDANT,
    *difference.METHODS,
    mle.MLE_LEVEL,
    mle.MLE_TREND,
]

#: Name to spec of every registered estimator (built-ins and :func:`register`-ed ones).
METHODS: dict[str, MethodSpec] = {}
#: The method of :func:`estimate` when none is named.
DEFAULT_METHOD: str = auto.AUTO.name
#: The samples around level jumps that the diagnostics of every method leave out: the
#: default method's jump detector (docs/algorithms.md §F5.3).
JUMP_MASK = auto.jump_mask


def register(spec: MethodSpec, replace: bool = False) -> MethodSpec:
    """Make an estimator available to :func:`estimate`, :func:`methods`, config and CLI.

    Parameters
    ----------
    spec : MethodSpec
        The method; its parameters are names in
        :data:`~noisevar.estimators.params.PARAMS` or new
        :class:`~noisevar.params.ParamSpec` objects.
    replace : bool
        Allow replacing a method of the same name.

    Returns
    -------
    MethodSpec
        ``spec`` (so that ``register`` can decorate a module-level assignment).
    """
    if spec.name in METHODS and not replace:
        raise ValueError(f"an estimator named {spec.name!r} is already registered")
    spec.param_specs  # noqa: B018 - refuses unknown parameter names now, not at first use
    METHODS[spec.name] = spec
    return spec


def unregister(name: str) -> None:
    """Remove a registered estimator (for tests and plug-ins)."""
    METHODS.pop(name, None)


for _spec in REGISTRY:
    register(_spec)


def methods(kind: str | None = None) -> list[str]:
    """Names of the available estimators.

    Parameters
    ----------
    kind : {"ours", "somd", "peer"}, optional
        Only methods of this kind.

    Returns
    -------
    list of str
    """
    return [m.name for m in METHODS.values() if kind is None or m.kind == kind]


def describe_methods() -> dict[str, str]:
    """Method name to one-line description."""
    return {m.name: m.description for m in METHODS.values()}


def method_spec(method: str) -> MethodSpec:
    """The registered spec of ``method``, or a :class:`NoisevarError` listing the methods."""
    if method not in METHODS:
        raise NoisevarError(f"unknown method {method!r}; choose one of: {', '.join(methods())}")
    return METHODS[method]


def _run(spec: MethodSpec, z: NDArray, notes: list[list[str]], params: dict) -> list:
    """``spec.func`` on validated channels ``z`` of shape ``(k, n)``: one result each."""
    if spec.vectorised:
        return list(spec.func(z, notes, **params))
    return [spec.func(row, nt, **params) for row, nt in zip(z, notes, strict=True)]


def _run_one(spec: MethodSpec, z: NDArray, notes: list[str], params: dict) -> VarianceEstimate:
    """``spec.func`` on one validated uniform segment."""
    return _run(spec, z[None, :], [notes], params)[0]


def _channels(spec: MethodSpec, z: NDArray, drop: bool, params: dict) -> list:
    """Every channel of ``z`` (shape ``(..., n)``), at once when the method allows it."""
    flat = z.reshape(-1, z.shape[-1])
    rows, notes = [], []
    for i, row in enumerate(flat):
        try:
            r, nt = check_samples(row, drop)
        except NoisevarError as exc:
            where = np.unravel_index(i, z.shape[:-1])
            raise NoisevarError(f"channel {tuple(int(w) for w in where)}: {exc}") from None
        rows.append(r)
        notes.append(nt)
    if spec.vectorised and len({r.size for r in rows}) == 1:
        return _run(spec, np.stack(rows), notes, params)
    return [_run(spec, r[None, :], [nt], params)[0] for r, nt in zip(rows, notes, strict=True)]


def _records(
    spec: MethodSpec, arr: NDArray, times: NDArray | None, drop: bool, used: dict, e: int
) -> list[VarianceEstimate]:
    """Every channel of ``arr`` (samples on the last axis, scaled by ``2**e``) through ``spec``."""
    if arr.ndim == 1:
        return [estimate_record(spec, arr, times, drop, used, _run_one, JUMP_MASK, e)]
    rows = arr.reshape(-1, arr.shape[-1])
    if times is None and np.isfinite(arr).all():  # the method's vectorised path
        results = _channels(spec, arr, drop, used)
        one = Segmentation(((0, arr.shape[-1]),), ())
        return [
            refusing_held(run_record, row, e, spec.name)(
                spec, InMemory(spec, row, one, _run_one, JUMP_MASK, []), used, r, e
            )
            for r, row in zip(results, rows, strict=True)
        ]
    return [estimate_record(spec, row, times, drop, used, _run_one, JUMP_MASK, e) for row in rows]


def estimate(
    z: ArrayLike,
    method: str = DEFAULT_METHOD,
    axis: int = -1,
    t: ArrayLike | None = None,
    **params: Any,
) -> VarianceEstimate | VarianceEstimates:
    """Estimate the measurement-noise variance of a signal, or of many channels.

    Parameters
    ----------
    z : array_like, shape (n,) or (..., n, ...)
        Samples, uniformly spaced. N-D input holds one channel per index of the other
        axes.
    method : str
        One of :func:`methods`; default ``"auto"``.
    axis : int
        Sample axis of N-D input.
    t : array_like, shape (n,), optional
        Sample times. The record is split where the sampling is not uniform (gaps,
        irregular steps), each uniform segment is estimated and the segments are
        pooled; so is a record whose non-finite samples are dropped.
    **params
        The method's parameters (``noisevar methods`` and
        :data:`~noisevar.estimators.params.PARAMS` list them); ``drop_nonfinite`` is
        accepted by every method. ``None`` means the method's default.

    Returns
    -------
    VarianceEstimate or VarianceEstimates
        One estimate for 1-D input (``.variance``, ``.std``, ``.ci95``, ``.n_used``,
        ``.params`` and, for SOMD methods, ``.details``); for N-D input, per-channel
        arrays in a :class:`~noisevar.estimators.results.VarianceEstimates`.

    Raises
    ------
    NoisevarError
        Bad input, an unknown method, a parameter the method does not take, or a value
        out of range, with a message that says what to do.

    Examples
    --------
    >>> import numpy as np, noisevar
    >>> z = np.sin(np.arange(5000) / 200) * 50 + np.random.default_rng(0).normal(0, 2, 5000)
    >>> round(noisevar.estimate(z).std, 1)
    2.0
    """
    spec = method_spec(method)
    valid = spec.validate(params)
    drop = bool(valid.pop("drop_nonfinite", None) or False)
    used = {k: v for k, v in valid.items() if v is not None}
    arr = as_channels(z, axis)
    times = None if t is None else np.asarray(t)
    # scale-safe: run on z 2**e (exact), scale the answer back (docstring of _scale)
    e = _scale.scale_exponent(arr)
    arr_s, used_s = (np.ldexp(arr, e), _scale.scale_params(used, e)) if e else (arr, used)
    results = _records(spec, arr_s, times, drop, used_s, e)
    if arr.ndim == 1:
        return results[0]
    return VarianceEstimates(method, arr.shape[:-1], results, dict(results[0].params))


def estimate_chunked(
    read: Callable[[int, int], NDArray],
    n: int,
    *,
    method: str = DEFAULT_METHOD,
    probe: Callable[[slice], NDArray] | None = None,
    chunk: int | None = None,
    workers: int = 2,
    note: str = "streamed",
    **params: Any,
) -> VarianceEstimate:
    """:func:`estimate` of a record read in chunks: the same numbers, bounded memory.

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b`` as finite float64 (a copy).
    n : int
        Samples in the record.
    method : str
        A method with a chunked engine (``spec.chunked``; ``auto``'s is
        :class:`~noisevar.estimators.auto.ChunkedAuto`).
    probe : callable, optional
        ``probe(slice)`` returns a strided selection (default: through ``read``).
    chunk : int, optional
        Samples per chunk (the engine's default when None).
    workers : int
        Threads.
    note : str
        How the record was read, for the first note ("streamed in chunks of ...").
    **params
        The method's parameters.

    Returns
    -------
    VarianceEstimate
        With its diagnostics (docs/algorithms.md §F5.7); ``jumps`` is not kept.
    """
    spec = method_spec(method)
    if spec.chunked is None:
        able = ", ".join(m.name for m in METHODS.values() if m.chunked is not None)
        raise NoisevarError(
            f"method {method!r} cannot read a record in chunks; methods that can: {able}"
        )
    valid = spec.validate(params)
    if valid.pop("drop_nonfinite", None):
        raise NoisevarError("a record read in chunks must be finite: drop_nonfinite is not taken")
    used = {k: v for k, v in valid.items() if v is not None}
    record = spec.chunked(read, n, probe=probe, chunk=chunk, workers=workers, note=note)
    return run_record(spec, record, used)
