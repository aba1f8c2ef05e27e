"""The Signal page's view of the loaded signal: column and period, summary, figure, exports."""

from __future__ import annotations

import numpy as np
import streamlit as st
from streamlit.delta_generator import DeltaGenerator

from dashboard import cache
from dashboard.sections.regimes import record_answer_box
from dashboard.state import (
    UNITS_KEY,
    LoadedSignal,
    clean_of,
    declared_units,
    reselect,
    signal_units,
    time_of,
    truth_of,
)
from dashboard.widgets import figure_downloads, fmt, guarded, lazy_expander, show_figure, show_table
from noisevar.estimators.answer import declared_note, record_answer
from noisevar.figures.estimator import signal_figure
from noisevar.format import duration as duration_text
from noisevar.io import signal_summary

#: Session-state key of the (lazy) "First rows of the table" expander.
ROWS_KEY = "sig_rows_open"


def column_and_period(sig: LoadedSignal, errors: DeltaGenerator) -> LoadedSignal:
    """The column and sample-period widgets; returns the (possibly re-selected) signal."""
    heading = st.empty()  # written last: the column chosen below, not the previous one
    cols = sig.table.data_columns
    c1, c2 = st.columns(2)
    column = c1.selectbox(
        "Signal column",
        cols,
        index=cols.index(sig.column) if sig.column in cols else 0,
        key=f"sig_column_{sig.table_digest}",
        help="The column every page estimates; the Two sensors page can use several.",
    )
    period = c2.number_input(
        "Sample period T (s)",
        value=sig.sample_period,
        min_value=1e-9,
        max_value=1e6,
        format="%.6g",
        key=f"sig_period_{sig.table_digest}",
        placeholder="unknown: axes in samples",
        help=(
            "From the time column when there is one. Only the time axes use it: the estimators "
            "work per sample."
        ),
    )
    st.text_input(
        "Units of the signal (optional)",
        key=UNITS_KEY,
        bind="query-params",
        max_chars=20,
        placeholder=declared_units(sig) or "e.g. m, V, s",
        help="Carried to the axes and numbers of every page: the variance is in units².",
    )
    if column != sig.column or period != sig.sample_period:
        with errors, guarded(f"Column {column!r}: "):
            sig = reselect(sig, column, period)
    heading.subheader(sig.label)
    return sig


def summary_metrics(sig: LoadedSignal, errors: DeltaGenerator) -> None:
    """Samples, duration, mean, std, range and the quick noise estimate (default method)."""
    summary = signal_summary(sig.z, sig.sample_period)
    auto = None
    with errors, guarded("Quick estimate: "):
        auto = cache.estimate(sig, cache.DEFAULT_METHOD, {})
    m = st.columns(6)
    m[0].metric("Samples", f"{summary['n']:,}")
    timing = time_of(sig)
    if isinstance(timing, np.ndarray):
        duration = float(timing[-1] - timing[0])  # the time column: gaps included
        how = "From the time column (gaps included)."
    else:
        duration = summary["duration_s"] if sig.sample_period else None
        how = "Samples × T." if sig.sample_period else "Set the sample period T to see it."
    m[1].metric("Duration", duration_text(duration), help=how)
    u = signal_units()
    m[2].metric("Mean", fmt(summary["mean"], unit=u))
    m[3].metric("Std (signal + noise)", fmt(summary["std"], unit=u))
    m[4].metric(
        "Min / max",
        f"{fmt(summary['min'], unit=u)} / {fmt(summary['max'], unit=u)}",
        help=f"{fmt(summary['min'], 8)} to {fmt(summary['max'], 8)}",
    )
    if auto is not None:
        truth = truth_of(sig)
        m[5].metric(
            f"Noise std ({cache.DEFAULT_METHOD})",
            fmt(auto.std, unit=u),
            delta=f"true {fmt(truth**0.5, unit=u)}" if truth else None,
            delta_color="off",
            delta_arrow="off",
            help="Quick estimate with the default method; tune it on the Estimator page.",
        )
    record_answer_box(auto)  # the record's verdict and regime warning, with its R
    declared = sig.table.declared_variance.get(sig.column)
    said = None  # no estimate (the column could not be estimated): nothing to compare
    if auto is not None and auto.diagnostics is not None:
        said = declared_note(record_answer(auto), declared, signal_units())
    if said:  # a ROS message's own covariance: its R
        st.info(said[0].upper() + said[1:] + ".", icon=":material/compare_arrows:")
    for note in sig.notes:
        st.caption(f"Note: {note}")


def preview(sig: LoadedSignal) -> None:
    """The signal figure, its downloads, the table as CSV and its first rows."""
    fig = signal_figure(
        sig.z,
        time_of(sig),
        name=sig.column,
        clean=clean_of(sig),
        units=signal_units(),
        title=f"{sig.label}",
    )
    show_figure(fig, key="signal_preview")
    c1, c2 = st.columns([1, 2])
    with c1:
        st.download_button(
            "Signal as CSV",
            data=lambda: sig.table.to_csv(),
            file_name=f"{sig.table.name.split('.')[0].replace(' ', '_')}.csv",
            mime="text/csv",
            key="signal_csv",
            on_click="ignore",
            icon=":material/download:",
            width="stretch",
        )
    with c2:
        figure_downloads(fig, "signal", "signal_fig")
    # Lazy: a closed expander's table is still drawn (and loads the browser's grid), issue 29
    with lazy_expander("First rows of the table", ROWS_KEY) as is_open:
        if is_open:
            first = {k: v[:20] for k, v in sig.table.columns.items()}
            show_table(first, digits=12, hide_index=False)  # the raw values, whole
