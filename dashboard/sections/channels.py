"""Several channels of the loaded table side by side: one 2-D estimate, a table and a figure."""

from __future__ import annotations

import streamlit as st

from dashboard.cache import DEFAULT_METHOD
from dashboard.state import LoadedSignal, initial
from dashboard.widgets import blank_frame, csv_download, guarded, show_figure, show_table
from noisevar.batch.channels import channel_estimates
from noisevar.estimators.results import VarianceEstimates
from noisevar.figures.fleet import channels_figure
from noisevar.io import LoadedTable

#: Channels chosen at first (at most this many of the table's data columns).
DEFAULT_CHANNELS = 6


@st.cache_data(show_spinner=False, max_entries=16)
def _estimates(
    digest: str, columns: tuple[str, ...], _table: LoadedTable
) -> tuple[VarianceEstimates | None, list[str], dict[str, str]]:
    """Each chosen column's estimate (``digest`` keys the table), and why others have none.

    As ``noisevar estimate --columns`` and ``noisevar batch`` estimate them
    (:func:`noisevar.batch.channels.channel_estimates`: the table's times, one 2-D call
    when every channel can be estimated); a channel that cannot (constant, too short,
    NaN) is left out and its reason kept.
    """
    answers = channel_estimates(_table, list(columns))
    results = [a for a in answers if not isinstance(a, str)]
    names = [c for c, a in zip(columns, answers, strict=True) if not isinstance(a, str)]
    errors = {c: a for c, a in zip(columns, answers, strict=True) if isinstance(a, str)}
    if not results:
        return None, [], errors
    est = VarianceEstimates(results[0].method, (len(results),), results, dict(results[0].params))
    return est, names, errors


def side_by_side(sig: LoadedSignal) -> None:
    """A channel picker (tables with several data columns) and each channel's noise."""
    cols = sig.table.data_columns
    if len(cols) < 2:
        return
    st.subheader("Channels side by side")
    key = f"sig_channels_{sig.table_digest}"
    chosen = st.multiselect(
        "Channels",
        cols,
        key=key,
        # a log's constant fields, counters and second clocks are left to pick by hand
        **initial(key, (sig.table.signals or cols)[:DEFAULT_CHANNELS], "default"),
        help=f"Each channel's noise by method {DEFAULT_METHOD}, estimated in one call on all "
        "of them.",
    )
    if not chosen:
        st.caption("Pick channels to compare their noise.")
        return
    with guarded():
        est, names, errors = _estimates(sig.table_digest, tuple(chosen), sig.table)
        for name, why in errors.items():
            st.caption(f"{name}: no estimate ({why})")
        if est is not None:
            show_figure(channels_figure(est, names))
            frame = est.to_frame()
            frame["channel"] = names
            # a column with an absent value (no still R: ``still_note`` says why) shows "—"
            # every float written whole at 4 significant digits (3e-7 stays 3e-07, not 0.0000003)
            show_table(blank_frame(frame, digits=4), hide_index=True)
            csv_download(
                st,
                "Channels table as CSV",
                frame.to_csv(index=False),
                "noisevar-channels.csv",
                f"sig_channels_csv_{sig.table_digest}",
                help="Absent values are empty cells; still_note says why a still R is absent.",
            )
