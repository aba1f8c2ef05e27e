"""``.npy`` arrays, read without pickle."""

from __future__ import annotations

import io

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.io.table import LoadedTable, _is_time_name, _period_from_time


def _read_npy(raw: bytes, name: str) -> LoadedTable:
    try:
        arr = np.load(io.BytesIO(raw), allow_pickle=False)
    except ValueError as exc:
        if "pickle" in str(exc).lower():
            raise NoisevarError(
                f"{name} holds Python objects (a pickled array), which are refused for safety: "
                "save a numeric array with np.save"
            ) from None
        raise NoisevarError(f"{name} is not a valid .npy file ({exc})") from None
    except Exception as exc:  # noqa: BLE001 - np.load raises several types on corrupt files
        raise NoisevarError(f"{name} is not a valid .npy file ({type(exc).__name__})") from None
    if not isinstance(arr, np.ndarray):  # pragma: no cover - .npz is read by np.load too
        raise NoisevarError(f"{name} is not a single .npy array")
    notes: list[str] = []
    if arr.dtype.names:
        if arr.ndim != 1:
            raise NoisevarError(f"{name}: a structured array must be 1-D, got shape {arr.shape}")
        columns = {}
        for fname in arr.dtype.names:
            try:
                columns[fname] = np.asarray(arr[fname], dtype=float)
            except (TypeError, ValueError):
                raise NoisevarError(f"{name}: field {fname!r} is not numeric") from None
    else:
        if arr.dtype.kind not in "biuf":
            raise NoisevarError(
                f"{name}: the array has dtype {arr.dtype}, not real numbers "
                "(give int or float samples)"
            )
        if arr.ndim == 0 or arr.size == 0:
            raise NoisevarError(f"{name} is empty or a single number: give a 1-D or 2-D array")
        if arr.ndim == 1:
            columns = {"value": arr.astype(float)}
        elif arr.ndim == 2:
            if arr.shape[0] < arr.shape[1] and arr.shape[0] <= 16:
                notes.append(f"array of shape {arr.shape} read as {arr.shape[0]} rows of signals")
                arr = arr.T
            columns = {f"col{i}": arr[:, i].astype(float) for i in range(arr.shape[1])}
        else:
            raise NoisevarError(
                f"{name} has shape {arr.shape}: give a 1-D signal or a 2-D (samples, columns) array"
            )
    time_col = next((c for c in columns if _is_time_name(c)), None)
    period = _period_from_time(columns[time_col], notes) if time_col else None
    return LoadedTable(name, columns, "npy", time_col, period, notes)
