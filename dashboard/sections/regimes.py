"""The regime warning and the "use the still regimes only" choice (issue 26, item 5).

The Noise model, Two sensors and Fleet pages warn when a record's noise level varies (motion
among still stretches) with the estimate's own verdict, and offer to use the still regimes
only: the R they show is then :func:`noisevar.estimators.regimes.variance_for` of the same
estimate the Estimator page makes, and the fits run on the longest still stretch.
"""

from __future__ import annotations

from collections.abc import Sequence

import streamlit as st

from noisevar.estimators.regimes import DEFAULT_REGIMES
from noisevar.estimators.results import VarianceEstimate

#: The checkbox's label.
STILL_LABEL = "Use the still regimes only"


def level_varies(est: VarianceEstimate | None) -> bool:
    """Whether the estimate's diagnostics found a level that varies (False without them)."""
    diag = None if est is None else est.diagnostics
    return bool(diag is not None and diag.level_varies)


def regime_warning(est: VarianceEstimate | None, name: str | None = None) -> bool:
    """The estimate's verdict as a warning when its level varies; whether it does.

    Parameters
    ----------
    est : VarianceEstimate or None
    name : str, optional
        What the record is (a sensor's column), said before the verdict.
    """
    if not level_varies(est):
        return False
    assert est is not None and est.diagnostics is not None
    said = f"**{name}**: " if name else ""
    st.warning(f"{said}{est.diagnostics.verdict}", icon=":material/warning:")
    return True


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
        ``"still"`` when the box is ticked, else ``"all"``.
    """
    warned = [regime_warning(est, name) for name, est in estimates]
    return still_choice(key, any(warned), help)
