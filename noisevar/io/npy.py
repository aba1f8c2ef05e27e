"""``.npy`` arrays, read without pickle."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.io.table import (
    LoadedTable,
    _period_from_time,
    echo,
    is_time_column,
    pick_time_column,
    time_in_seconds,
)
from noisevar.io.text import EXACT_INT, MAX_COLUMNS
from noisevar.io.time_option import StatedTime


def _load(source: Path | bytes, name: str) -> np.ndarray:
    """The array of a ``.npy`` file: memory-mapped from a path, never unpickled."""
    try:
        if isinstance(source, Path):
            return np.load(source, mmap_mode="r", allow_pickle=False)
        return np.load(io.BytesIO(source), allow_pickle=False)
    except ValueError as exc:
        if "pickle" in str(exc).lower():
            raise NoisevarError(
                f"{echo(name)} holds Python objects (a pickled array), which are refused for "
                "safety: save a numeric array with np.save"
            ) from None
        raise NoisevarError(f"{echo(name)} is not a valid .npy file ({echo(exc, 200)})") from None
    except Exception as exc:  # noqa: BLE001 - np.load raises several types on corrupt files
        raise NoisevarError(
            f"{echo(name)} is not a valid .npy file ({type(exc).__name__})"
        ) from None


def _as_float(values: np.ndarray, field: str, name: str, column: str = "") -> NDArray:
    """One column as floats: real numbers only, integers exactly representable (``field``
    names it in messages; ``column``, its name, says whether it is a time column)."""
    kind = values.dtype.kind
    if kind not in "biuf":
        what = "complex" if kind == "c" else f"of dtype {values.dtype}"
        raise NoisevarError(
            f"{echo(name)}: {field} is {what}, not real numbers: save real samples "
            "(for complex data, the real and imaginary parts as two fields)"
        )
    if kind in "iu" and values.size:
        top = max(abs(int(values.max())), abs(int(values.min())))
        if top > EXACT_INT:
            if column and is_time_column(column):
                # t - t[0] in integers (exact), then float
                return (values.astype(object) - int(values[0])).astype(float)
            raise NoisevarError(
                f"{echo(name)}: {field} holds integers beyond 2**53 (up to {float(top):.3g}), "
                "which floating point cannot hold exactly (precision lost): subtract an "
                "offset first"
            )
    return np.array(values, dtype=float)


def _read_npy(source: Path | bytes, name: str, told: StatedTime | None = None) -> LoadedTable:
    arr = _load(source, name)
    if not isinstance(arr, np.ndarray):  # pragma: no cover - .npz is read by np.load too
        raise NoisevarError(f"{echo(name)} is not a single .npy array")
    notes: list[str] = []
    if arr.dtype.names:
        if arr.ndim != 1:
            raise NoisevarError(f"{name}: a structured array must be 1-D, got shape {arr.shape}")
        if len(arr.dtype.names) > MAX_COLUMNS:
            raise NoisevarError(
                f"{echo(name)} has {len(arr.dtype.names):,} fields, over the limit of {MAX_COLUMNS}"
            )
        columns = {}
        for fname in arr.dtype.names:
            if arr.dtype[fname].shape:
                raise NoisevarError(
                    f"{echo(name)}: field {echo(fname)!r} is a sub-array: give scalar fields"
                )
            columns[fname] = _as_float(arr[fname], f"field {echo(fname)!r}", name, fname)
    else:
        _as_float(np.empty(0, arr.dtype), "the array", name)
        if arr.ndim == 0 or arr.size == 0:
            raise NoisevarError(
                f"{echo(name)} is empty or a single number: give a 1-D or 2-D array"
            )
        if arr.ndim == 1:
            columns = {"value": _as_float(arr, "the array", name)}
        elif arr.ndim == 2:
            if arr.shape[0] < arr.shape[1] and arr.shape[0] <= 16:
                notes.append(f"array of shape {arr.shape} read as {arr.shape[0]} rows of signals")
                arr = arr.T
            if arr.shape[1] > MAX_COLUMNS:
                raise NoisevarError(
                    f"{echo(name)} has {arr.shape[1]:,} columns, over the limit of {MAX_COLUMNS}"
                )
            columns = {
                f"col{i}": _as_float(arr[:, i], f"col{i}", name) for i in range(arr.shape[1])
            }
        else:
            raise NoisevarError(
                f"{echo(name)} has shape {arr.shape}: give a 1-D signal or a 2-D (samples, "
                "columns) array"
            )
    idx = pick_time_column(list(columns))
    time_col = None if idx is None else list(columns)[idx]
    if time_col:
        first = float(arr[time_col][0]) if arr.dtype.names and arr.size else None
        time_in_seconds(columns, time_col, notes, first, told=told)
    period = _period_from_time(columns[time_col], notes) if time_col else None
    return LoadedTable(name, columns, "npy", time_col, period, notes)
