"""The Noise panel (issue 13): the verdict, the flags, the notes and four figures; assumptions.

The Estimator page calls :func:`render_noise_panel` with its record and estimate; the Compare
page calls :func:`render_assumptions` with one estimate per method.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import pandas as pd
import streamlit as st
from numpy.typing import ArrayLike

from dashboard.sections.regimes import still_levels_table
from dashboard.widgets import guarded, lazy_expander, show_figure, show_table
from noisevar.diagnostics.panel import (
    NoisePanelData,
    assumption_rows,
    noise_panel_data,
    verdict_severity,
)
from noisevar.estimators.answer import record_answer
from noisevar.figures.noise import acf_plot, level_profile_plot, qq_plot, residual_histogram

#: Flag -> (label, the value that is good news; None: neither good nor bad).
FLAG_LABELS: dict[str, tuple[str, bool | None]] = {
    "white": ("white", True),
    "heavy_tailed": ("heavy tails", False),
    "quantised": ("on a grid", None),
    "gaps": ("gaps", False),
    "level_varies": ("level varies", False),
    "identifiable": ("noise identifiable", True),
}


def _badges(flags: dict[str, bool | None]) -> None:
    """One small badge per flag: green when good news, orange when not, grey when neutral
    or not checked (None: the record is too short to check it).

    One line of Markdown badges, which wraps (fixed columns cut the longer labels off).
    """
    badges = []
    for key, (label, good) in FLAG_LABELS.items():
        if key in flags and flags[key] is None:
            badges.append(f":gray-badge[:material/help: {label}: not checked]")
            continue
        value = bool(flags.get(key, False))
        color = "gray" if good is None else ("green" if value == good else "orange")
        icon = ":material/check:" if value else ":material/close:"
        badges.append(f":{color}-badge[{icon} {label}]")
    st.markdown(" ".join(badges))


@st.cache_data(max_entries=8, show_spinner=False)
def _panel_data(digest: str, _z: ArrayLike, _diag: Any, _t: ArrayLike | None) -> NoisePanelData:
    """:func:`noise_panel_data` once per record (``digest``): it depends on the record only."""
    return noise_panel_data(_z, _diag, _t)


def render_noise_panel(
    z: ArrayLike,
    estimate: Any,
    t: ArrayLike | None = None,
    key: str = "np",
    digest: str | None = None,
) -> None:
    """The verdict (info or warning by severity), flags, notes and the Noise figures.

    Parameters
    ----------
    z : array_like, shape (n,)
        The finite samples the estimate was computed from.
    estimate : VarianceEstimate
        Its ``.diagnostics`` (nothing is drawn without them).
    t : array_like, optional
        Sample times (the level profile's abscissa).
    key : str
        Prefix of the widget keys (give each panel on a page its own).
    digest : str, optional
        The record's content hash: the figure data are then computed once per record.
    """
    diag = getattr(estimate, "diagnostics", None)
    if diag is None:
        verdict = getattr(estimate, "verdict", "")  # a record too short to diagnose says so
        if verdict:
            st.warning(verdict, icon=":material/warning:")
        else:
            st.caption("This estimate carries no noise diagnostics.")
        return
    if verdict_severity(diag, estimate.variance) == "ok":
        st.info(diag.verdict, icon=":material/check_circle:")
    else:
        st.warning(diag.verdict, icon=":material/warning:")
    _badges(diag.flags)
    for note in diag.notes:
        st.caption(note)
    still_levels_table(record_answer(estimate))  # the other still levels, as data
    _figures(z, diag, t, key, digest)


#: The Noise panel's figure tabs: label -> (chart key suffix, figure function).
TABS = {
    "Histogram": ("hist", residual_histogram),
    "QQ plot": ("qq", qq_plot),
    "Autocorrelation": ("acf", acf_plot),
    "Level profile": ("profile", level_profile_plot),
}


def _figures(z: ArrayLike, diag: Any, t: ArrayLike | None, key: str, digest: str | None) -> None:
    """The figures' expander; lazy: only the open tab of an open expander is computed and sent."""
    label = "Noise: distribution, autocorrelation, level along the record"
    with lazy_expander(label, f"{key}_open") as is_open:
        if not is_open:
            return
        with guarded("Noise panel: "):
            data = (
                noise_panel_data(z, diag, t) if digest is None else _panel_data(digest, z, diag, t)
            )
            tabs = st.tabs(list(TABS), key=f"{key}_tab", on_change="rerun")
            for (suffix, draw), tab in zip(TABS.values(), tabs, strict=True):
                if not tab.open:
                    continue
                with tab:
                    extra = {}
                    if draw is residual_histogram:
                        log_y = st.toggle("Logarithmic density (tails)", key=f"{key}_log_y")
                        extra["log_y"] = log_y
                    show_figure(draw(data, **extra), key=f"{key}_{suffix}")


def render_assumptions(estimates: Iterable[Any]) -> None:
    """Table: each method's assumptions that hold or fail on this record, in plain words."""
    rows = assumption_rows(estimates)
    if not rows:
        return
    st.markdown("**Which methods' assumptions hold on this record**")
    frame = pd.DataFrame(rows).rename(
        columns={"method": "Method", "holds": "Holds", "fails": "Fails", "meaning": "Meaning"}
    )
    show_table(frame, hide_index=True, width="stretch")
