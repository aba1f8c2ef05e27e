"""The regime warning and the "use the still regimes only" choice (issue 26, item 5).

The Noise model, Two sensors and Fleet pages warn when a record's noise level varies (motion
among still stretches) with the estimate's own verdict, and offer to use the still regimes
only: the R they show is then :func:`noisevar.estimators.regimes.variance_for` of the same
estimate the Estimator page makes, and the fits run on the longest still stretch.
"""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd
import streamlit as st

from dashboard.state import signal_units
from dashboard.widgets import show_table
from noisevar.estimators.answer import (
    STILL_LEVELS_NOTE,
    WHY_DIFFERENT,
    RecordAnswer,
    record_answer,
)
from noisevar.estimators.regimes import DEFAULT_REGIMES, why_no_still
from noisevar.estimators.results import VarianceEstimate

#: The checkbox's label.
STILL_LABEL = "Use the still regimes only"


def level_varies(est: VarianceEstimate | None) -> bool:
    """Whether the estimate's diagnostics found a level that varies (False without them)."""
    diag = None if est is None else est.diagnostics
    return bool(diag is not None and diag.level_varies)


def record_answer_box(
    est: VarianceEstimate | None,
    name: str | None = None,
    *,
    regimes: str = DEFAULT_REGIMES,
    unit: str | None = None,
    differs: str | None = None,
) -> bool:
    """The record's one answer: its verdict and R (as the Estimator page), on any page.

    A warning when the noise level varies (the regime warning) or the verdict says a
    white R misleads, else an info box; then, when the page's own R is another quantity,
    why it differs (a label of :data:`~noisevar.estimators.answer.WHY_DIFFERENT`).

    Parameters
    ----------
    est : VarianceEstimate or None
        The record's estimate, method auto (nothing is shown without one).
    name : str, optional
        What the record is (a sensor's column), said before the verdict.
    regimes : {"all", "still"}
        The page's regime choice (which R is quoted).
    unit : str, optional
        The record's unit (default: the one declared on the Signal page).
    differs : str, optional
        A key of ``WHY_DIFFERENT``: the page's R differs from this one, and why.

    Returns
    -------
    bool
        Whether the level varies.
    """
    if est is None:
        return False
    ans = record_answer(est, regimes)
    unit = signal_units() if unit is None else unit
    said = f"**{name}**: " if name else ""
    verdict = ans.verdict.rstrip()
    if verdict and not verdict.endswith((".", "!", "?")):
        verdict += "."  # a sentence of its own before the answer's
    text = f"{said}{verdict} The record's answer (Estimator page): {ans.sentence(unit)}"
    if ans.level_varies or ans.severity == "warning":
        st.warning(text, icon=":material/warning:")
    else:
        st.info(text, icon=":material/check_circle:")
    if differs is not None:
        st.caption(f"This page's R differs from the record's answer: {WHY_DIFFERENT[differs]}.")
    return ans.level_varies


def regime_warning(est: VarianceEstimate | None, name: str | None = None) -> bool:
    """The record's verdict and R (:func:`record_answer_box`) and its other still levels
    (:func:`still_levels_table`); whether its level varies.

    Parameters
    ----------
    est : VarianceEstimate or None
    name : str, optional
        What the record is (a sensor's column), said before the verdict.
    """
    varies = record_answer_box(est, name)
    if est is not None:
        still_levels_table(record_answer(est), name=name)
    return varies


def still_levels_table(ans: RecordAnswer, name: str | None = None, unit: str | None = None) -> None:
    """The record's other still levels as a small table (nothing when there is none).

    Each near-still stretch above the still R (another posture, slow sway): its samples,
    share of the record, level and 95 % interval over the still R, and the R there
    (:meth:`~noisevar.estimators.answer.RecordAnswer.still_level_rows`), under
    :data:`~noisevar.estimators.answer.STILL_LEVELS_NOTE`.

    Parameters
    ----------
    ans : RecordAnswer
        The record's answer.
    name : str, optional
        What the record is (a sensor's column), said before the note.
    unit : str, optional
        The record's unit (default: the one declared on the Signal page).
    """
    rows = ans.still_level_rows(signal_units() if unit is None else unit)
    if not rows:
        return
    said = f"**{name}**: " if name else ""
    st.caption(f"{said}{STILL_LEVELS_NOTE}")
    show_table(pd.DataFrame(rows), hide_index=True, width="stretch")


def still_choice(key: str, offered: bool, help: str) -> str:
    """The "use the still regimes only" checkbox when ``offered``: ``"still"`` or ``"all"``."""
    if not offered:
        return DEFAULT_REGIMES
    return "still" if st.checkbox(STILL_LABEL, key=key, help=help) else DEFAULT_REGIMES


def regime_choice(
    estimates: Sequence[tuple[str | None, VarianceEstimate | None]], key: str, help: str
) -> str:
    """A warning per record whose level varies, then the checkbox (offered when one does).

    Parameters
    ----------
    estimates : sequence of (name or None, VarianceEstimate or None)
        The records' estimates (method auto, as on the Estimator page).
    key : str
        The checkbox's widget key.
    help : str
        What the checkbox changes on this page.

    Returns
    -------
    str
        ``"still"`` when the box is ticked, else ``"all"``; ``"all"`` with an error when
        a record has no still R to use (:func:`~noisevar.estimators.regimes.why_no_still`:
        its still stretches are too short), never the whole record's R as the still one.
    """
    warned = [regime_warning(est, name) for name, est in estimates]
    regimes = still_choice(key, any(warned), help)
    if regimes == DEFAULT_REGIMES:
        return regimes
    gaps = [(name, why_no_still(est)) for name, est in estimates if est is not None]
    said = "; ".join(f"{name}: {gap}" if name else gap for name, gap in gaps if gap)
    if said:
        st.error(f"{said}. This page stays on the whole record.", icon=":material/error:")
        return DEFAULT_REGIMES
    return regimes
