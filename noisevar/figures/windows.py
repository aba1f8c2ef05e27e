"""Figures of the SOMD window selection: the steps on the record and the window tests.

* :func:`somd_figure` - raw samples with the smooth and tracking outputs, kept
  windows shaded, rejected windows marked with the test that failed.
* :func:`window_tests_figure` - each window's amplitude and angle statistics
  against the thresholds of eq. [19].
* :func:`window_status`, :func:`amplitude_ratios`, :func:`amplitude_deviation` -
  what the figures and the table rows show per window.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike, NDArray

from noisevar.estimators.results import VarianceEstimate
from noisevar.figures._common import (
    COLORS,
    MAX_FIGURE_MARKERS,
    MAX_FIGURE_POINTS,
    PALETTE,
    Timing,
    band,
    capped,
    downsample_note,
    has_time,
    hline,
    layout,
    line_trace,
    log_axis,
    unit_name,
    vline,
    x_axis,
    x_title,
)
from noisevar.figures._shapes import merge_runs, runs_of
from noisevar.filters.selection import WindowSelection
from noisevar.format import wrap_words

#: Points per line of the SOMD figure: about one min-max pair per pixel column of the
#: dashboard's plot (~600 px) keeps the noise band (min-max LTTB); the browser draws each
#: point again on every control change.
SOMD_LINE_POINTS = 800
#: Most kept-window runs (and rejection marks per test) drawn; neighbours merge beyond it.
MAX_RUNS = 120

#: Window status labels, in drawing order.
STATUS = ("kept", "amplitude test", "angle test", "both tests", "transient")


# --------------------------------------------------------------------- helpers
def window_status(selection: WindowSelection) -> NDArray:
    """Status label of each window: kept, failed test(s), or inside the start-up transient.

    Parameters
    ----------
    selection : WindowSelection
        Per-window tests.

    Returns
    -------
    ndarray of str, shape (n_windows,)
        One of :data:`STATUS`.
    """
    amp, ang = selection.amp_ok, selection.ang_ok
    status = np.full(selection.n_windows, "kept", dtype=object)
    status[~amp & ang] = "amplitude test"
    status[amp & ~ang] = "angle test"
    status[~amp & ~ang] = "both tests"
    status[~selection.in_record] = "transient"
    return status


def amplitude_ratios(selection: WindowSelection) -> NDArray:
    """The amplitude ratios of eq. [19] the selection's test uses, per window (NaN if undefined).

    ``|A1/A2|, |A2/A3|, |A3/A4|`` for the printed test, and ``|A4/A1|`` as
    well for the symmetric one (:mod:`noisevar.filters.selection`).
    """
    return selection.amplitude_ratios()


def amplitude_ratio_labels(selection: WindowSelection) -> list[str]:
    """``["A1/A2", "A2/A3", ...]``: the names of :func:`amplitude_ratios`' columns."""
    return [f"A{i + 1}/A{j + 1}" for i, j in selection.amplitude_pairs]


def amplitude_deviation(selection: WindowSelection) -> NDArray:
    """The amplitude test's statistic per window: the test passes where it is below ``Γ_amp``."""
    if selection.amplitude_deviation is not None:
        return selection.amplitude_deviation
    with np.errstate(invalid="ignore"):  # a selection built by hand: the printed test
        return np.max(np.abs(amplitude_ratios(selection) - 1.0), axis=1)


def _deviation_label(selection: WindowSelection) -> str:
    pairs = ", ".join(f"|{x}|" for x in amplitude_ratio_labels(selection))
    if selection.amplitude_test == "paper":
        return f"max |r − 1|, r = {pairs}"
    return f"max tanh|ln r|, r = {pairs}"


def _finite_range(*arrays: ArrayLike) -> tuple[float, float]:
    lo, hi = math.inf, -math.inf
    for a in arrays:
        a = np.asarray(a, dtype=float)
        a = a[np.isfinite(a)]
        if a.size:
            lo, hi = min(lo, float(a.min())), max(hi, float(a.max()))
    if not math.isfinite(lo):
        return 0.0, 1.0
    if hi == lo:
        hi = lo + 1.0
    return lo, hi


def _fmt(v: float) -> str:
    return f"{v:.4g}" if math.isfinite(v) else "n/a"


# ------------------------------------------------------------------------ SOMD
def somd_figure(  # long: one figure, built trace by trace in drawing order
    z: ArrayLike,
    est: VarianceEstimate,
    sample_period: Timing = None,
    stretch: slice | None = None,
    max_points: int = SOMD_LINE_POINTS,
    title: str | None = None,
    height: int = 520,
    units: str = "",
    name: str = "signal",
) -> go.Figure:
    """Raw samples, smooth and tracking outputs, kept and rejected windows.

    Kept windows are shaded; each rejected window is marked above the record
    with the test that failed (amplitude, angle, both) or as start-up
    transient; hovering a mark gives the window's statistics. The drag mode
    is a horizontal box select, so a drag picks a stretch (see
    :func:`noisevar.figures.axes.range_to_slice`).

    Parameters
    ----------
    z : array_like, shape (n,)
        The samples the estimate was computed on.
    est : VarianceEstimate
        A SOMD estimate (``est.details`` set); other methods draw the record only.
    sample_period : float or ndarray, optional
        Seconds per sample, or the samples' own times (seconds; gaps drawn as gaps).
    stretch : slice, optional
        A chosen stretch to highlight.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.
    units : str
        Units of the samples (axis title).
    name : str
        What the samples are (the axis title: the record's column, not "signal").

    Returns
    -------
    go.Figure
    """
    z = np.asarray(z, dtype=float)
    n = z.size
    data: list[Any] = []
    shapes: list[dict[str, Any]] = []
    anns: list[dict[str, Any]] = []
    d = est.details
    lo, hi = _finite_range(z)
    pad = 0.04 * (hi - lo)
    merged_gap = 0
    if d is not None:
        kept, merged_gap = _kept_runs(d.kept_windows, int(est.params.get("window", 40)), n)
        data.extend(_kept_trace(kept, sample_period, lo - pad, hi + pad))
    marks = []
    if d is not None and d.selection is not None:
        marks = _rejection_marks(d.selection, sample_period, hi + 2 * pad)
    lines = [(z, unit_name(units, "raw samples"), {"color": COLORS["raw"], "width": 1})]
    if d is not None:
        for j, h in enumerate(d.h_smooth):
            color = COLORS["smooth"] if j == 0 else PALETTE[(j + 4) % len(PALETTE)]
            lines.append((d.smooth_output[j], f"smooth output, h_S={h:.3g}", {"color": color}))
        # thin and half transparent: the kept-window shading stays visible through it
        style = {"color": COLORS["track"], "width": 1, "dash": "dot"}
        lines.append((d.track_output, f"tracking output, h_T={d.h_track:.3g}", style))
    used = sum(len(tr.x) for tr in data + marks)
    per_line = max(min(max_points, (MAX_FIGURE_POINTS - used) // len(lines)), 100)
    for y, label, style in lines:  # (not ``name``: the axis title's below)
        dotted = style.get("dash") == "dot"
        data.append(
            line_trace(
                y,
                label,
                sample_period,
                per_line,
                line={"width": 1.6, **style},
                opacity=0.6 if dotted else 1.0,
            )[0]
        )
    data += marks
    if stretch is not None and stretch.stop > stretch.start:
        x0, x1 = x_axis([stretch.start, stretch.stop - 1], sample_period)
        shp = band(float(x0), float(x1), axis="x", color=COLORS["stretch"])
        shp["line"] = {"width": 1, "color": COLORS["amp"]}
        shp["layer"] = "above"
        shapes.append(shp)
        anns.append(
            {
                "x": float(x0),
                "y": 1.0,
                "xref": "x",
                "yref": "paper",
                "text": "chosen stretch",
                "showarrow": False,
                "xanchor": "left",
                "yanchor": "top",
                "font": {"size": 11, "color": COLORS["amp"]},
            }
        )
    note = downsample_note(n, per_line)
    if note:
        if merged_gap:
            # a second line: one line this long runs off the figure's left edge
            note["text"] += f"<br>kept-window gaps under {merged_gap:,} samples shaded over"
        anns.append(note)
    lay = layout(
        title,
        height,
        dragmode="select",
        selectdirection="h",
        xaxis={"title": {"text": x_title(sample_period)}},
        yaxis={"title": {"text": unit_name(units, name)}},
        shapes=shapes,
        annotations=anns,
    )
    return capped(go.Figure(data=data, layout=lay))


def _kept_runs(kept: NDArray, window: int, n: int) -> tuple[tuple[NDArray, NDArray], int]:
    """Sample runs ``[start, stop)`` of adjacent kept windows, merged to :data:`MAX_RUNS`."""
    a, b = runs_of(kept)
    a, b, gap = merge_runs(a, b, MAX_RUNS)
    return (a * window, np.minimum(b * window, n)), int(gap * window)


def _kept_trace(
    runs: tuple[NDArray, NDArray], sample_period: Timing, y_lo: float, y_hi: float
) -> list[go.Scatter]:
    """The kept runs as one filled trace (one rectangle per run; no layout shapes)."""
    a, b = runs
    if a.size == 0:
        return []
    x0 = x_axis(a, sample_period)
    x1 = x_axis(b - 1, sample_period)
    nan = np.full(a.size, np.nan)
    xs = np.column_stack([x0, x0, x1, x1, nan]).ravel()
    ys = np.tile([y_lo, y_hi, y_hi, y_lo, np.nan], a.size)
    trace = go.Scatter(
        x=xs,
        y=ys,
        fill="toself",
        fillcolor=COLORS["kept"],
        line={"width": 0},
        mode="lines",
        name="kept windows",
        hoverinfo="skip",
    )
    return [trace]


def _rejection_marks(sel: WindowSelection, sample_period: Timing, y: float) -> list[go.Scatter]:
    status = window_status(sel)
    ratios = amplitude_ratios(sel)
    centre = x_axis(sel.starts + sel.window / 2.0, sample_period)
    symbols = {"amplitude test": "x", "angle test": "triangle-down", "both tests": "diamond"}
    colors = {
        "amplitude test": COLORS["amp"],
        "angle test": COLORS["angle"],
        "both tests": COLORS["both"],
        "transient": COLORS["transient"],
    }
    out = []
    for label in STATUS[1:]:
        idx = np.flatnonzero(status == label)
        if idx.size == 0:
            continue
        if idx.size > MAX_RUNS:
            style = (symbols.get(label, "line-ew-open"), colors[label])
            out.append(_merged_marks(status == label, sel, sample_period, label, y, style))
            continue
        what = label if label != "transient" else "filter start-up transient"
        custom = np.column_stack([idx, ratios[idx], sel.angle_diff_deg[idx]])
        k = ratios.shape[1]
        values = ", ".join(f"%{{customdata[{c + 1}]:.3g}}" for c in range(k))
        out.append(
            go.Scatter(
                x=centre[idx],
                y=np.full(idx.size, y),
                mode="markers",
                marker={
                    "symbol": symbols.get(label, "line-ew-open"),
                    "color": colors[label],
                    "size": 7,
                    "line": {"width": 1.5, "color": colors[label]},
                },
                name=f"rejected: {label}" if label != "transient" else "start-up transient",
                customdata=custom,
                hovertemplate=(
                    f"window %{{customdata[0]}}: {what}<br>"
                    f"{', '.join(f'|{x}|' for x in amplitude_ratio_labels(sel))} = {values}"
                    f"<br>angle difference %{{customdata[{k + 1}]:.3g}}°<extra></extra>"
                ),
            )
        )
    return out


def _merged_marks(
    mask: NDArray,
    sel: WindowSelection,
    sample_period: Timing,
    label: str,
    y: float,
    style: tuple[str, str],
) -> go.Scatter:
    """Many rejected windows: one mark per run of neighbouring ones (merged to MAX_RUNS)."""
    a, b, _ = merge_runs(*runs_of(mask), MAX_RUNS)
    # windows of this status in run j: cumsum[b_j] - cumsum[a_j]
    csum = np.concatenate([[0], np.cumsum(mask, dtype=np.int64)])
    count = csum[b] - csum[a]
    centre = x_axis((sel.starts[a] + sel.starts[b - 1] + sel.window) / 2.0, sample_period)
    symbol, color = style
    return go.Scatter(
        x=centre,
        y=np.full(a.size, y),
        mode="markers",
        marker={"symbol": symbol, "color": color, "size": 7},
        name=f"rejected: {label}" if label != "transient" else "start-up transient",
        customdata=np.column_stack([a, b - 1, count]),
        hovertemplate=(
            f"windows %{{customdata[0]}}–%{{customdata[1]}}: %{{customdata[2]}} {label}"
            "<extra></extra>"
        ),
    )


def window_tests_figure(  # long: one figure, built trace by trace in drawing order
    selection: WindowSelection,
    gamma_amp: float,
    gamma_ang: float,
    sample_period: float | None = None,
    title: str | None = None,
    height: int = 460,
    max_markers: int = MAX_FIGURE_MARKERS,
) -> go.Figure:
    """Each window's two test statistics against the thresholds of eq. [19].

    Abscissa: the amplitude test's statistic (:func:`amplitude_deviation`:
    ``max |r - 1|`` over ``|A1/A2|, |A2/A3|, |A3/A4|`` for the printed test,
    ``max tanh|ln r|`` over those and ``|A4/A1|`` for the symmetric one; the
    test passes below ``Γ_amp``); ordinate: the angle difference (passes
    below ``Γ_ang``). Kept windows sit in the lower-left box; the dashed lines
    show how far a threshold must move to keep more windows.

    Parameters
    ----------
    selection : WindowSelection
        Per-window tests (of the first smoothing filter).
    gamma_amp, gamma_ang : float
        The thresholds used.
    sample_period : float, optional
        Seconds per sample (for hover text).
    title : str, optional
        Figure title.
    height : int
        Pixel height.
    max_markers : int
        Most windows drawn (thinned beyond it; the legend counts them all).

    Returns
    -------
    go.Figure
    """
    dev = amplitude_deviation(selection)
    undefined = ~np.isfinite(dev)
    cap = max(10.0, gamma_amp * 10)
    dev = np.where(undefined, cap, np.clip(dev, 1e-4, cap))
    ang = np.clip(selection.angle_diff_deg, 1e-5, 90.0)
    status = window_status(selection)
    colors = {
        "kept": COLORS["kept_line"],
        "amplitude test": COLORS["amp"],
        "angle test": COLORS["angle"],
        "both tests": COLORS["both"],
        "transient": COLORS["transient"],
    }
    start = x_axis(selection.starts, sample_period)
    unit = "s" if has_time(sample_period) else "sample"
    data = []
    for label in STATUS:
        idx = np.flatnonzero(status == label)
        if idx.size == 0:
            continue
        data.append(
            go.Scatter(
                x=dev[idx],
                y=ang[idx],
                mode="markers",
                marker={"color": colors[label], "size": 6, "opacity": 0.75},
                name=f"{label} ({idx.size})",
                customdata=np.column_stack([idx, start[idx]]),
                hovertemplate=(
                    f"window %{{customdata[0]}} at %{{customdata[1]:.4g}} {unit}<br>"
                    "amplitude deviation = %{x:.3g}<br>angle diff = %{y:.3g}°<extra>"
                    f"{label}</extra>"
                ),
            )
        )
    v_shape, v_ann = vline(math.log10(gamma_amp), COLORS["amp"], text=f"Γ_amp = {gamma_amp:g}")
    h_shape, h_ann = hline(math.log10(gamma_ang), COLORS["angle"], text=f"Γ_ang = {gamma_ang:g}°")
    # shapes on log axes take log10 coordinates
    v_shape["x0"] = v_shape["x1"] = gamma_amp
    h_shape["y0"] = h_shape["y1"] = gamma_ang
    assert v_ann is not None and h_ann is not None
    v_ann["x"] = math.log10(gamma_amp)
    h_ann["y"] = math.log10(gamma_ang)
    anns = [v_ann, h_ann]
    if undefined.any():
        anns.append(
            {
                "text": f"{int(undefined.sum())} windows with an undefined ratio drawn at {cap:g}",
                "xref": "paper",
                "yref": "paper",
                "x": 1,
                "y": 0,
                "xanchor": "right",
                "yanchor": "bottom",
                "showarrow": False,
                "font": {"size": 11, "color": "#666"},
            }
        )
    lay = layout(
        title,
        height,
        # two lines: one is wider than a phone's figure
        xaxis=log_axis(
            wrap_words(f"amplitude test: {_deviation_label(selection)}"), np.r_[dev, gamma_amp]
        ),
        yaxis=log_axis("angle test: |atan a_S − atan a_T| (°)", np.r_[ang, gamma_ang]),
        shapes=[v_shape, h_shape],
        annotations=anns,
    )
    return capped(go.Figure(data=data, layout=lay), max_points=min(max_markers, MAX_FIGURE_MARKERS))
