"""The Kalman fit's ``r`` beside the record's answer (method ``auto``): one record, one answer.

:func:`record_check` compares a :class:`~noisevar.noise_model.kalman_fit.KalmanTuning`'s ``r``
with :func:`noisevar.estimate`'s R of the same samples (the whole record, or its still
regimes for a ``regimes="still"`` fit), says which of the fit's assumptions (one noise
level, white, Gaussian, no level jumps) the record breaks by the estimate's own diagnostics,
why the two differ, which R a filter should use and what to do (docs/algorithms.md §E6
*The record's answer*).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import DEFAULT_REGIMES, estimate_for, why_no_still
from noisevar.estimators.results import VarianceEstimate
from noisevar.format import eng, eng_range

#: Where each regime choice's R is measured.
WHERE = {"all": "the whole record", "still": "its still regimes"}
#: What to do when the noise level varies and the record has a still R.
USE_STILL = (
    "fit the still regimes only (regimes='still'; CLI --regimes still; dashboard: tick the "
    "still regimes only)"
)
#: What to do when the noise level varies and no still stretch measures the sensor's noise.
NO_STILL = "record the sensor still for a while"


@dataclass(frozen=True)
class RecordCheck:
    """The record's R (method ``auto``) beside a Kalman fit's ``r``.

    Attributes
    ----------
    variance, ci95 : float, (float, float)
        The record's R for the fit's regime choice, and its 95 % interval.
    where : str
        ``"the whole record"`` or ``"its still regimes"``.
    ratio : float
        The fit's ``r`` over ``variance``.
    agrees : bool
        ``r`` lies inside ``ci95``.
    use : float or None
        The R a filter should use: the still regimes' when the level varies and there is
        one, else the record's; None when the level varies and no still stretch measures it.
    broken : tuple of str
        The fit's assumptions the record breaks, by the estimate's diagnostics.
    advice : tuple of str
        What to do about each (same order; duplicates dropped).
    note : str
        The sentence the fit's notes, the CLI and the page say.
    """

    variance: float
    ci95: tuple[float, float]
    where: str
    ratio: float
    agrees: bool
    use: float | None
    broken: tuple[str, ...]
    advice: tuple[str, ...]
    note: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary."""
        return {
            "variance": float(self.variance),
            "ci95": [float(v) for v in self.ci95],
            "where": self.where,
            "ratio": float(self.ratio),
            "agrees": self.agrees,
            "use": None if self.use is None else float(self.use),
            "broken": list(self.broken),
            "advice": list(self.advice),
            "note": self.note,
        }


def _level(est: VarianceEstimate) -> list[tuple[str, str]]:
    """(broken assumption, advice) when the noise level varies and the estimate has a still R
    or says why not (a record it takes as one still level gives none)."""
    d = est.diagnostics
    gap = why_no_still(est)
    if d is None or not d.level_changes or (est.still is None and gap is None):
        return []
    what = "one noise level (it varies along the record: regimes of motion and stillness)"
    if est.still is not None and gap is None:
        return [(what, USE_STILL)]
    return [(what, "there is no still R to use (the estimate's verdict says why): " + NO_STILL)]


def _colour(est: VarianceEstimate) -> list[tuple[str, str]]:
    """(broken assumption, advice) when the record's noise is not white."""
    d = est.diagnostics
    if d is None or d.white or d.motion_explains_colour:
        return []
    osc = d.whiteness.oscillation
    if d.lsb is not None and est.variance < d.lsb**2:  # under a step: rounding matters
        return [
            (
                f"white noise (quantised on a step of {eng(d.lsb)}: its rounding error is "
                "neither white nor of one level)",
                "read r and R as the noise plus the rounding error lsb²/12",
            )
        ]
    if d.differenced:
        return [
            (
                "white noise (it looks differenced: correlation near -1/2 at a short lag)",
                "filter the undifferenced quantity, or model MA(1) noise",
            )
        ]
    if osc is not None and osc.found:
        return [
            (
                f"white noise (an oscillation at {osc.frequency:.2f} of the sample rate: r "
                "takes all of it, R leaves its line out)",
                "notch or low-pass it out before the filter, or model it as a state",
            )
        ]
    return [
        (
            "white noise (coloured, or motion leaks through: q and r share its slow part "
            "otherwise than R's smoother)",
            "compare the models (BIC) or fit a coloured-noise model",
        )
    ]


def _jumps_and_tails(est: VarianceEstimate, left_out: bool) -> list[tuple[str, str]]:
    """(broken assumption, advice) for level jumps left out of R (unless the fit
    ``left_out`` them too) and heavy tails."""
    out = []
    jumps = 0 if est.jumps is None else int(np.count_nonzero(est.jumps))
    if jumps and not left_out:
        out.append(
            (
                f"no level jumps ({jumps} samples around jumps are left out of R, not of the fit)",
                "fit between the jumps",
            )
        )
    d = est.diagnostics
    if d is not None and d.heavy_tailed and est.outlier_fraction > 0:  # not a regime mixture
        core = (
            "" if est.core_variance is None else f" with the core variance {eng(est.core_variance)}"
        )
        out.append(
            (
                f"Gaussian noise (kurtosis {d.kurtosis:.3g}, {est.outlier_fraction:.2%} of the "
                "samples outlying: in r and R both)",
                f"a robust filter{core}",
            )
        )
    return out


def _note(
    r: float, ans: VarianceEstimate, where: str, use: float | None, pairs: list[tuple[str, str]]
) -> str:
    """The sentence: r against the record's R, why they differ, the R to use, what to do."""
    ratio = r / ans.variance
    iv = eng_range(*ans.ci95)
    said = f"the record's R = {eng(ans.variance)} (95 % {iv}, method auto over {where})"
    agrees = ans.ci95[0] <= r <= ans.ci95[1]
    head = f"r agrees with {said}" if agrees else f"r is {ratio:.3g}x {said}, outside its interval"
    if pairs:
        head += "; the record breaks the fit's assumptions of " + ", ".join(p[0] for p in pairs)
    elif not agrees:
        head += (
            "; the record breaks none of the fit's assumptions the estimate checks: the "
            "kinematic model reads its motion differently from R's smoother (compare the models)"
        )
    if use is not None and use != ans.variance:
        head += f"; the R to use is its still regimes' {eng(use)}"
    advice = list(dict.fromkeys(p[1] for p in pairs))
    return head + ("; what to do: " + "; ".join(advice) if advice else "")


def record_check(
    r: float, est: VarianceEstimate, regimes: str = DEFAULT_REGIMES, left_out: bool = False
) -> RecordCheck | None:
    """A fit's ``r`` against the record's answer, and why they differ.

    Parameters
    ----------
    r : float
        The fit's measurement variance.
    est : VarianceEstimate
        :func:`noisevar.estimate` (method ``auto``) of the whole record the fit was given.
    regimes : {"all", "still"}
        The fit's regime choice: its ``r`` is compared with that choice's R.
    left_out : bool
        Whether the fit left out the samples R leaves out around level jumps
        (:func:`~noisevar.noise_model.kalman_pieces.between_jumps`).

    Returns
    -------
    RecordCheck or None
        None with ``"still"`` when the record has no still R (the fit refuses those).

    Notes
    -----
    docs/algorithms.md §E6 *The record's answer*. The level's (regimes) reason is not a
    reason of a ``"still"`` fit's: it ran on still samples alone.
    """
    try:
        ans = estimate_for(est, regimes)
    except NoisevarError:
        return None
    use = None if why_no_still(est) else estimate_for(est, "still").variance
    pairs = (
        ([] if regimes == "still" else _level(est)) + _colour(ans) + _jumps_and_tails(ans, left_out)
    )
    where = WHERE["all"] if ans is est else WHERE["still"]
    return RecordCheck(
        variance=float(ans.variance),
        ci95=(float(ans.ci95[0]), float(ans.ci95[1])),
        where=where,
        ratio=float(r / ans.variance),
        agrees=bool(ans.ci95[0] <= r <= ans.ci95[1]),
        use=None if use is None else float(use),
        broken=tuple(p[0] for p in pairs),
        advice=tuple(dict.fromkeys(p[1] for p in pairs)),
        note=_note(r, ans, where, use, pairs),
    )


def record_estimate(z: NDArray, t: NDArray | None = None) -> VarianceEstimate | str:
    """The record's answer (:func:`noisevar.estimate`, method auto, on the sample times ``t``
    where given: the CLI's ``estimate`` reads a file's), or why there is none."""
    from noisevar.estimators import estimate

    try:
        return estimate(z, t=t)
    except NoisevarError as exc:
        return str(exc)


def with_record(fit: Any, est: VarianceEstimate | str) -> Any:
    """A ``KalmanTuning`` with its :class:`RecordCheck`, the check's sentence last in its notes."""
    check = (
        None if isinstance(est, str) else record_check(fit.r, est, fit.regimes, fit.left_out > 0)
    )
    if check is None:
        why = est if isinstance(est, str) else "the record has no R for this regime choice"
        note = f"the record's answer (method auto) is not made ({why}), so r is not checked"
        return replace(fit, notes=(*fit.notes, note))
    return replace(fit, record=check, notes=(*fit.notes, check.note))
