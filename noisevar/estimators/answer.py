"""The record's one answer, as every page states it: R, its interval, the verdict (issue 28).

Every page that shows an R of a record quotes :func:`record_answer` of the same estimate
(method ``auto``, as the Estimator page makes it): its R over the whole record or the
still regimes, the interval, the verdict sentence and whether the noise level varies
(regimes of motion and stillness, docs §E1). A page whose own R is another quantity says
why with a label from :data:`WHY_DIFFERENT`, the one table of those reasons.
"""

from __future__ import annotations

from dataclasses import dataclass

from noisevar.diagnostics.panel import verdict_severity
from noisevar.estimators.regimes import DEFAULT_REGIMES, estimate_for, still_used
from noisevar.estimators.results import VarianceEstimate
from noisevar.format import eng, eng_range, squared

#: What a record whose noise level varies is warned of (reports, exports).
REGIME_WARNING = (
    "the noise level varies across the record (regimes of motion and stillness): the whole "
    "record's R mixes them; the still regimes' R is the sensor's own noise"
)
#: Why a page's R differs from the record's answer: key -> the label the page shows.
WHY_DIFFERENT: dict[str, str] = {
    "still": "still regimes only: the sensor's own noise, motion left out",
    "method": "each method's own estimate, under its own assumptions (the table's note column)",
    "kalman": "MLE of a state-space model's r: the white part a filter with this motion "
    "model sees, not the record's variance",
    "redundant": "from the differences between two sensors of one quantity (their own noise "
    "only when both measure the same thing)",
    "filter": "the filter's own running R (it follows the innovations), not the record's",
}


@dataclass(frozen=True)
class RecordAnswer:
    """The record's R as every page quotes it, and the verdict that goes with it.

    Attributes
    ----------
    variance : float
        R for the regime choice (the whole record's, or its still regimes').
    ci95 : (float, float)
        Its 95 % interval.
    method : str
        The method that made it.
    regimes : str
        ``"all"`` or ``"still"`` (what was asked).
    where : str
        ``"the whole record"`` or ``"its still regimes"`` (what was used).
    verdict : str
        The estimate's verdict sentence (empty without diagnostics).
    severity : str
        ``"ok"``, ``"caution"`` or ``"warning"`` (:func:`verdict_severity`).
    level_varies : bool
        Whether the noise level varies (regimes of motion and stillness).
    whole_variance : float
        The whole record's R.
    still_variance : float or None
        The still regimes' R when the record has some beside motion.
    """

    variance: float
    ci95: tuple[float, float]
    method: str
    regimes: str
    where: str
    verdict: str
    severity: str
    level_varies: bool
    whole_variance: float
    still_variance: float | None

    def sentence(self, unit: str = "") -> str:
        """``R = 1.2e-3 m² (95 % 1.1e-3 .. 1.3e-3), method auto over the whole record.``"""
        u = squared(unit)
        out = (
            f"R = {eng(self.variance, u)} (95 % {eng_range(*self.ci95, u)}), method "
            f"{self.method} over {self.where}."
        )
        if self.still_variance is not None and self.where != "its still regimes":
            out += f" Its still regimes alone: R = {eng(self.still_variance, u)}."
        return out

    def summary(self, unit: str = "") -> dict[str, str]:
        """The verdict, :meth:`sentence` and (when the level varies) the regime warning, as
        the exports write them (a config's ``record``, the CSV's last rows)."""
        out = {"verdict": self.verdict, "answer": self.sentence(unit)}
        if self.level_varies:
            out["regime_warning"] = REGIME_WARNING
        return {k: v for k, v in out.items() if v}


def record_answer(est: VarianceEstimate, regimes: str = DEFAULT_REGIMES) -> RecordAnswer:
    """The record's answer from its estimate (method ``auto``, as the Estimator page).

    Parameters
    ----------
    est : VarianceEstimate
        The record's estimate (with diagnostics for the verdict).
    regimes : {"all", "still"}
        The page's regime choice.

    Returns
    -------
    RecordAnswer
    """
    quoted = estimate_for(est, regimes)
    diag = est.diagnostics
    still = est.still
    return RecordAnswer(
        variance=float(quoted.variance),
        ci95=(float(quoted.ci95[0]), float(quoted.ci95[1])),
        method=str(est.method),
        regimes=regimes,
        where="its still regimes" if still_used(est, regimes) else "the whole record",
        verdict="" if diag is None else str(diag.verdict),
        severity="ok" if diag is None else verdict_severity(diag, est.variance),
        # a still R apart from one regime (still_set.has_still_apart) is a varying level too
        level_varies=bool(diag is not None and (diag.level_varies or still is not None)),
        whole_variance=float(est.variance),
        still_variance=None if still is None else float(still.variance),
    )
