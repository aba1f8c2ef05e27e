"""Input checks shared by the estimators: one signal, many channels, sample times."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import check_exact_ints, steps_evenly
from noisevar.errors import EmptyCells, NoisevarError


def _refuse_kind(kind: str, what: str) -> None:
    if kind == "c":
        raise NoisevarError(
            f"{what} is complex: give real samples (for example the real part, the imaginary "
            "part or the magnitude, estimated separately)"
        )
    if kind in "Mm":
        raise NoisevarError(
            f"{what} holds dates or durations, not measurements: give numbers (times go in t)"
        )


def _as_float_array(z: ArrayLike, what: str = "the signal") -> NDArray:
    """``z`` as floats; a masked array's masked samples become NaN (a gap)."""
    if isinstance(z, np.ma.MaskedArray):
        _refuse_kind(z.dtype.kind, what)
        try:
            return np.ma.getdata(z.astype(float).filled(np.nan))
        except (TypeError, ValueError):
            raise NoisevarError(f"{what} is not numeric: give an array of numbers") from None
    dtype = getattr(z, "dtype", None)
    if dtype is not None:
        _refuse_kind(getattr(dtype, "kind", ""), what)
        if str(dtype).startswith(("datetime", "timedelta", "period", "interval")):
            _refuse_kind("M", what)
    try:
        arr = np.asarray(z)
    except (TypeError, ValueError, OverflowError):
        raise NoisevarError(f"{what} is not numeric: give an array of numbers") from None
    _refuse_kind(arr.dtype.kind, what)
    check_exact_ints(arr, what)
    try:
        return arr.astype(float, copy=False)
    except (TypeError, ValueError, OverflowError):
        raise NoisevarError(f"{what} is not numeric: give an array of numbers") from None


def check_samples(arr: NDArray, drop_nonfinite: bool = False) -> tuple[NDArray, list[str]]:
    """Check a 1-D float array: finite (or drop non-finite samples), long enough, not constant.

    Parameters
    ----------
    arr : ndarray of float, shape (n,)
        Samples.
    drop_nonfinite : bool
        Drop NaN/Inf samples (and say how many) instead of refusing them.

    Returns
    -------
    z : ndarray of float, shape (n_kept,)
    notes : list of str
    """
    notes: list[str] = []
    bad = ~np.isfinite(arr)
    if bad.any():
        first = int(np.argmax(bad))
        if not drop_nonfinite:
            raise EmptyCells(
                f"the signal has {int(bad.sum())} non-finite values (NaN or Inf), the first at "
                f"sample {first}: clean them, or drop them with drop_nonfinite=True "
                "(CLI: --drop-nonfinite)"
            )
        arr = arr[~bad]
        notes.append(f"dropped {int(bad.sum())} non-finite samples (first at sample {first})")
    if arr.size == 0:
        raise NoisevarError("the signal is empty: give at least a few hundred samples")
    if arr.size < 8:
        raise NoisevarError(f"the signal has only {arr.size} samples: give at least 100")
    if not arr.flags.writeable:  # e.g. a memory-mapped file; PyWavelets needs writable input
        arr = arr.copy()
    if np.ptp(arr) == 0:
        raise NoisevarError(
            "the signal is constant: its noise variance is 0 and there is nothing to estimate "
            "(a field the logger never changes?): give a channel that varies"
        )
    if steps_evenly(arr):
        raise NoisevarError(
            "the signal steps by the same amount every sample (a counter or a clock, not a "
            "measurement): its noise variance is 0 and there is nothing to estimate: give a "
            "measured channel (a table's row numbers or time stamps are no signal)"
        )
    return arr, notes


def as_signal(z: ArrayLike, drop_nonfinite: bool = False) -> tuple[NDArray, list[str]]:
    """Validate one signal: numeric, 1-D, finite (or drop non-finite samples), not constant.

    Parameters
    ----------
    z : array_like
        Samples (an ``(n, 1)`` or ``(1, n)`` array counts as one signal).
    drop_nonfinite : bool
        Drop NaN/Inf samples (and say how many) instead of refusing them.

    Returns
    -------
    z : ndarray of float, shape (n,)
    notes : list of str
    """
    arr = _as_float_array(z)
    arr = np.squeeze(arr) if arr.ndim > 1 and 1 in arr.shape else arr
    if arr.ndim != 1:
        raise NoisevarError(
            f"expected one signal (a 1-D array), got shape {arr.shape}: pick one column"
        )
    return check_samples(arr, drop_nonfinite)


def as_channels(z: ArrayLike, axis: int) -> NDArray:
    """``z`` as a float array with the sample axis last; 1-D when it holds one signal.

    An array whose only non-unit axis holds the samples (``(n, 1)``, ``(1, n)``)
    is one signal, whatever ``axis`` says, as :func:`as_signal` has it.
    """
    arr = _as_float_array(z)
    if arr.ndim == 0:
        raise NoisevarError("expected a signal (an array of samples), got a single number")
    if arr.ndim > 1 and np.squeeze(arr).ndim == 1:
        return np.squeeze(arr)
    try:
        return np.moveaxis(arr, axis, -1)
    except np.exceptions.AxisError:
        raise NoisevarError(
            f"axis={axis} is out of range for an array of shape {arr.shape}"
        ) from None


def check_times(t: ArrayLike, n: int) -> NDArray:
    """Validate sample times: 1-D, ``n`` of them, finite and strictly increasing.

    Non-uniform steps are allowed: the record is split there into uniform segments
    (:func:`noisevar.diagnostics.split_times`).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times.
    n : int
        Number of samples along the estimation axis.

    Returns
    -------
    ndarray of float, shape (n,)
    """
    arr = _as_float_array(t, "t")
    if arr.ndim != 1 or arr.size != n:
        raise NoisevarError(
            f"t must give one time per sample: {n} samples, but t has shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise NoisevarError("t has NaN or Inf values: give a finite time for every sample")
    dt = np.diff(arr)
    if np.any(dt <= 0):
        first = int(np.argmax(dt <= 0))
        raise NoisevarError(
            f"t must be strictly increasing: t[{first + 1}] <= t[{first}]; sort the record first"
        )
    return arr


def check_window(window: object, n: int, need: int = 1) -> int:
    """``window`` as an int of at least 8 samples that fits ``need`` times in ``n`` samples."""
    try:
        m = int(window)  # type: ignore[call-overload]
    except (TypeError, ValueError):
        raise NoisevarError(f"window must be an integer, got {window!r}") from None
    if m != window or m < 8:
        raise NoisevarError(f"window must be an integer of at least 8 samples, got {window}")
    if n < need * m:
        raise NoisevarError(
            f"too few samples for the window: {n} samples, window {m} "
            f"(need at least {need * m}); use a smaller window or a longer record"
        )
    return m
