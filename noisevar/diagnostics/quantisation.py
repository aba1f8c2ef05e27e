"""Samples on a grid: the quantisation step (docs/algorithms.md §E3)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: Samples used to propose a step; the whole record then confirms it.
LSB_PROBE = 4096
#: A sample is on the grid when within this fraction of a step of a grid point.
LSB_TOL = 1e-3
#: A second difference up to this many times float64's epsilon times the largest sample is
#: float rounding (a held stretch plus a trend), not a step: its three samples carry up to
#: half a unit in the last place each, weighed 1, 2, 1.
ROUNDING_EPS = 8 * float(np.finfo(float).eps)
#: The same for samples that passed through float32 (:func:`second_difference_step`).
F32_EPS = 8 * float(np.finfo(np.float32).eps)
#: A grid step of second differences is at least this many times their float rounding.
ROUNDING_STEPS = 16
#: float32's rounding seen in the samples: up to this many of their smallest second
#: difference (half a unit in the last place on each of three samples weighed 1, 2, 1 is
#: 2 units; 4 more for units that differ across binades).
F32_SEEN = 8
#: Fewest second differences above float32's rounding that a grid read there needs: random
#: values fall within LSB_TOL of a multiple of the least 1 time in 500 at most, so 8 that
#: all do are no chance (an offset over a reset left one, the reset's, read as a "grid").
F32_CONFIRM = 8
#: Rounding to the decimal digits the samples are written with (the largest power of ten
#: every first difference is a whole multiple of), seen in a second difference: half a unit
#: on each of three samples weighed 1, 2, 1 is 2 units at most.
WRITTEN_SEEN = 2
#: A first difference on the written resolution is within this fraction of a unit of a
#: whole multiple: float64's rounding at the values' size before an offset moved them
#: (926.146 - 900 keeps 926's); random values fall there 1 time in 5e5.
UNIT_TOL = 1e-6


def half_a_step(lsb: float) -> float:
    """The error variance of noise of half a grid step ``lsb``: ``(1/4 + 1/12) lsb²``.

    Below it, the noise is under half a step and the error a sample carries follows the
    signal's offset within a step (docs/algorithms.md §E3): quantisation, not a level of
    its own.
    """
    # σ² + Δ²/12 with σ = Δ/2
    return lsb * lsb * (0.25 + 1.0 / 12.0)


def second_difference_step(z: NDArray) -> float | None:
    """The step of the grid the samples' second differences sit on (0 when they are all 0).

    Parameters
    ----------
    z : ndarray
        Consecutive samples.

    Returns
    -------
    float or None
        The smallest second difference above float rounding (:data:`ROUNDING_EPS` times the
        largest ``|z|``), when it is at least :data:`ROUNDING_STEPS` times that rounding
        and every second difference is a whole multiple of it (to :data:`LSB_TOL` plus the
        rounding); 0.0 when none is above float rounding (held values, a line); None off a
        grid.

    Notes
    -----
    docs/algorithms.md §E3 (*Held values*). A linear trend or an offset adds nothing to a
    second difference, so the grid of a record held on a grid stays found under them
    (the distinct values' step needs the samples themselves on it). The first :data:`LSB_PROBE`
    second differences are tried first: a record off any grid (most) costs no pass over
    the whole (a probe whose smallest second difference is not its grid is taken for off a
    grid).
    """
    if z.size < 3:
        return 0.0
    if z.size > LSB_PROBE + 2 and _stored_step(z[: LSB_PROBE + 2]) is None:
        return None
    return _stored_step(z)


def _stored_step(z: NDArray) -> float | None:
    """:func:`_d2_step` at float64's rounding, else at float32's.

    A grid scaled into float32 (counts times a calibration, as HDF5 and netCDF files keep
    them) is off by float32's rounding, far above float64's, and stays so when the values
    are scaled or moved after: there the smallest second difference above float64's
    rounding is float32's own spacing (or none is on a grid), not the grid. An offset far
    above the values leaves that spacing as it was, under ``F32_EPS`` times the moved
    values: the rounding is then read off the samples, :data:`F32_SEEN` times that
    spacing (GOES's flux plus 1e4 standard deviations lost its grid). Second
    differences that are whole multiples of one step at float32's rounding are a grid all
    the same (random values are not: each of thousands would have to fall within
    :data:`LSB_TOL` of a multiple).
    """
    step = _d2_step(z, ROUNDING_EPS)
    if step is None or (step > 0 and _power_of_ten(step)):  # under the written digits?
        written = _above_resolution(z)
        if written:
            return written
    if step is not None and step >= F32_EPS * float(np.max(np.abs(z))):
        coarse = _float32_spacing_moved(z, step)
        return coarse or step  # coarser than float32's rounding: a grid (most grids end here)
    eps = F32_EPS
    wide = _d2_step(z, eps)
    seen = step or _least_d2(z)  # float32's rounding at the values' own scale, moved after
    if not wide and seen:  # none found, or all under float32 rounding at a moved scale
        eps = F32_SEEN * seen / float(np.max(np.abs(z)))
        wide = _d2_step(z, eps)
    found = (_confirmed(z, eps, wide) if wide else None) or step
    return _step_over_gap(z) if found is None else found


def _step_over_gap(z: NDArray) -> float | None:
    """The grid whose least second difference is at least ``1 / LSB_TOL`` times every
    smaller one above float64's rounding (those are rounding, on the grid's 0, and at most
    float32's rounding of the largest ``|z|``), read with that rounding as in
    :func:`_stored_step` and confirmed by :data:`F32_CONFIRM` second differences above it;
    else None.

    Notes
    -----
    docs/algorithms.md §E3 (*A rounding seen under the step*). Rounding that scales with
    each sample's own size (decimals or float32 digits of values near 0) is not a fixed
    fraction of the largest ``|z|``: an offset far above the values leaves it as it was,
    above float64's rounding of the moved values and under float32's, which covers the
    step. A tolerance taken from the step (:data:`LSB_TOL`), not from the values' size, reads
    the same grid at any offset or trend.
    """
    top = float(np.max(np.abs(z)))
    d2 = np.abs(np.diff(z, 2))
    seen = np.unique(d2[d2 > ROUNDING_EPS * top])
    gaps = seen[:-1] <= LSB_TOL * seen[1:]
    # rounding a storage format makes: at most float32's of the largest value (noise
    # 1e4 times under a few equal jumps is no rounding, and the jumps no grid)
    for j in np.flatnonzero(gaps & (seen[:-1] <= F32_EPS * top)):
        eps = float(seen[j]) / top  # every second difference up to it is rounding
        wide = _d2_step(z, eps)
        found = _confirmed(z, eps, wide) if wide else None
        if found:
            return found
    return None


def written_resolution(z: NDArray) -> float | None:
    """The largest power of ten that every second difference of ``z`` is a whole multiple
    of, to float64's rounding or :data:`UNIT_TOL` of it (the decimal digits the samples
    were written with); None when there is none above :data:`ROUNDING_STEPS` times float64's
    rounding, or no second difference above it.

    Notes
    -----
    Second differences see neither an offset nor a linear trend, so neither does this
    resolution: 926.146 m written in mm has 0.001 at +0, at +1000 m and on a ramp. Binary
    digits (float32) are not read here: float32 rounding scaled after is no written digit
    (:func:`_stored_step`).
    """
    tol = ROUNDING_EPS * float(np.max(np.abs(z), initial=0.0))
    d = np.abs(np.diff(z, 2))
    d = d[d > tol]
    if not d.size:
        return None
    k = np.floor(np.log10(float(d.min())))
    # at least the smallest normal float: a record of subnormal values has tol 0, and
    # 10**k reaches 0 (the loop would not end)
    least = max(ROUNDING_STEPS * tol, float(np.finfo(float).tiny))
    while (unit := float(10.0**k)) >= least:
        near = max(tol, UNIT_TOL * unit)
        if _multiples(d[:64], unit, near) and _multiples(d, unit, near):
            return unit
        k -= 1
    return None


def _power_of_ten(x: float) -> bool:
    """``x`` is a power of ten (to float64's rounding of its logarithm)."""
    e = float(np.log10(x))
    return abs(e - round(e)) < 1e-9


def _multiples(d: NDArray, unit: float, tol: float) -> bool:
    """Every ``d`` within ``tol`` of a whole multiple of ``unit``."""
    return bool(np.max(np.abs(d - np.rint(d / unit) * unit)) <= tol)


def _above_resolution(z: NDArray) -> float | None:
    """The grid the second differences sit on up to the rounding of the samples' written
    digits (:data:`WRITTEN_SEEN` times :func:`written_resolution`), at least
    :data:`ROUNDING_STEPS` times that rounding, confirmed by :data:`F32_CONFIRM` second
    differences above it and read from every multiple; else None.

    Notes
    -----
    docs/algorithms.md §E3 (*The grid of the second differences*): Polar's altitude, a
    0.1524 m grid written in mm (926.146), is off its grid by the mm, at every offset.
    """
    unit = written_resolution(z)
    if unit is None:
        return None
    tol = WRITTEN_SEEN * unit + ROUNDING_EPS * float(np.max(np.abs(z)))
    d2 = np.abs(np.diff(z, 2))
    big = d2[d2 > tol]
    if big.size < F32_CONFIRM or float(big.min()) <= ROUNDING_STEPS * tol:
        return None
    step = float(big.min())
    if float(big.max()) / step > 1e9:
        return None
    one = big[big < 1.5 * step]  # a step apart: no multiple to mistake
    step = float(one.mean())
    step = float(big.sum() / np.rint(big / step).sum())
    return step if _multiples(big, step, tol + LSB_TOL * step) else None


def _float32_spacing_moved(z: NDArray, step: float) -> float | None:
    """The grid above ``step`` when ``step`` is float32's spacing at the values' scale
    before an offset moved them (a power of two, every second difference a multiple of
    it): read with second differences up to :data:`F32_SEEN` steps taken for rounding,
    confirmed as in :func:`_stored_step`; else None.

    Notes
    -----
    An altitude on a 0.2 m grid written through float32 (473.7999878) sits on float32's
    spacing there, 2^-15; moved by -470 it keeps that spacing, which is then coarser
    than float32's rounding at the moved values and was taken for the grid.
    """
    if np.frexp(step)[0] != 0.5:  # not a power of two: not float32's spacing
        return None
    eps = F32_SEEN * step / float(np.max(np.abs(z)))
    wide = _d2_step(z, eps)
    return _confirmed(z, eps, wide) if wide and wide > step else None


def _confirmed(z: NDArray, eps: float, wide: float) -> float | None:
    """The grid step ``wide`` read at rounding ``eps``, from every multiple (not the least
    alone), when at least :data:`F32_CONFIRM` second differences are above that rounding;
    else None."""
    d2 = np.abs(np.diff(z, 2))
    if np.count_nonzero(d2 > eps * float(np.max(np.abs(z)))) < F32_CONFIRM:
        return None
    return float(d2.sum() / np.rint(d2 / wide).sum())


def _least_d2(z: NDArray) -> float:
    """The smallest second difference above float64's rounding (0.0 when none is): where
    the values moved after float32 kept its rounding (an altitude of 473.7999878 moved by
    -470: 13.7999878), the float32 rounding they carry."""
    d2 = np.abs(np.diff(z, 2))
    above = d2 > ROUNDING_EPS * float(np.max(np.abs(z)))
    return float(np.min(d2, where=above, initial=np.inf)) if above.any() else 0.0


def _d2_step(z: NDArray, eps: float) -> float | None:
    """:func:`second_difference_step` of ``z`` (at least 3 samples), over all of it, with
    second differences up to ``eps`` times the largest ``|z|`` taken for rounding."""
    d2 = np.abs(np.diff(z, 2))
    tol = eps * float(np.max(np.abs(z)))
    d2[d2 <= tol] = 0.0  # float rounding
    top = float(d2.max())
    if not top > 0:
        return 0.0
    step = float(np.min(d2, where=d2 > 0, initial=top))
    if step <= ROUNDING_STEPS * tol or top / step > 1e9:
        return None
    if _on_multiples(d2, step, tol):
        return step
    step = _least_squares_step(d2, step, tol)
    return step if _on_multiples(d2, step, tol) else None


def _on_multiples(d2: NDArray, step: float, tol: float) -> bool:
    """Every ``d2`` within :data:`LSB_TOL` of a step plus ``tol`` of a whole multiple of
    ``step``: in pieces, so that a record off any grid (most) is told at its first piece."""
    for a in range(0, d2.size, LSB_PROBE):
        r = d2[a : a + LSB_PROBE] / step
        if not float(np.max(np.abs(r - np.rint(r)))) < LSB_TOL + tol / step:
            return False
    return True


def _least_squares_step(d2: NDArray, step: float, tol: float) -> float:
    """The step read from every second difference, ``Σ d2 / Σ k`` (``k`` steps each), when
    the least one's rounding ``tol`` can mistake none of their multiples (``k`` at most a
    half of ``step / tol``); else ``step`` as it was.

    Notes
    -----
    The least second difference carries up to ``tol`` of float rounding, and ``k`` steps
    read with it carry ``k`` times that: 0.1 mm heights moved by 1.4e4 m read a step 3e-8
    off, and a second difference of 1e5 steps fell 3e-3 of a step off its multiple.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # subnormal steps
        k = np.rint(d2 / step)
        # a multiple the rounding could mistake (or no rounding measured: tol 0)
        if not (tol > 0 and float(k.max()) * tol <= 0.5 * step):
            return step
        found = float(d2.sum() / k.sum())
    return found if np.isfinite(found) and found > 0 else step


def joined_step(steps: list[float | None]) -> float | None:
    """The grid step of a record from its parts' :func:`second_difference_step`.

    None when a part is off a grid or the steps are not whole multiples of the smallest;
    parts with no step (0.0) say nothing.
    """
    if any(s is None for s in steps):
        return None
    found = np.array([s for s in steps if s], dtype=float)
    if not found.size:
        return None
    step = float(found.min())
    return step if on_grid(found, step) else None


def level_step(levels: NDArray) -> float | None:
    """The grid step of sorted distinct values ``levels`` (at least 2): their smallest gap,
    when every gap is a whole multiple of it and float64 resolves the grid (the span under
    1e9 steps); else None."""
    steps = np.diff(levels)
    step = float(steps.min())
    with np.errstate(over="ignore"):  # a span beyond the float range: inf, not a grid
        span = float(levels[-1] - levels[0])
    if step <= 0 or span / step > 1e9:
        return None
    return step if on_grid(steps, step) else None


def held_step(z: NDArray) -> float | None:
    """The grid step of held values ``z``: their distinct values' :func:`level_step`, else
    their :func:`written_resolution` (a staircase of 0.2 and 0.3 steps written with one
    decimal is on a grid of 0.1 at least); None on neither."""
    levels = np.unique(z)
    step = level_step(levels) if levels.size >= 2 else None
    return step or written_resolution(z)


def on_grid(x: NDArray, step: float) -> bool:
    """Every ``x / step`` within :data:`LSB_TOL` of an integer."""
    r = x / step
    return bool(np.max(np.abs(r - np.rint(r)), initial=0.0) < LSB_TOL)
