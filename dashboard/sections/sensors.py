"""The Two sensors page's parts: sensor data offers, sensor choice, redundant SOMD results."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import streamlit as st

from dashboard import cache, loading
from dashboard.pages import SIGNAL
from dashboard.sections.regimes import regime_choice
from dashboard.state import LoadedSignal, follow_table, initial, keep_valid
from dashboard.widgets import (
    blank_missing,
    fmt,
    guarded,
    how_it_works,
    show_figure,
    show_table,
    table_and_figure_downloads,
)
from noisevar import RedundantEstimate
from noisevar.estimators.answer import WHY_DIFFERENT
from noisevar.estimators.redundant import (
    same_quantity_columns,
    same_quantity_notes,
)
from noisevar.estimators.regimes import DEFAULT_REGIMES, estimate_for
from noisevar.estimators.results import VarianceEstimate
from noisevar.figures.estimator import redundant_figure
from noisevar.format import squared
from noisevar.systems.latency import DelayEstimate
from noisevar.units import declared_unit

#: The delay of a sensor behind the first: (column, estimate or None, error or None).
Delay = tuple[str, DelayEstimate | None, str | None]


def require_sensors(sig: LoadedSignal | None, explain: Sequence[str]) -> LoadedSignal:
    """The loaded signal when it has two columns or more; else offer sensor data and stop."""
    if sig is not None and len(sig.table.data_columns) >= 2:
        return sig
    if sig is None:
        st.info("No signal loaded yet.")
    else:
        st.info(
            f"The loaded signal ({sig.label}) has a single column: this page needs a file with "
            "one column per sensor."
        )
    files = [p.name for p in loading.sample_files()]
    c1, c2, c3 = st.columns(3)
    if "two_sensors.csv" in files and c1.button("Load two_sensors.csv", key="ts_two"):
        with guarded():
            loading.load_sample("two_sensors.csv")
            st.rerun()
    if "three_sensors.csv" in files and c2.button("Load three_sensors.csv", key="ts_three"):
        with guarded():
            loading.load_sample("three_sensors.csv")
            st.rerun()
    if c3.button("Simulate three sensors (noise std 1, 2, 3)", key="ts_sim"):
        with guarded():
            loading.load_simulated_sensors()
            st.rerun()
    st.page_link(SIGNAL.path, label="Upload your own file", icon=":material/upload:")
    how_it_works(*explain)
    st.stop()
    raise AssertionError("unreachable")  # pragma: no cover


def sensor_picker(sig: LoadedSignal) -> tuple[list[str], bool]:
    """The sensor columns (stops the page with fewer than two) and the delay-removal toggle.

    The toggle only acts with exactly two sensors.
    """
    data_cols = sig.table.data_columns
    # a logger's index, year and day-of-year columns are constant: left to pick by hand
    usable = sig.table.signals or data_cols
    finite = {c: sig.table.columns[c] for c in usable if np.all(np.isfinite(sig.table.columns[c]))}
    # a new table: start from the columns that look like one quantity (not a sensor's axes)
    default = same_quantity_columns(finite, dict(sig.table.units))
    follow_table("ts_table", "ts_cols", sig.table_digest, default)
    keep_valid("ts_cols", lambda v: all(c in data_cols for c in v), default)
    cols = st.multiselect(
        "Sensors of the same quantity (columns of the loaded table)",
        data_cols,
        key="ts_cols",
        bind="query-params",
        max_selections=6,
        help="Pick two or more columns that measure the same quantity (not the x, y and z "
        "axes of one sensor): a mismatch is flagged below.",
        **initial("ts_cols", default, "default"),
    )
    if len(cols) < 2:
        st.info(
            "Pick at least two sensors of one quantity. No two columns of this table follow "
            "the same signal (their difference varies more than their noise allows), so none "
            "is picked for you: the x, y and z axes of one sensor are not two sensors."
            if not default
            else "Pick at least two sensors."
        )
        st.stop()
    align = st.toggle(
        "Estimate and remove the delay between the two sensors first",
        key="ts_align",
        bind="query-params",
        disabled=len(cols) != 2,
        help=(
            "Least squares over shifts with sub-sample refinement (noisevar.systems.latency): a "
            "delay between the records would otherwise add the signal's changes to the "
            "differences."
        ),
    )
    return cols, bool(align)


def delays_behind_first(sig: LoadedSignal, cols: list[str]) -> list[Delay]:
    """The delay of every sensor behind the first (a check even when not removed)."""
    delays: list[Delay] = []
    for c in cols[1:]:
        try:
            delays.append((c, cache.delay_between(sig, cols[0], c), None))
        except Exception as exc:  # noqa: BLE001 - shown as a note, the estimate still runs
            delays.append((c, None, str(exc)))
    return delays


def redundant_results(sig: LoadedSignal, cols: list[str], align: bool) -> None:
    """Redundant SOMD on the sensors: metrics, delay, tables, figure, downloads."""
    delays = delays_behind_first(sig, cols)
    out = None
    with guarded():
        out = cache.redundant(sig, cols, align and len(cols) == 2)
    if out is None:
        return
    res, used, delay, removed = out
    unit = "s" if sig.sample_period else "samples"
    single = _regime_choice(cols, _single_estimates(sig, cols))
    _same_quantity(used, cols, single, res)
    _metrics(res, cols, single, _variance_units(sig, cols))
    st.caption(f"The redundant R's differ from each record's answer: {WHY_DIFFERENT['redundant']}.")
    _delay_message(delay, removed, cols, unit, used.shape[0])
    _sensor_table(res, cols, single)
    _pair_table(res, cols, delays, unit)
    big = [
        (c, d) for c, d, _ in delays if d is not None and d.is_significant(sig.sample_period or 1.0)
    ]
    if big and not align:
        st.warning(
            "A delay of more than half a sample separates "
            + ", ".join(f"{c} ({d.delay_s:.3g} ± {d.std_s:.2g} {unit})" for c, d in big)
            + f" from {cols[0]}: the differences then contain signal, not only noise."
            + (" Turn on the delay removal above." if len(cols) == 2 else "")
        )
    fig = redundant_figure(
        used, list(cols), res, sig.sample_period, title=f"{len(cols)} sensors of {sig.table.name}"
    )
    show_figure(fig, key="ts_chart")
    ci = res.ci95
    csv_rows = [
        {
            "sensor": c,
            "variance": float(res.variances[j]),
            "ci95_low": float(ci[j, 0]),
            "ci95_high": float(ci[j, 1]),
            "single_signal_auto": single[j].variance if single[j] else float("nan"),
            "note": "; ".join(res.notes),  # two sensors: each variance is their sum
        }
        for j, c in enumerate(cols)
    ]
    table_and_figure_downloads(
        "Results (CSV)",
        csv_rows,
        "noisevar-sensors.csv",
        "ts_csv",
        fig,
        "noisevar-sensors",
        "ts_fig",
    )


def _variance_units(sig: LoadedSignal, cols: list[str]) -> list[str]:
    """Each sensor's variance unit: the square of the unit its file declares ('' if none)."""
    return [squared(declared_unit(sig.table.units.get(c)) or "") for c in cols]


def _metrics(
    res: RedundantEstimate,
    cols: list[str],
    single: list[VarianceEstimate | None],
    units: list[str],
) -> None:
    """One headline per sensor: its own variance, never the pair's sum; each in its unit.

    Two sensors only give ``var a + var b``: each sensor's headline is then its
    single-signal estimate and the redundant sum is shown beside them as a check.
    """
    ci = res.ci95
    u = units[0] if len(set(units)) == 1 else ""  # a sum or a hat across units: none
    pair_only = len(cols) == 2
    mcols = st.columns(len(cols) + (1 if pair_only else 0))
    for j, c in enumerate(cols):
        if pair_only:
            e = single[j]
            mcols[j].metric(
                f"{c}: noise variance",
                fmt(e.variance if e is not None else None, unit=units[j]),
                help="This sensor alone (method auto): two sensors only give the sum of the two "
                "variances.",
            )
            if e is not None:
                mcols[j].caption(
                    f"std {fmt(e.std)}; 95 % {fmt(e.ci95[0])} to {fmt(e.ci95[1])}; single-signal"
                )
            continue
        mcols[j].metric(
            f"{c}: noise variance",
            fmt(res.variances[j], unit=u),
            help=f"Three-cornered hat; 95 % interval {fmt(ci[j, 0])} to {fmt(ci[j, 1])}",
        )
        mcols[j].caption(f"std {fmt(float(res.stds[j]))}; 95 % {fmt(ci[j, 0])} to {fmt(ci[j, 1])}")
    if pair_only:
        total = sum(e.variance for e in single if e is not None)
        mcols[2].metric(
            f"{cols[0]} + {cols[1]} (two sensors)",
            fmt(res.pair_sums[0, 1], unit=u),
            help="½ E[(ΔZa − ΔZb)²]: the sum of the two noise variances, the only quantity two "
            "sensors determine (a third sensor separates them).",
        )
        mcols[2].caption(f"sum of the single-signal values: {fmt(total)}")
    else:
        for note in res.notes:
            st.caption(f"Note: {note}")


def _delay_message(
    delay: DelayEstimate | None, removed: float, cols: list[str], unit: str, n_used: int
) -> None:
    if delay is not None and removed:
        st.success(
            f"Estimated delay of {cols[1]} behind {cols[0]}: {delay.delay_s:.4g} ± "
            f"{delay.std_s:.2g} {unit}; removed a whole-sample shift of {removed:.4g} {unit} "
            f"(interpolating between samples would shrink the noise); {n_used:,} "
            "overlapping samples used."
        )
    elif delay is not None:
        st.info(
            f"Estimated delay of {cols[1]} behind {cols[0]}: {delay.delay_s:.4g} ± "
            f"{delay.std_s:.2g} {unit}, not significant (under half a sample or under two "
            "standard deviations): nothing removed."
        )


def _regime_choice(
    cols: list[str], single: list[VarianceEstimate | None]
) -> list[VarianceEstimate | None]:
    """The regime warning of each sensor whose level varies and the still-regimes choice.

    Returns each sensor's single-signal estimate for the choice: its whole record's, or
    its still regimes' (``estimate_for``), the R the Estimator page shows for it.
    """
    regimes = regime_choice(
        list(zip(cols, single, strict=True)),
        key="ts_regimes",
        help="Each sensor's single-signal R is then its still regimes' (where its level "
        "varies); the redundant estimate still uses the whole records.",
    )
    if regimes != DEFAULT_REGIMES:
        st.caption(
            "Single-signal values: each sensor's still regimes where its level varies, its "
            "whole record where it does not."
        )
    return [None if e is None else estimate_for(e, regimes) for e in single]


def _same_quantity(
    used: np.ndarray, cols: list[str], single: list[VarianceEstimate | None], res: RedundantEstimate
) -> None:
    """A warning when the columns do not look like sensors of one quantity (and why)."""
    single_r = [e.variance if e is not None else float("nan") for e in single]
    notes = same_quantity_notes(used, list(cols), single_r, res.variances)
    if notes:
        st.warning(
            "These columns may not measure the same quantity, which the redundant estimate "
            "assumes; pick only sensors of one quantity above.\n"
            + "\n".join(f"- {n}" for n in notes),
            icon=":material/warning:",
        )


def _single_estimates(sig: LoadedSignal, cols: list[str]) -> list[VarianceEstimate | None]:
    single: list[VarianceEstimate | None] = []
    for c in cols:
        try:
            single.append(cache.column_estimate(sig, c))
        except Exception:  # noqa: BLE001 - a column the single-signal method cannot use
            single.append(None)
    return single


def _sensor_table(
    res: RedundantEstimate, cols: list[str], single: list[VarianceEstimate | None]
) -> None:
    ci = res.ci95
    st.markdown("#### Each sensor")
    # two sensors give only their sum: each row's value is that sum, an upper bound (res.notes)
    head = "redundant SOMD variance" + (" (≤ the pair's sum)" if len(cols) == 2 else "")
    table = {
        "sensor": cols,
        head: [float(v) for v in res.variances],
        "95 % low": [float(v) for v in ci[:, 0]],
        "95 % high": [float(v) for v in ci[:, 1]],
        "single-signal estimate (auto)": [e.variance if e else float("nan") for e in single],
    }
    show_table(table, hide_index=True)
    st.caption(
        "The single-signal column estimates each sensor alone (method auto): a cross-check "
        "that needs no second sensor."
    )


def _pair_table(res: RedundantEstimate, cols: list[str], delays: list[Delay], unit: str) -> None:
    st.markdown("#### Pairs: ½ E[(ΔZi − ΔZj)²] = var i + var j")
    pair_rows = []
    for i in range(len(cols)):
        for j in range(i + 1, len(cols)):
            row = {"pair": f"{cols[i]} – {cols[j]}", "var i + var j": float(res.pair_sums[i, j])}
            d = next((x for x in delays if x[0] == cols[j]), None) if i == 0 else None
            if d is not None:
                row["delay of j behind i"] = (
                    f"{d[1].delay_s:.4g} ± {d[1].std_s:.2g} {unit}"
                    if d[1] is not None
                    else f"n/a ({d[2]})"
                )
            pair_rows.append(row)
    show_table(blank_missing(pair_rows), hide_index=True)
