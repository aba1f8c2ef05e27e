"""The axes of an IMU fitted together: each axis's estimate, and one still stretch for all.

:func:`imu_still_stretch` is the stretch a filter's IMU is still on (every axis of the
gyroscope and the accelerometer still), which ``regimes="still"`` fits of its axes take
(:func:`noisevar.inertial_noise`'s and :func:`noisevar.fit_imu_model`'s ``stretch``), so
the exports' terms all come from the same samples (docs/algorithms.md §E7).
"""

from __future__ import annotations

from collections.abc import Sequence

from numpy.typing import ArrayLike

from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import StillStretch, common_still_stretch
from noisevar.estimators.results import VarianceEstimate
from noisevar.noise_model.allan import KINDS
from noisevar.noise_model.gmwm import STILL_NEED

#: Fewest samples of an IMU's still stretch: two taus of the overlapping ADEV (2 span + 2
#: phase samples, :func:`noisevar.inertial_noise`'s) and three wavelet scales (GMWM's).
IMU_STILL_NEED = max(2 * KINDS["oadev"].span + 2, STILL_NEED)


def imu_still_stretch(
    rows: ArrayLike, estimates: Sequence[VarianceEstimate | None] | None = None
) -> StillStretch:
    """The longest stretch where every axis of an IMU is still, for its fits.

    Parameters
    ----------
    rows : array_like, shape (axes, n)
        The gyroscope's and the accelerometer's axes, sample for sample (one rate).
    estimates : sequence of VarianceEstimate, optional
        :func:`noisevar.estimate` of each row, when made already.

    Returns
    -------
    StillStretch
        Its note says the stretch is the IMU's (all axes still) and which samples.

    Raises
    ------
    NoisevarError
        No stretch of :data:`IMU_STILL_NEED` samples is still on every axis.

    Notes
    -----
    :func:`~noisevar.estimators.regimes.common_still_stretch`. A single channel keeps its
    own longest still stretch (``regimes="still"`` without ``stretch``).
    """
    ests = None if estimates is None else list(estimates)
    return common_still_stretch(rows, IMU_STILL_NEED, "the IMU's noise terms", ests)


def per_axis(
    estimates: VarianceEstimate | Sequence[VarianceEstimate] | None, n: int, one: bool = False
) -> list[VarianceEstimate | None]:
    """``inertial_noise``'s ``estimates``, one per axis (None: each axis estimated)."""
    if estimates is None:
        return [None] * n
    if isinstance(estimates, VarianceEstimate):
        estimates = [estimates]
    out = list(estimates) if isinstance(estimates, Sequence) else []
    if len(out) != n or not all(isinstance(e, VarianceEstimate) for e in out):
        what = "one VarianceEstimate" if one else f"{n} VarianceEstimates, one per axis"
        raise NoisevarError(f"estimates must be {what} (noisevar.estimate of each axis).")
    return out
