"""Scale-safe estimation: run a method on a copy scaled by an exact power of two.

Every estimator squares differences of samples. With ``|z|`` near 1e154 the squares
overflow; near 1e-155 they underflow to 0. A record whose magnitude is far from 1 is
therefore multiplied by ``2**e`` (exact in binary floating point: no rounding) so that
its largest magnitude is about 1; the method runs on the copy and the variance and its
interval are multiplied back by ``2**(-2e)``. Records of ordinary magnitude
(:data:`SAFE_RANGE`) are not touched, so their results are bit-identical.

The noise-model entry points (``allan``, ``inertial_noise``, ``fit_coloured_noise``,
``fit_kalman``) scale the same way: :func:`scale_exponent` of the record, the fit on the
copy, :func:`scale_back` of each result by its power of the signal's unit; their sample
rate is checked by :func:`check_rate` (``allan`` scales the rate by a power of two too).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import fields, is_dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.quantisation import half_a_step, held_step
from noisevar.errors import NoisevarError

#: Largest magnitudes (powers of two) left as they are: squares and sums of squares of
#: samples in this range neither overflow nor underflow.
SAFE_RANGE = (-100, 100)
#: Parameters in signal units, with their power: scaled along with the samples.
UNIT_PARAMS = {"reference": 1, "reference_variance": 2}
#: Result attributes in variance units (scaled back); other arrays of ``details`` are in
#: signal units (``window_variance`` is a variance).
_VARIANCE_FIELDS = ("variance", "core_variance", "quiet_variance")
_DETAIL_VARIANCES = ("window_variance",)


def scale_exponent(z: NDArray, safe: tuple[int, int] = SAFE_RANGE) -> int:
    """The exponent ``e`` to scale ``z`` by (``2**e``); 0 for records of ordinary size.

    Parameters
    ----------
    z : ndarray of float
        Samples (non-finite values are ignored).
    safe : (int, int)
        Largest magnitudes (powers of two) left as they are (default :data:`SAFE_RANGE`;
        a fit whose numerics need magnitudes nearer 1 gives a narrower range).

    Returns
    -------
    int
    """
    with np.errstate(invalid="ignore"):  # all NaN: no finite sample, NaN extremes
        lo, hi = (float(f.reduce(z, axis=None)) if z.size else 0.0 for f in (np.fmin, np.fmax))
    # fmin/fmax skip NaN; infinite samples are not finite: the largest finite magnitude
    if not (np.isfinite(lo) and np.isfinite(hi)):
        fin = np.abs(z[np.isfinite(z)])
        lo, hi = 0.0, float(fin.max()) if fin.size else 0.0
    return exponent_of(max(abs(lo), abs(hi)) if np.isfinite(lo) and np.isfinite(hi) else 0.0, safe)


def exponent_of(top: float, safe: tuple[int, int] = SAFE_RANGE) -> int:
    """:func:`scale_exponent` of a record whose largest magnitude is ``top``.

    Parameters
    ----------
    top : float
        The largest ``|z|`` (finite; 0 for no sample).
    safe : (int, int)
        As for :func:`scale_exponent`.

    Returns
    -------
    int
    """
    if top == 0.0:
        return 0
    # top = m 2**k with 0.5 <= m < 1
    _, k = math.frexp(top)
    if safe[0] <= k <= safe[1]:
        return 0
    return -k


#: Sample rates (Hz) the noise-model fits take: beyond, their per-second quantities (q in
#: u²/s^k, taus, per-sample terms) leave the floating-point range.
RATE_RANGE = (2.0**-64, 2.0**64)


def check_rate(rate: float | None, name: str = "rate") -> None:
    """Refuse a sample rate that is not a number within :data:`RATE_RANGE` (None passes).

    Raises
    ------
    NoisevarError
        Not a finite positive number, or outside :data:`RATE_RANGE` (one sentence).
    """
    if rate is None:
        return
    if isinstance(rate, bool) or not isinstance(rate, int | float | np.number):
        raise NoisevarError(f"{name} must be a number of samples per second, got {rate!r}")
    if not (math.isfinite(rate) and rate > 0):
        raise NoisevarError(f"{name} must be a positive number of samples per second, got {rate}")
    lo, hi = RATE_RANGE
    if not lo <= rate <= hi:
        raise NoisevarError(
            f"{name} {float(rate):.3g} Hz is outside {lo:.3g} .. {hi:.3g} Hz, where the noise "
            "model's per-second quantities stay in floating-point range: give the rate in "
            "other units (e.g. samples per hour or per microsecond)"
        )


def scale_back(value: Any, shift: int, what: str = "result") -> Any:
    """``value * 2**shift`` (exact), refusing a value that leaves the normal float range.

    Parameters
    ----------
    value : float or ndarray
        A result computed on a scaled copy (NaN passes through).
    shift : int
        The power of two to multiply by (``-power * e`` for a result in the signal's unit
        to the ``power``, computed on the record scaled by ``2**e``).
    what : str
        The result's name, for the message.

    Returns
    -------
    float or ndarray
        Of the same kind as ``value``.

    Raises
    ------
    NoisevarError
        A finite non-zero value that would overflow, or fall below the smallest normal
        number (where it would lose its precision), in the record's units.
    """
    if shift == 0 or value is None:
        return value
    arr = np.asarray(value, dtype=float)
    fin = arr[np.isfinite(arr) & (arr != 0)]
    if fin.size:
        top = math.frexp(float(np.max(np.abs(fin))))[1] + shift
        low = math.frexp(float(np.min(np.abs(fin))))[1] + shift
        if top > 1024 or low < -1021:
            side = "larger than the largest" if top > 1024 else "smaller than the smallest normal"
            raise NoisevarError(
                f"the {what} of this record is {side} floating-point number: rescale the "
                "record (change its units) first"
            )
    out = np.ldexp(arr, shift)
    return float(out) if np.ndim(value) == 0 else out


def scale_params(params: dict[str, Any], e: int) -> dict[str, Any]:
    """``params`` with the ones in signal units (:data:`UNIT_PARAMS`) scaled by ``2**e``."""
    if e == 0:
        return params
    out = dict(params)
    for name, power in UNIT_PARAMS.items():
        if out.get(name) is not None:
            out[name] = np.ldexp(np.asarray(out[name], dtype=float), power * e)
            if np.ndim(out[name]) == 0:
                out[name] = float(out[name])
    return out


def _unscale_details(details: Any, e: int) -> None:
    if details is None or not is_dataclass(details):
        return
    for f in fields(details):
        val = getattr(details, f.name)
        if isinstance(val, np.ndarray) and val.dtype.kind == "f":
            power = 2 if f.name in _DETAIL_VARIANCES else 1
            with np.errstate(over="ignore", under="ignore"):
                setattr(details, f.name, np.ldexp(val, -power * e))


def _check_representable(result: Any, e: int) -> None:
    """Refuse a variance that exists on the scaled copy but not in the record's units."""
    var = float(result.variance)
    if not (math.isfinite(var) and var > 0.0):
        return  # degenerate on the copy too: check_answer says so
    # log2(variance in the record's units) = log2(var) - 2e
    log2 = math.log2(var) - 2 * e
    if log2 >= 1024 or log2 < -1074:
        side = "larger than the largest" if log2 > 0 else "smaller than the smallest"
        raise NoisevarError(
            f"the noise variance of this record (about 2^{log2:.0f}) is {side} floating-point "
            "number: rescale the record (change its units) first"
        )


def unscale(results: Sequence[Any], e: int) -> None:
    """Scale results computed on ``z * 2**e`` back to the units of ``z`` (in place)."""
    if e == 0:
        return
    for r in results:
        _check_representable(r, e)
        for name in _VARIANCE_FIELDS:
            val = getattr(r, name, None)
            if isinstance(val, float):
                with np.errstate(over="ignore", under="ignore"):
                    setattr(r, name, float(np.ldexp(val, -2 * e)))
        with np.errstate(over="ignore", under="ignore"):
            r.ci95 = tuple(float(np.ldexp(c, -2 * e)) for c in r.ci95)
        for name, power in UNIT_PARAMS.items():
            if isinstance(r.params.get(name), float):
                r.params[name] = float(np.ldexp(r.params[name], -power * e))
        _unscale_details(getattr(r, "details", None), e)
        r.notes.append(f"computed on a copy scaled by 2^{e} (exact) to keep the squares in range")


class ZeroVariance(NoisevarError):
    """:func:`check_answer`'s refusal of a variance of 0 (:func:`held_refusal` may say
    more)."""


def held_refusal(z: NDArray, method: str, found: float = 0.0) -> NoisevarError | None:
    """The refusal of a variance of 0 on samples ``z`` (in the record's units) held on a
    grid (most samples repeat the one before): the noise is under the resolution, and the
    rounding error is the R to use; None when ``z`` is not held or on no grid (a line).

    Notes
    -----
    docs/algorithms.md §E3 (*Held values*): GENEActiv's temperature, 0.1 °C values held for
    hundreds of samples, was told to "try another method such as 'rice'", whose R would be
    its steps'.
    """
    moves = int(np.count_nonzero(np.diff(z)))
    step = held_step(z) if 2 * moves < z.size else None  # most samples repeat the last
    if step is None:
        return None
    every = f", every {z.size / moves:.0f} samples on average" if moves else ""
    return NoisevarError(
        f"method {method!r} found a noise variance of {found:.3g} on this record: its values "
        "are held "
        f"on a grid of step {step:.4g} (they change {moves} times in {z.size} samples{every}), "
        "so the sensor's noise is under the resolution and cannot be measured; a filter "
        f"reading them sees their rounding error: use R = lsb²/12 = {step * step / 12:.4g} "
        f"(a bound: at most (1/4 + 1/12) lsb² = {half_a_step(step):.4g} while the noise stays "
        "under half a step), or record the sensor at a finer resolution"
    )


def refusing_held(run: Callable[..., Any], z: NDArray, scaled: int, method: str) -> Any:
    """``run``, raising :func:`held_refusal` of ``z`` (the samples times ``2**scaled``) in
    place of a :class:`ZeroVariance`, or of an answer with no diagnostics (its residual
    degenerate), when ``z`` is held on a grid.

    Notes
    -----
    A slow signal on a 0.1 grid with noise far under the step (flips at its crossings, held
    between): R 1.1e-7, 7,500x under lsb²/12, with no diagnostics and no verdict, where the
    same record crossing one more step was refused as held (benchmarks/real_audit19.py)."""

    @functools.wraps(run)
    def refusing(*args: Any, **kwargs: Any) -> Any:
        try:
            out = run(*args, **kwargs)
        except ZeroVariance as exc:
            raise (held_refusal(np.ldexp(z, -scaled), method) or exc) from None
        # a residual with no variation to diagnose: held values whose R is a few flips'
        if out.diagnostics is not None:
            return out
        with np.errstate(over="ignore", under="ignore"):  # a variance past float's range
            found = float(np.ldexp(out.variance, -2 * scaled))
        if (held := held_refusal(np.ldexp(z, -scaled), method, found)) is not None:
            raise held
        return out

    return refusing


def check_answer(result: Any) -> None:
    """Refuse a degenerate answer: a non-finite or zero variance, or an unusable interval.

    Raises
    ------
    NoisevarError
        Naming the method and what to do.
    """
    var = float(result.variance)
    lo, hi = (float(c) for c in result.ci95)
    name = result.method
    if not math.isfinite(var):
        raise NoisevarError(
            f"method {name!r} found no finite noise variance on this record: its noise is "
            "larger than floating point can square; rescale the record first"
        )
    if var <= 0.0:
        raise ZeroVariance(
            f"method {name!r} found a noise variance of {var:.3g} on this record (not positive: "
            "the noise is below the method's resolution, e.g. quantised samples, or a known "
            "reference variance is too large): try another method such as 'rice'"
        )
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= var <= hi):
        raise NoisevarError(
            f"method {name!r} gave no usable confidence interval on this record (the fit is "
            "degenerate): the noise is not identifiable by this method; try another one"
        )


def held_but_for(result: Any) -> None:
    """Refuse a record that holds one value but for its outlying samples (no diagnostics).

    Raises
    ------
    NoisevarError
        When the estimate without its outlying samples is 0: a trigger or event channel
        (0 with one-sample pulses), whose R would be the pulses' alone, with an interval
        from their count.
    """
    if result.core_variance == 0.0 and result.outlier_fraction > 0.0:
        k = round(result.outlier_fraction * result.n_used)
        raise NoisevarError(
            f"the signal holds one value but for {k} sample{'' if k == 1 else 's'} "
            f"({100 * result.outlier_fraction:.2g}%): a trigger or event channel, or a "
            "sensor far below its resolution; between them its noise variance is 0 and "
            "there is nothing to estimate"
        )
