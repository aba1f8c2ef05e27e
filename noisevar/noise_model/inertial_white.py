"""The white level of rate data and N's interval held against it (docs/algorithms.md §E4)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray


def white_level(y: ArrayLike, rate: float) -> float:
    """The white level ``sigma(tau0) sqrt(tau0)`` of rate data (unit/√Hz).

    Parameters
    ----------
    y : array_like, shape (n,)
        Rate samples.
    rate : float
        Sample rate (Hz).

    Returns
    -------
    float

    Notes
    -----
    docs/algorithms.md §E4. At ``tau0 = 1/fs`` the overlapping Allan variance is
    ``mean(diff(y)²) / 2``, so this is the std of first differences over ``sqrt(2 fs)``:
    ``N`` exactly for white rate noise, ``sqrt(N² + 3 Q² fs)`` with quantisation
    (its per-sample variance is ``2 Q² fs²``: counted 1.5x, on the safe side), and
    blind to a slow bias.
    """
    d = np.diff(np.asarray(y, dtype=float))
    return math.sqrt(float(np.mean(d**2)) / 2.0 / rate)


def tau0_holders(coef: NDArray, weights: NDArray, labels: Sequence[str]) -> str:
    """The terms other than N that hold the fitted Allan variance at tau0, with their shares.

    Parameters
    ----------
    coef : ndarray
        The squared terms ``(Q², N², B², K², R²)``.
    weights : ndarray
        Each squared term's weight in the white level squared (E4.2: ``3 fs``, 1,
        ``2 ln 2 / (pi fs)``, ...).
    labels : sequence of str
        Each term's label, e.g. ``"B (bias instability)"``.

    Returns
    -------
    str
        ``"B (bias instability) 81 %, Q (quantization) 3 %"``, largest first; shares
        under 0.5 % are left out; empty when N holds it all.
    """
    parts = np.asarray(coef, dtype=float) * weights
    total = float(np.sum(parts))
    if not total > 0:
        return ""
    shares = sorted(((p / total, lab) for i, (p, lab) in enumerate(zip(parts, labels, strict=True))
                     if i != 1 and p / total >= 0.005), reverse=True)  # fmt: skip
    return ", ".join(f"{lab} {share:.0%}" for share, lab in shares)


def why_below_white(held: str) -> str:
    """Why an axis's N is below its white level, for the consumers' notes (``held``:
    :func:`tau0_holders`)."""
    if held:
        return (
            f"the fit gave part of the Allan variance at tau0 to {held}, which the consumers "
            "have no field for"
        )
    return "the fitted Allan variance at tau0 falls short of the measured one"


def n_against_white(
    coef: NDArray, ivals: NDArray, white: float, unit: str, weights: NDArray, labels: Sequence[str]
) -> list[str]:
    """Keep N's interval reaching the white level; ``ivals`` is edited in place.

    Parameters
    ----------
    coef, ivals : ndarray
        The squared terms (Q, N, B, K, R) and their intervals (unsquared, one row each).
    white : float
        The measured white level (:func:`white_level`).
    unit : str
        The rate data's unit, for the notes.
    weights, labels
        As :func:`tau0_holders`.

    Returns
    -------
    list of str
        The notes.

    Notes
    -----
    docs/algorithms.md §E4. N's upper bound is raised until it reaches what the white
    level leaves after every other term at its lower bound, ``N_hi² >= W² - sum_j
    weights_j lo_j²`` (to ``W`` itself when N is not told from 0): a Q the fit cannot
    tell from 0 may be white noise; what the fit gives B, K or R at tau0 is extrapolated
    from longer taus, and the bootstrap, drawing from that fit, never doubts it, while
    motion or a short record can leave white noise there (gtsam's legged robot: B took
    85 % of it).
    """
    n_value = math.sqrt(coef[1])
    held = tau0_holders(coef, weights, labels)
    told = ivals[1, 0] > 0.0
    # every other term at its lower bound: the rest of W^2 may be N's (Q's lower bound 0
    # when the fit put Q where the record holds white noise alone)
    others = np.delete(weights * ivals[:, 0] ** 2, 1)
    need = math.sqrt(max(white**2 - float(np.sum(others)), 0.0)) if told else white
    notes, raised = [], ivals[1, 1] < need
    if raised:
        old, ivals[1, 1] = ivals[1, 1], need
        if told:
            notes.append(
                f"N's upper bound is raised from {old:.4g} to {need:.4g} {unit}/√Hz, what the "
                f"white level {white:.4g} leaves after the other terms' lower bounds: "
                + (
                    f"the fit gave {held} of the Allan variance at tau0, extrapolated from "
                    "longer taus, where motion or a short record can leave white noise"
                    if held
                    else "the fitted Allan variance at tau0 falls short of the measured one"
                )
            )
        else:
            why = f" (the fit gave {held} of the short-tau noise)" if held else ""
            notes.append(
                f"N is not told from 0{why}: its upper bound is the white level "
                f"{white:.4g} {unit}/√Hz, as if all of the short-tau noise were white"
            )
    if held and n_value < white:
        why = "" if raised else f" (the fit gave {held} of the Allan variance at tau0)"
        notes.append(
            f"N = {n_value:.4g} is below the white level {white:.4g} {unit}/√Hz{why}: a "
            "model with N alone there (Kalibr, OpenVINS) needs the white level"
        )
    return notes
