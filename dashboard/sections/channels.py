"""Several channels of the loaded table side by side: one 2-D estimate, a table and a figure."""

from __future__ import annotations

import numpy as np
import streamlit as st

import noisevar
from dashboard.cache import DEFAULT_METHOD
from dashboard.state import LoadedSignal, initial
from dashboard.widgets import guarded, show_figure
from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimates
from noisevar.figures.fleet import channels_figure
from noisevar.io import LoadedTable, pick_column

#: Channels chosen at first (at most this many of the table's data columns).
DEFAULT_CHANNELS = 6


@st.cache_data(show_spinner=False, max_entries=16)
def _estimates(
    digest: str, columns: tuple[str, ...], _table: LoadedTable
) -> tuple[VarianceEstimates | None, list[str], dict[str, str]]:
    """Each chosen column's estimate (``digest`` keys the table), and why others have none.

    The channels are estimated in one 2-D call when they all can be; a channel that
    cannot (constant, too short, NaN) is left out and its reason kept.
    """
    try:
        z = np.stack([pick_column(_table, c) for c in columns])
        return noisevar.estimate(z, axis=-1), list(columns), {}
    except NoisevarError:
        pass
    results, names, errors = [], [], {}
    for c in columns:
        try:
            results.append(noisevar.estimate(pick_column(_table, c)))
            names.append(c)
        except NoisevarError as exc:
            errors[c] = str(exc)
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
        **initial(key, cols[:DEFAULT_CHANNELS], "default"),
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
            frame = est.to_frame()
            frame["channel"] = names
            show_figure(channels_figure(est, names))
            st.dataframe(frame, hide_index=True)
