"""Two sensors page: redundant SOMD with two or three real sensors of one quantity."""

from __future__ import annotations

import numpy as np
import streamlit as st

import dashboard_common as dc
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.estimator import redundant_figure

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**Two sensors (eq. 8).** Sensor $i$ reads $Z_i = Z + \\delta Z_i + V_i$: the true value, a "
    "slowly varying systematic error ($\\delta Z_i[k] \\approx \\delta Z_i[k+1]$) and white "
    "noise. Differencing in time removes $Z$'s level and the systematic errors; differencing "
    "the two sensors removes $Z$'s changes. What is left is noise:",
    "$$\\tfrac12\\,\\mathrm{E}\\big[(\\Delta Z_1 - \\Delta Z_2)^2\\big] = "
    "\\operatorname{var}(V_1) + \\operatorname{var}(V_2)$$",
    "With two sensors only the sum is known (the paper assumes one sensor is far better, so the "
    "sum is the worse sensor's variance).",
    "**Three sensors (three-cornered hat).** The three pair sums give three equations in three "
    "unknowns:",
    "$$s_{12} = \\sigma_1^2 + \\sigma_2^2,\\quad s_{13} = \\sigma_1^2 + \\sigma_3^2,\\quad "
    "s_{23} = \\sigma_2^2 + \\sigma_3^2 \\;\\Rightarrow\\; "
    "\\sigma_1^2 = \\tfrac12(s_{12} + s_{13} - s_{23})$$",
    "With more sensors the pair sums are solved by least squares.",
    "**Delays.** If one record lags, $\\Delta Z_1 - \\Delta Z_2$ also contains the signal's "
    "change over the lag. The delay is the shift $\\tau$ minimising "
    "$\\sum_k (Z_1[k] - Z_2[k+\\tau])^2$, refined below one sample by a parabola through the "
    "three best shifts; the late record is then read at $t + \\tau$.",
)

dc.setup_page("Two sensors", ":material/compare_arrows:")
st.title("Two sensors")
st.caption(
    "Two or more real sensors of the same quantity: the second-order mutual difference of "
    "each pair gives the sum of their noise variances; three sensors give each one."
)
sig = dc.current_signal()

if sig is None or len(sig.table.data_columns) < 2:
    if sig is None:
        st.info("No signal loaded yet.")
    else:
        st.info(
            f"The loaded signal ({sig.label}) has a single column: this page needs a file with "
            "one column per sensor."
        )
    files = [p.name for p in dc.sample_files()]
    c1, c2, c3 = st.columns(3)
    if "two_sensors.csv" in files and c1.button("Load two_sensors.csv", key="ts_two"):
        with dc.guarded():
            dc.load_sample("two_sensors.csv")
            st.rerun()
    if "three_sensors.csv" in files and c2.button("Load three_sensors.csv", key="ts_three"):
        with dc.guarded():
            dc.load_sample("three_sensors.csv")
            st.rerun()
    if c3.button("Simulate three sensors (noise std 1, 2, 3)", key="ts_sim"):
        with dc.guarded():
            dc.load_simulated_sensors()
            st.rerun()
    st.page_link("pages/1_Signal.py", label="Upload your own file", icon=":material/upload:")
    dc.how_it_works(*HOW_IT_WORKS)
    st.stop()

data_cols = sig.table.data_columns
default = [c for c in data_cols if np.all(np.isfinite(sig.table.columns[c]))][:3]
if st.session_state.get("ts_table") != sig.table_digest:
    # a new table: start from its first (up to three) usable columns
    st.session_state["ts_table"] = sig.table_digest
    if "ts_cols" in st.session_state:
        st.session_state["ts_cols"] = default
dc.keep_valid("ts_cols", lambda v: all(c in data_cols for c in v), default)
cols = st.multiselect(
    "Sensors (columns of the loaded table)",
    data_cols,
    key="ts_cols",
    bind="query-params",
    max_selections=6,
    help="Pick two or more columns that measure the same quantity.",
    **dc.initial("ts_cols", default, "default"),
)
if len(cols) < 2:
    st.info("Pick at least two sensors.")
    st.stop()

align = st.toggle(
    "Estimate and remove the delay between the two sensors first",
    key="ts_align",
    bind="query-params",
    disabled=len(cols) != 2,
    help=(
        "Least squares over shifts with sub-sample refinement (noisevar.systems.latency): a delay "
        "between the records would otherwise add the signal's changes to the differences."
    ),
)

# the delay of every sensor behind the first (a check even when not removed)
delays = []
for c in cols[1:]:
    try:
        d = dc.delay_between(sig, cols[0], c)
        delays.append((c, d, None))
    except Exception as exc:  # noqa: BLE001 - shown as a note, the estimate still runs
        delays.append((c, None, str(exc)))

res = None
with dc.guarded():
    res, used, delay, removed = dc.redundant(sig, cols, align and len(cols) == 2)

if res is not None:
    ci = res.ci95
    unit = "s" if sig.sample_period else "samples"
    mcols = st.columns(len(cols))
    for j, c in enumerate(cols):
        mcols[j].metric(
            f"{c}: noise variance",
            dc.fmt(res.variances[j]),
            help=f"95 % interval {dc.fmt(ci[j, 0])} to {dc.fmt(ci[j, 1])}",
        )
        mcols[j].caption(
            f"std {dc.fmt(float(res.stds[j]))}; 95 % {dc.fmt(ci[j, 0])} … {dc.fmt(ci[j, 1])}"
        )
    for note in res.notes:
        st.caption(f"Note: {note}")
    if delay is not None and removed:
        st.success(
            f"Estimated delay of {cols[1]} behind {cols[0]}: {delay.delay_s:.4g} ± "
            f"{delay.std_s:.2g} {unit}; removed a whole-sample shift of {removed:.4g} {unit} "
            f"(interpolating between samples would shrink the noise); {used.shape[0]:,} "
            "overlapping samples used."
        )
    elif delay is not None:
        st.info(
            f"Estimated delay of {cols[1]} behind {cols[0]}: {delay.delay_s:.4g} ± "
            f"{delay.std_s:.2g} {unit}, not significant (under half a sample or under two "
            "standard deviations): nothing removed."
        )

    single = []
    for c in cols:
        try:
            single.append(dc.column_estimate(sig, c))
        except Exception:  # noqa: BLE001 - a column the single-signal method cannot use
            single.append(None)
    st.markdown("#### Each sensor")
    table = {
        "sensor": cols,
        "redundant SOMD variance": [float(v) for v in res.variances],
        "95 % low": [float(v) for v in ci[:, 0]],
        "95 % high": [float(v) for v in ci[:, 1]],
        "single-signal estimate (auto)": [e.variance if e else float("nan") for e in single],
    }
    st.dataframe(
        table,
        hide_index=True,
        column_config={k: st.column_config.NumberColumn(format="%.4g") for k in list(table)[1:]},
    )
    st.caption(
        "The single-signal column estimates each sensor alone (method auto): a cross-check "
        "that needs no second sensor."
    )
    st.markdown("#### Pairs: ½ E[(ΔZi − ΔZj)²] = var i + var j")
    pair_rows = []
    for i in range(len(cols)):
        for j in range(i + 1, len(cols)):
            row = {
                "pair": f"{cols[i]} – {cols[j]}",
                "var i + var j": float(res.pair_sums[i, j]),
            }
            d = next((x for x in delays if x[0] == cols[j]), None) if i == 0 else None
            if d is not None:
                row["delay of j behind i"] = (
                    f"{d[1].delay_s:.4g} ± {d[1].std_s:.2g} {unit}"
                    if d[1] is not None
                    else f"n/a ({d[2]})"
                )
            pair_rows.append(row)
    st.dataframe(pair_rows, hide_index=True)
    big = [
        (c, d)
        for c, d, _ in delays
        if d is not None and dc.delay_is_significant(d, sig.sample_period or 1.0)
    ]
    if big and not align:
        st.warning(
            "A delay of more than half a sample separates "
            + ", ".join(f"{c} ({d.delay_s:.3g} ± {d.std_s:.2g} {unit})" for c, d in big)
            + f" from {cols[0]}: the differences then contain signal, not only noise."
            + (" Turn on the delay removal above." if len(cols) == 2 else "")
        )

    names = list(cols)
    fig = redundant_figure(
        used, names, res, sig.sample_period, title=f"{len(cols)} sensors of {sig.table.name}"
    )
    dc.show_figure(fig, key="ts_chart")
    csv_rows = [
        {
            "sensor": c,
            "variance": float(res.variances[j]),
            "ci95_low": float(ci[j, 0]),
            "ci95_high": float(ci[j, 1]),
            "single_signal_auto": single[j].variance if single[j] else float("nan"),
        }
        for j, c in enumerate(cols)
    ]
    c1, c2 = st.columns([1, 2])
    c1.download_button(
        "Results (CSV)",
        data=rows_to_csv(csv_rows),
        file_name="noisevar-sensors.csv",
        mime="text/csv",
        key="ts_csv",
        on_click="ignore",
        icon=":material/table:",
        width="stretch",
    )
    with c2:
        dc.figure_downloads(fig, "noisevar-sensors", "ts_fig")

dc.how_it_works(*HOW_IT_WORKS)
