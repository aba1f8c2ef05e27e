"""The record's one answer, as every page states it: R, its interval, the verdict (issue 28).

Every page that shows an R of a record quotes :func:`record_answer` of the same estimate
(method ``auto``, as the Estimator page makes it): its R over the whole record or the
still regimes, the interval, the verdict sentence and whether the noise level varies
(regimes of motion and stillness, docs §E1). A page whose own R is another quantity says
why with a label from :data:`WHY_DIFFERENT`, the one table of those reasons.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from noisevar.diagnostics.panel import verdict_severity
from noisevar.diagnostics.verdict_parts import still_level_fields
from noisevar.estimators.regimes import DEFAULT_REGIMES, estimate_for, still_used, why_no_still
from noisevar.estimators.results import VarianceEstimate
from noisevar.format import eng, eng_range, squared

if TYPE_CHECKING:
    from noisevar.diagnostics.regimes import StillLevel

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


#: The columns of :meth:`RecordAnswer.still_level_rows`: field -> the label pages show.
STILL_LEVEL_COLUMNS: dict[str, str] = {
    "stretch": "Stretch",
    "share": "Share of record",
    "level": "Level (x still R)",
    "ci95": "95 % (x still R)",
    "variance": "R there",
}
#: What the other still levels mean, said under their table.
STILL_LEVELS_NOTE = (
    "Other still stretches rest at a higher level on the same residual (another posture, or "
    "slow sway): the still R is the floor, the sensor's own noise; a filter that runs through "
    "those stretches without modelling that motion needs their level."
)


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
    still_levels : tuple of StillLevel
        The other still levels (``NoiseDiagnostics.other_still``), their ratios to the
        still R; empty when there is none (or no still R).
    n : int
        Samples in the record (each still level's share of it).
    still_refused : str or None
        Why ``regimes="still"`` gives no R although the still regimes were measured
        (:func:`~noisevar.estimators.regimes.why_no_still`: a smoothed output's); None
        when it gives one.
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
    still_levels: tuple[StillLevel, ...] = ()
    n: int = 0
    still_refused: str | None = None

    def sentence(self, unit: str = "") -> str:
        """``R = 1.2e-3 m² (95 % 1.1e-3 .. 1.3e-3), method auto over the whole record.``"""
        u = squared(unit)
        out = (
            f"R = {eng(self.variance, u)} (95 % {eng_range(*self.ci95, u)}), method "
            f"{self.method} over {self.where}."
        )
        if self.still_variance is not None and self.still_refused is not None:
            out += (
                f" Its still regimes read {eng(self.still_variance, u)}: not an R to use "
                "(a smoothed output's; see the verdict)."
            )
        elif self.still_variance is not None and self.where != "its still regimes":
            out += f" Its still regimes alone: R = {eng(self.still_variance, u)}."
        return out

    def still_level_rows(self, unit: str = "") -> list[dict[str, str]]:
        """The other still levels as table rows, keyed by :data:`STILL_LEVEL_COLUMNS`' labels:
        stretch, share of the record, level and interval over the still R, the R there."""
        return still_level_rows(self.still_levels, self.n, self.still_variance, unit)

    def still_levels_text(self, unit: str = "") -> str:
        """The other still levels in one line ('' when there is none), as the exports write
        them: ``samples 300-5400 (76% of the record) at 2.20x (ci95 1.95-2.48x) the still R,
        R there 2.2 m²; ...``."""
        c = STILL_LEVEL_COLUMNS
        return "; ".join(
            f"{r[c['stretch']]} ({r[c['share']]} of the record) at {r[c['level']]} (ci95 "
            f"{r[c['ci95']]}) the still R, R there {r[c['variance']]}"
            for r in self.still_level_rows(unit)
        )

    def summary(self, unit: str = "") -> dict[str, str]:
        """The verdict, :meth:`sentence`, (when the level varies) the regime warning and (when
        there are some) the other still levels, as the exports write them (a config's
        ``record``, the CSV's last rows)."""
        out = {"verdict": self.verdict, "answer": self.sentence(unit)}
        if self.level_varies:
            out["regime_warning"] = REGIME_WARNING
        out["other_still_levels"] = self.still_levels_text(unit)
        return {k: v for k, v in out.items() if v}


def declared_note(answer: RecordAnswer, declared: float | None, unit: str = "") -> str | None:
    """What the log's declared variance for a field (a ROS message's covariance, which a ROS
    filter such as robot_localization takes as R) is against the R to use; None without one.

    Within R's 95 % interval it agrees; else the note says by how much, and which way the
    filter told the declared value is wrong (docs/algorithms.md §E8, *Declared noise*).
    """
    if declared is None or not declared > 0:
        return None
    u = squared(unit)
    said = (
        f"the log declares a variance of {eng(declared, u)} for this field (its messages' "
        "covariance, which a ROS filter such as robot_localization takes as R); "
        f"the R to use (its sample-to-sample noise, measured) is {eng(answer.variance, u)}"
    )
    lo, hi = answer.ci95
    ratio = answer.variance / declared
    if lo <= declared <= hi:
        return said + ", and the declared value lies inside its 95 % interval"
    if ratio > 1:
        return (
            said + f", {ratio:.3g}x the declared value: a filter given the declared value "
            "trusts this sensor more than it should"
        )
    return (
        said + f", {1 / ratio:.3g}x below the declared value: a filter given the declared "
        "value trusts this sensor less than it could"
    )


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
        verdict=est.verdict,
        severity=verdict_severity(diag, est.variance, int(est.n_total)),
        level_varies=bool(diag is not None and diag.level_changes),
        whole_variance=float(est.variance),
        still_variance=None if still is None else float(still.variance),
        still_levels=() if diag is None or still is None else tuple(diag.other_still),
        n=0 if diag is None else int(diag.n),
        still_refused=None if still is None else why_no_still(est),
    )


def still_level_rows(
    levels: Sequence[StillLevel], n: int, still_variance: float | None, unit: str = ""
) -> list[dict[str, str]]:
    """Other still levels as table rows, keyed by :data:`STILL_LEVEL_COLUMNS`' labels.

    Parameters
    ----------
    levels : sequence of StillLevel
        ``NoiseDiagnostics.other_still`` (or :func:`row_still_levels` of a table's row).
    n : int
        Samples in the record.
    still_variance : float or None
        The still R the levels are ratios to (no rows without it).
    unit : str
        The record's unit.

    Returns
    -------
    list of dict
        Per level: stretch, share of the record, level and 95 % interval over the still
        R (:func:`~noisevar.diagnostics.verdict_parts.still_level_fields`, as the verdict says
        them) and the R there.
    """
    if still_variance is None or not math.isfinite(still_variance):
        return []
    c, u = STILL_LEVEL_COLUMNS, squared(unit)
    return [
        {c[k]: v for k, v in still_level_fields(x, n).items()}
        | {c["variance"]: eng(x.ratio * still_variance, u)}
        for x in levels
    ]


def row_still_levels(value: object) -> tuple[StillLevel, ...]:
    """The other still levels of a table's row (its ``other_still_levels`` JSON text).

    Returns
    -------
    tuple of StillLevel
        Empty for a missing value (None, NaN) or one that is not such a list (of finite
        levels over non-empty sample ranges).
    """
    from noisevar.diagnostics.regimes import StillLevel

    if not isinstance(value, str) or not value or len(value) > 100_000:
        return ()
    try:
        items = json.loads(value)
        out = tuple(
            StillLevel(
                int(d["start"]),
                int(d["stop"]),
                float(d["ratio"]),
                float(d["ci95_low"]),
                float(d["ci95_high"]),
            )
            for d in items
        )
    except (ValueError, TypeError, KeyError, OverflowError):
        return ()
    finite = all(math.isfinite(v) for x in out for v in (x.ratio, x.lo, x.hi))
    return out if finite and all(0 <= x.start < x.stop for x in out) else ()
