"""Which regimes of a record a noise model or a filter's R is made from: all, or the still ones.

A real log is a sequence of regimes (still, moving, ...; :mod:`noisevar.diagnostics.regimes`).
``regimes="all"`` uses the whole record; ``regimes="still"`` the sensor's own noise: the
estimate's ``.still`` for R (:func:`variance_for`), the record's longest still stretch for a
fit (:func:`longest_still_stretch`). One home for the choice, used by ``fit_kalman``,
``fit_coloured_noise``, ``allan``, ``inertial_noise``, the fleet report, the CLI and the
dashboard.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate
from noisevar.estimators.still_quiet import regime_stretches
from noisevar.estimators.still_set import STILL_MIN, USE_ALL, still_gap, still_refusal

__all__ = [
    "DEFAULT_REGIMES",
    "REGIMES",
    "STILL_MIN",
    "StillStretch",
    "check_regimes",
    "choose_variances",
    "common_still_stretch",
    "estimate_for",
    "longest_still_stretch",
    "no_still_rows",
    "still_gap",
    "still_used",
    "variance_for",
    "why_no_still",
]

#: The regime choices: the whole record, or its still regimes only.
REGIMES = ("all", "still")
#: The choice a function makes when none is named.
DEFAULT_REGIMES = "all"


def check_regimes(regimes: Any) -> str:
    """``regimes`` when it is one of :data:`REGIMES`; else a :class:`NoisevarError`."""
    if not isinstance(regimes, str) or regimes not in REGIMES:
        raise NoisevarError(
            f"regimes must be one of {', '.join(map(repr, REGIMES))}, got {regimes!r}"
        )
    return regimes


@dataclass(frozen=True)
class StillStretch:
    """The stretch of a record a ``regimes="still"`` fit runs on.

    Attributes
    ----------
    start, stop : int
        Its sample range ``[start, stop)``.
    n_record : int
        Samples of the whole record.
    one_regime : bool
        The record is one still regime: the stretch is the whole record.
    axes : int
        The axes it is still on: 1, one record's own; more, an IMU's stretch where all
        its axes are still (:func:`common_still_stretch`).
    """

    start: int
    stop: int
    n_record: int
    one_regime: bool
    axes: int = 1

    @property
    def share(self) -> float:
        """Share of the record's samples in the stretch."""
        return (self.stop - self.start) / self.n_record

    @property
    def note(self) -> str:
        """What a result fitted on this stretch says about it."""
        if self.one_regime:
            return (
                "regimes='still': the record is one still regime (its level does not vary), "
                "so the whole record was used"
                + (f" (each of the IMU's {self.axes} axes)" if self.axes > 1 else "")
            )
        if self.axes > 1:
            return (
                f"regimes='still': fitted on the IMU's longest stretch where all its "
                f"{self.axes} axes are still, samples {self.start} to {self.stop} "
                f"({self.stop - self.start} samples, {self.share:.1%} of the record)"
            )
        return (
            f"regimes='still': fitted on the record's longest still stretch, samples "
            f"{self.start} to {self.stop} ({self.stop - self.start} samples, "
            f"{self.share:.1%} of the record)"
        )

    def take(self, z: NDArray) -> NDArray:
        """The stretch's samples of ``z`` (along its first axis)."""
        return z[self.start : self.stop]


def longest_still_stretch(
    z: ArrayLike, need: int = 0, purpose: str = "the fit", est: VarianceEstimate | None = None
) -> StillStretch:
    """The longest still stretch of a record, from :func:`noisevar.estimate`'s regimes.

    Parameters
    ----------
    z : array_like, shape (n,)
        The record.
    need : int
        Fewest samples ``purpose`` needs.
    purpose : str
        What the stretch is for, for the error message (e.g. ``"the 'cv' model"``).
    est : VarianceEstimate, optional
        :func:`noisevar.estimate` of ``z`` (method auto), when it was made already: its
        regimes are used instead of estimating again.

    Returns
    -------
    StillStretch
        The whole record when it is one still regime (``level_varies`` is False).

    Raises
    ------
    NoisevarError
        When the record has no still R to use (:func:`still_gap`: the same rule as
        :func:`variance_for`), or no still stretch has ``need`` samples.

    Notes
    -----
    docs/algorithms.md §E1 (Regimes). The stretches are the diagnostics' still stretches
    (``level_profile.still_stretches``: the still regimes' quiet blocks, with the
    samples around level jumps cut out); when none is of :data:`STILL_MIN` samples, the
    still regimes' own stretches too (less a block at either end and the blocks that lost
    samples around a jump), from which the still R then comes
    (:func:`~noisevar.estimators.still_quiet.regime_stretches`).
    """
    arr = np.asarray(z, dtype=float)
    stretches = _still_stretches(arr, est)
    if stretches is None:  # one still regime (still_gap)
        return StillStretch(0, arr.shape[0], arr.shape[0], True)
    return _longest(stretches, arr.shape[0], need, purpose, "still stretch")


def _still_stretches(arr: NDArray, est: VarianceEstimate | None) -> list | None:
    """A record's still stretches ``[(start, stop), ...]`` (:func:`longest_still_stretch`'s
    Notes), None when the record is one still regime; refused as there."""
    from noisevar.estimators import estimate

    try:
        est = estimate(arr) if est is None else est
    except NoisevarError as exc:
        raise NoisevarError(
            f"regimes='still': the record's regimes could not be found ({exc}); {USE_ALL}"
        ) from exc
    diag = est.diagnostics
    gap = why_no_still(est)  # the one rule, as variance_for's
    if gap is not None:
        raise NoisevarError(gap)
    if diag is None or est.still is None:  # one still regime (still_gap)
        return None
    # the still regimes' own stretches where the quiet blocks are all in pieces (as the
    # still R, still_quiet.still_estimate)
    stretches = diag.level_profile.still_stretches
    if not any(b - a >= STILL_MIN for a, b in stretches):
        # the ranges the still R was measured on (both block grids), else this grid's
        measured = None if est.still.stretches is None else list(est.still.stretches)
        stretches = stretches + regime_stretches(diag, measured)
    if not stretches:
        raise NoisevarError(
            "regimes='still': the record has no still stretch (its level varies throughout); "
            f"record the sensor still for a while, or {USE_ALL}"
        )
    return list(stretches)


def _longest(stretches: list, n: int, need: int, purpose: str, what: str) -> StillStretch:
    a, b = max(stretches, key=lambda s: s[1] - s[0])
    if b - a < need:
        raise NoisevarError(
            f"regimes='still': the longest {what} (samples {a} to {b}, {b - a} samples) "
            f"is too short for {purpose}, which needs {need}; record the sensor still for "
            f"longer, or {USE_ALL}"
        )
    return StillStretch(int(a), int(b), int(n), False)


def common_still_stretch(
    rows: ArrayLike,
    need: int = 0,
    purpose: str = "the fit",
    estimates: list[VarianceEstimate | None] | None = None,
) -> StillStretch:
    """The longest stretch where every axis of an IMU is still.

    Parameters
    ----------
    rows : array_like, shape (axes, n)
        The IMU's axes (gyroscope and accelerometer), one record each, sample for sample.
    need, purpose : int, str
        As :func:`longest_still_stretch`'s.
    estimates : list of VarianceEstimate, optional
        :func:`noisevar.estimate` of each row (method auto), when made already.

    Returns
    -------
    StillStretch
        With ``axes`` the number of rows; the whole record when every row is one still
        regime.

    Raises
    ------
    NoisevarError
        An axis with no still stretch, or no stretch of ``need`` samples where all are.

    Notes
    -----
    docs/algorithms.md §E1 (Regimes). A filter's IMU is still when all its axes are: each
    axis's still stretches (:func:`longest_still_stretch`'s) are intersected and the
    longest common one is kept. Per axis the longest stretches can lie apart (autoflpy's
    ArduPlane SITL log: the gyro's 11786-12687, AccX's 10-650).
    """
    arr = np.asarray(rows, dtype=float)
    ests = list(estimates) if estimates is not None else [None] * arr.shape[0]
    n = arr.shape[1]
    common: list = [(0, n)]
    for row, est in zip(arr, ests, strict=True):
        own = _still_stretches(row, est)
        if own is None:
            continue
        common = [
            (max(a, c), min(b, d)) for a, b in common for c, d in own if min(b, d) > max(a, c)
        ]
        if not common:
            raise NoisevarError(
                "regimes='still': no stretch of the record is still on all the IMU's "
                f"{arr.shape[0]} axes together (each axis is still at other times); record "
                f"the IMU still for a while, or {USE_ALL}"
            )
    s = _longest(common, n, need, purpose, "stretch still on every axis")
    return replace(s, one_regime=common == [(0, n)], axes=int(arr.shape[0]))


def why_no_still(est: VarianceEstimate) -> str | None:
    """Why ``regimes="still"`` has no R for an estimate (or None): :func:`still_gap`, or
    a smoothed output's still level (``still_set.still_refusal``)."""
    return still_refusal(est.diagnostics, est.variance, est.still)


def still_used(est: VarianceEstimate, regimes: str = DEFAULT_REGIMES) -> bool:
    """Whether ``regimes`` gives the estimate's still R: ``"still"`` and it has one."""
    return check_regimes(regimes) == "still" and est.still is not None


def estimate_for(est: VarianceEstimate, regimes: str = DEFAULT_REGIMES) -> VarianceEstimate:
    """The estimate a regime choice quotes: ``est``, or ``est.still`` (:func:`still_used`).

    Raises
    ------
    NoisevarError
        With ``"still"``, when the record has no still R to use (:func:`why_no_still`).
    """
    still = est.still
    if check_regimes(regimes) == "all":
        return est
    gap = why_no_still(est)
    if gap is not None:
        raise NoisevarError(gap)
    return est if still is None else still


def variance_for(est: VarianceEstimate, regimes: str = DEFAULT_REGIMES) -> float:
    """The R of an estimate for a regime choice: ``est.variance``, or ``est.still.variance``.

    Parameters
    ----------
    est : VarianceEstimate
    regimes : {"all", "still"}

    Returns
    -------
    float
        With ``"still"``, the still regimes' variance when the estimate has one (the
        level varies); else the whole record's (one regime: the record is still).

    Raises
    ------
    NoisevarError
        With ``"still"``, when the level varies and there is no still R
        (:func:`still_gap`): never the whole record's R in its place.
    """
    return float(estimate_for(est, regimes).variance)


def choose_variances(
    variance: ArrayLike,
    still_variance: ArrayLike,
    regimes: str = DEFAULT_REGIMES,
    level_varies: ArrayLike | None = None,
) -> NDArray:
    """:func:`variance_for` on columns of estimates (a batch table's rows).

    Parameters
    ----------
    variance, still_variance : array_like, shape (n,)
        The whole records' variances and the still regimes' (NaN or None where a row
        has none).
    regimes : {"all", "still"}
    level_varies : array_like of bool, shape (n,), optional
        The rows' ``flag_level_varies``: a row whose level varies and that has no still
        variance has no still R (the still_set rule on a row).

    Returns
    -------
    ndarray, shape (n,)
        ``still_variance`` where it is finite and ``regimes`` is ``"still"``; NaN where
        the row has no still R (``level_varies`` given); else ``variance`` (one regime).
    """
    whole = np.asarray(variance, dtype=float)
    if check_regimes(regimes) == "all":
        return whole
    still = np.array([_number(v) for v in np.ravel(np.asarray(still_variance, dtype=object))])
    still = still.reshape(whole.shape)
    out = np.where(np.isfinite(still), still, whole)
    return np.where(no_still_rows(still, level_varies), np.nan, out)


def no_still_rows(still_variance: ArrayLike, level_varies: ArrayLike | None) -> NDArray:
    """Rows with no still R: their level varies and they have no still variance.

    ``level_varies`` None (a table without the flag): none is known to have no still R.
    """
    still = np.array([_number(v) for v in np.ravel(np.asarray(still_variance, dtype=object))])
    if level_varies is None:
        return np.zeros(still.shape, dtype=bool)
    varies = np.array([_number(v) == 1.0 for v in np.ravel(np.asarray(level_varies, dtype=object))])
    return varies & ~np.isfinite(still)


def _number(value: Any) -> float:
    """A float, NaN for a missing value (None, pandas' NA) or text."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return float("nan")
