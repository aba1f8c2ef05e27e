"""Figures (and the tables beside them) of the variance estimators.

Every builder takes noisevar results and returns a ``go.Figure``; none
computes an estimate. Long records are drawn downsampled (see
:mod:`noisevar.figures`), with a note on the figure.

* :func:`signal_figure` - a record (and the clean signal when known).
* :func:`somd_figure` - raw samples with the smooth and tracking outputs, kept
  windows shaded, rejected windows marked with the test that failed, an
  optional chosen stretch; box-select on it picks a stretch.
* :func:`window_tests_figure` - each window's amplitude and angle statistics
  against the thresholds of eq. [19] (what to relax when few are kept).
* :func:`envelope_figure` - upper and lower envelopes and ``|V|`` per window (eq. [13]).
* :func:`scan_figure` - the ratio-vs-``h`` curve with the ``[1/20, 1/10]`` band (eq. [14]).
* :func:`window_variance_figure` - per-window variances and the final estimate with its 95 % CI.
* :func:`compare_figure`, :func:`monte_carlo_figure` - methods side by side.
* :func:`redundant_figure` - several real sensors and their mutual differences.
* :func:`window_rows`, :func:`estimate_rows` - the same results as table rows (CSV export).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike, NDArray
from plotly.subplots import make_subplots

from noisevar.estimators.compare import Comparison, MonteCarloResult
from noisevar.estimators.results import RedundantEstimate, VarianceEstimate
from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    band,
    downsample_note,
    hline,
    layout,
    line_trace,
    stacked_axes,
    step_xy,
    vline,
    x_axis,
    x_title,
)
from noisevar.filters.envelope import HScan, WindowAmplitude
from noisevar.filters.selection import WindowSelection

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


def _runs(mask: NDArray) -> list[tuple[int, int]]:
    """Start and stop (exclusive) of each run of True."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    d = np.diff(m.astype(np.int8))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1), strict=True))


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


# ---------------------------------------------------------------------- signal
def signal_figure(
    z: ArrayLike,
    sample_period: float | None = None,
    name: str = "signal",
    clean: ArrayLike | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 420,
) -> go.Figure:
    """A record, downsampled for drawing when long (and the clean signal when known).

    Parameters
    ----------
    z : array_like, shape (n,)
        Samples.
    sample_period : float, optional
        Seconds per sample (abscissa in seconds), else the sample index.
    name : str
        Legend name of the record.
    clean : array_like, optional
        Noise-free signal of a generated record.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    z = np.asarray(z, dtype=float)
    data = [
        line_trace(
            z, name, sample_period, max_points, line={"color": COLORS["smooth"], "width": 1}
        )[0]
    ]
    if clean is not None:
        data.append(
            line_trace(
                clean,
                "clean",
                sample_period,
                max_points,
                line={"color": COLORS["truth"], "width": 1.5},
            )[0]
        )
    note = downsample_note(z.size, max_points)
    lay = layout(
        title,
        height,
        xaxis={"title": {"text": x_title(sample_period)}},
        annotations=[note] if note else [],
    )
    return go.Figure(data=data, layout=lay)


# ------------------------------------------------------------------------ SOMD
def somd_figure(
    z: ArrayLike,
    est: VarianceEstimate,
    sample_period: float | None = None,
    stretch: slice | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 520,
) -> go.Figure:
    """Raw samples, smooth and tracking outputs, kept and rejected windows.

    Kept windows are shaded; each rejected window is marked above the record
    with the test that failed (amplitude, angle, both) or as start-up
    transient; hovering a mark gives the window's statistics. The drag mode
    is a horizontal box select, so a drag picks a stretch (see
    :func:`noisevar.figures.range_to_slice`).

    Parameters
    ----------
    z : array_like, shape (n,)
        The samples the estimate was computed on.
    est : VarianceEstimate
        A SOMD estimate (``est.details`` set); other methods draw the record only.
    sample_period : float, optional
        Seconds per sample.
    stretch : slice, optional
        A chosen stretch to highlight.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

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
    if d is not None:
        m = int(est.params.get("window", 40))
        runs = _runs(d.kept_windows)
        if runs:
            a, b = np.array(runs).T
            x0 = x_axis(a * m, sample_period)
            x1 = x_axis(np.minimum(b * m, n) - 1, sample_period)
            nan = np.full(a.size, np.nan)
            xs = np.column_stack([x0, x0, x1, x1, x0, nan]).ravel()
            y_lo, y_hi = lo - pad, hi + pad
            ys = np.tile([y_lo, y_hi, y_hi, y_lo, y_lo, np.nan], a.size)
            data.append(
                go.Scattergl(
                    x=xs,
                    y=ys,
                    fill="toself",
                    fillcolor=COLORS["kept"],
                    line={"width": 0},
                    mode="lines",
                    name="kept windows",
                    hoverinfo="skip",
                )
            )
    data.append(
        line_trace(
            z, "raw samples", sample_period, max_points, line={"color": COLORS["raw"], "width": 1}
        )[0]
    )
    if d is not None:
        for j, h in enumerate(d.h_smooth):
            color = COLORS["smooth"] if j == 0 else PALETTE[(j + 4) % len(PALETTE)]
            data.append(
                line_trace(
                    d.smooth_output[j],
                    f"smooth output, h_S={h:.3g}",
                    sample_period,
                    max_points,
                    line={"color": color, "width": 1.6},
                )[0]
            )
        data.append(
            line_trace(
                d.track_output,
                f"tracking output, h_T={d.h_track:.3g}",
                sample_period,
                max_points,
                line={"color": COLORS["track"], "width": 1.2, "dash": "dot"},
            )[0]
        )
        if d.selection is not None:
            data += _rejection_marks(d.selection, sample_period, hi + 2 * pad)
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
    note = downsample_note(n, max_points)
    if note:
        anns.append(note)
    lay = layout(
        title,
        height,
        dragmode="select",
        selectdirection="h",
        xaxis={"title": {"text": x_title(sample_period)}},
        shapes=shapes,
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


def _rejection_marks(
    sel: WindowSelection, sample_period: float | None, y: float
) -> list[go.Scattergl]:
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
        what = label if label != "transient" else "filter start-up transient"
        custom = np.column_stack([idx, ratios[idx], sel.angle_diff_deg[idx]])
        k = ratios.shape[1]
        values = ", ".join(f"%{{customdata[{c + 1}]:.3g}}" for c in range(k))
        out.append(
            go.Scattergl(
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


def window_tests_figure(
    selection: WindowSelection,
    gamma_amp: float,
    gamma_ang: float,
    sample_period: float | None = None,
    title: str | None = None,
    height: int = 460,
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
    unit = "s" if sample_period else "sample"
    data = []
    for label in STATUS:
        idx = np.flatnonzero(status == label)
        if idx.size == 0:
            continue
        data.append(
            go.Scattergl(
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
        xaxis={
            "type": "log",
            "title": {"text": f"amplitude test: {_deviation_label(selection)}"},
        },
        yaxis={"type": "log", "title": {"text": "angle test: |atan a_S − atan a_T| (°)"}},
        shapes=[v_shape, h_shape],
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


# -------------------------------------------------------------------- envelopes
def envelope_figure(
    raw: WindowAmplitude,
    detrended: ArrayLike,
    smooth: WindowAmplitude | None = None,
    sample_period: float | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 580,
) -> go.Figure:
    """Envelopes of the window-detrended record and ``|V|`` per window (eq. [13]).

    Top: the raw record with each window's least-squares line removed, its
    upper envelope (through the local maxima) and lower envelope (through
    the local minima). Bottom: ``|V| = Σ(U - L) / 2m`` per window for the raw
    record and, when given, for the smooth output: their ratio is the
    quantity of eq. [14].

    Parameters
    ----------
    raw : WindowAmplitude
        :func:`noisevar.filters.envelope.noise_amplitude` of the raw record.
    detrended : array_like, shape (n_windows * m,)
        The window-detrended raw record
        (:func:`noisevar.filters.envelope.detrend_windows`, flattened).
    smooth : WindowAmplitude, optional
        The same for the smooth output.
    sample_period : float, optional
        Seconds per sample.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    det = np.ravel(np.asarray(detrended, dtype=float))
    data = [
        line_trace(
            det,
            "detrended raw",
            sample_period,
            max_points,
            line={"color": COLORS["raw"], "width": 1},
        )[0]
    ]
    for arr, label, color in (
        (raw.upper, "upper envelope U", COLORS["track"]),
        (raw.lower, "lower envelope L", COLORS["smooth"]),
    ):
        data.append(
            line_trace(arr, label, sample_period, max_points, line={"color": color, "width": 1})[0]
        )
    m = raw.window
    edges = x_axis(np.arange(raw.amplitude.size + 1) * m, sample_period)
    x, y = step_xy(edges, raw.amplitude)
    data.append(
        go.Scattergl(
            x=x,
            y=y,
            yaxis="y2",
            mode="lines",
            name="|V| raw",
            line={"color": COLORS["track"], "width": 1.2},
        )
    )
    if smooth is not None:
        k = min(smooth.amplitude.size, raw.amplitude.size)
        x, y = step_xy(edges[: k + 1], smooth.amplitude[:k])
        data.append(
            go.Scattergl(
                x=x,
                y=y,
                yaxis="y2",
                mode="lines",
                name="|V| smooth output",
                line={"color": COLORS["smooth"], "width": 1.2},
            )
        )
    axes = stacked_axes(
        [0.6, 0.4],
        titles=("window-detrended raw record and its envelopes", "|V| per window (eq. 13)"),
    )
    axes["yaxis2"].update(type="log", title={"text": "|V|"})
    axes["xaxis"]["title"] = {"text": x_title(sample_period)}
    anns = axes.pop("annotations")
    note = downsample_note(det.size, max_points)
    if note:
        anns.append(note)
    return go.Figure(data=data, layout=layout(title, height, annotations=anns, **axes))


def scan_figure(
    scan: HScan,
    h_selected: Sequence[float] = (),
    h_track: float | None = None,
    title: str | None = None,
    height: int = 440,
) -> go.Figure:
    """The ratio ``|V1|/|V2|`` against ``h`` with the band of eq. [14] and the chosen ``h``.

    Parameters
    ----------
    scan : HScan
        :func:`noisevar.filters.envelope.scan_h` result.
    h_selected : sequence of float
        The smoothing ``h`` in use (drawn as vertical lines).
    h_track : float, optional
        The tracking ``h_T`` in use.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    lo, hi = scan.band
    shapes = [band(lo, hi, axis="y")]
    anns: list[dict[str, Any]] = [
        {
            "text": "band [1/20, 1/10]",
            "xref": "paper",
            "x": 1.0,
            "yref": "y",
            "y": math.log10(lo),
            "xanchor": "right",
            "yanchor": "top",
            "showarrow": False,
            "font": {"size": 11, "color": COLORS["smooth"]},
        }
    ]
    if math.isfinite(scan.h_min) and math.isfinite(scan.h_max):
        shapes.append(band(scan.h_min, scan.h_max, axis="x", color="rgba(0,158,115,0.12)"))
    data = [
        go.Scatter(
            x=scan.h,
            y=scan.ratio,
            mode="lines+markers",
            name="|V1| / |V2|",
            line={"color": COLORS["smooth"]},
            hovertemplate="h = %{x:.3g}<br>ratio = %{y:.3g}<extra></extra>",
        )
    ]
    j = int(np.argmin(np.abs(np.log(scan.h / scan.h_chosen))))
    data.append(
        go.Scatter(
            x=[scan.h_chosen],
            y=[scan.ratio[j]],
            mode="markers",
            marker={"size": 13, "color": COLORS["kept_line"], "symbol": "star"},
            name=f"chosen h = {scan.h_chosen:.3g}",
        )
    )
    for k, h in enumerate(h_selected):
        shp, ann = vline(h, COLORS["smooth"], text="h_S in use" if k == 0 else None)
        shapes.append(shp)
        if ann:
            ann["x"] = math.log10(h)
            anns.append(ann)
    if h_track is not None:
        shp, ann = vline(h_track, COLORS["track"], dash="dot", text="h_T")
        shapes.append(shp)
        assert ann is not None
        ann["x"] = math.log10(h_track)
        anns.append(ann)
    lay = layout(
        title,
        height,
        xaxis={"type": "log", "title": {"text": "h = q / r"}},
        yaxis={"type": "log", "title": {"text": "noise amplitude ratio |V1| / |V2|"}},
        shapes=shapes,
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


def window_variance_figure(
    est: VarianceEstimate,
    sample_period: float | None = None,
    true_variance: float | None = None,
    title: str | None = None,
    height: int = 420,
) -> go.Figure:
    """Per-window variance estimates with the final estimate and its 95 % interval.

    Parameters
    ----------
    est : VarianceEstimate
        A SOMD estimate (per-window values in ``est.details``); for other
        methods only the final estimate is drawn.
    sample_period : float, optional
        Seconds per sample.
    true_variance : float, optional
        Known variance (generated signals).
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    shapes: list[dict[str, Any]] = []
    anns: list[dict[str, Any]] = []
    data: list[Any] = []
    lo, hi = est.ci95
    if math.isfinite(lo) and math.isfinite(hi):
        shapes.append(band(lo, hi, axis="y"))
    d = est.details
    if d is not None:
        m = int(est.params.get("window", 40))
        wv = d.window_variance
        idx = np.flatnonzero(np.isfinite(wv))
        centre = x_axis(idx * m + m / 2.0, sample_period)
        data.append(
            go.Scattergl(
                x=centre,
                y=wv[idx],
                mode="markers",
                marker={"size": 5, "color": COLORS["kept_line"], "opacity": 0.7},
                name=f"window variance ({idx.size} kept windows)",
                hovertemplate="window centre %{x:.4g}<br>variance %{y:.4g}<extra></extra>",
            )
        )
    shp, ann = hline(
        est.variance,
        COLORS["estimate"],
        dash="solid",
        text=f"estimate {est.variance:.4g}  (95 % CI {_fmt(lo)} to {_fmt(hi)})",
    )
    shapes.append(shp)
    anns.append(ann)
    if true_variance is not None and math.isfinite(true_variance):
        shp, ann = hline(true_variance, COLORS["truth"], text=f"true {true_variance:.4g}")
        assert ann is not None
        ann.update(x=1.0, xanchor="right", yanchor="top")
        shapes.append(shp)
        anns.append(ann)
    lay = layout(
        title,
        height,
        xaxis={"title": {"text": x_title(sample_period)}},
        yaxis={"title": {"text": "noise variance"}, "rangemode": "tozero"},
        shapes=shapes,
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


# ------------------------------------------------------------------- comparisons
_KIND_COLOR = {"ours": PALETTE[2], "somd": PALETTE[0], "peer": PALETTE[9]}


def compare_figure(
    comp: Comparison, title: str | None = None, height: int | None = None
) -> go.Figure:
    """Every method's estimate with its 95 % interval (and the truth when known).

    Parameters
    ----------
    comp : Comparison
        :func:`noisevar.estimators.compare.compare_methods` result.
    title : str, optional
        Figure title.
    height : int, optional
        Pixel height (default grows with the number of methods).

    Returns
    -------
    go.Figure
    """
    data = []
    ok = [r for r in comp.results if r.estimate is not None]
    failed = [r for r in comp.results if r.estimate is None]
    for kind in ("ours", "somd", "peer"):
        rs = [r for r in ok if r.kind == kind]
        if not rs:
            continue
        v = np.array([r.variance for r in rs])
        lo = np.array([r.ci95[0] for r in rs])
        hi = np.array([r.ci95[1] for r in rs])
        data.append(
            go.Scatter(
                x=v,
                y=[r.method for r in rs],
                mode="markers",
                marker={"size": 10, "color": _KIND_COLOR[kind]},
                error_x={
                    "type": "data",
                    "symmetric": False,
                    "array": np.where(np.isfinite(hi), hi - v, 0),
                    "arrayminus": np.where(np.isfinite(lo), v - lo, 0),
                    "thickness": 2,
                },
                name={"ours": "our default", "somd": "SOMD family", "peer": "peers"}[kind],
                customdata=np.column_stack([lo, hi]),
                hovertemplate=(
                    "%{y}: %{x:.4g}<br>95 % CI %{customdata[0]:.4g} to %{customdata[1]:.4g}"
                    "<extra></extra>"
                ),
            )
        )
    shapes = []
    anns = []
    if comp.true_variance is not None:
        shp, ann = vline(comp.true_variance, COLORS["truth"], text=f"true {comp.true_variance:.4g}")
        shapes.append(shp)
        anns.append(ann)
    for r in failed:
        anns.append(
            {
                "x": 0,
                "xref": "paper",
                "y": r.method,
                "yref": "y",
                "text": f"{r.method}: failed",
                "showarrow": False,
                "xanchor": "left",
                "font": {"color": COLORS["both"]},
            }
        )
    order = [r.method for r in comp.results][::-1]
    lay = layout(
        title,
        height or 200 + 34 * len(comp.results),
        xaxis={"title": {"text": "noise variance (95 % interval)"}},
        yaxis={"categoryorder": "array", "categoryarray": order, "type": "category"},
        shapes=shapes,
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


def monte_carlo_figure(
    mc: MonteCarloResult, bins: int = 40, cols: int = 3, title: str | None = None
) -> go.Figure:
    """Relative-error histogram per method (the paper's Fig. 2) with the Cramér-Rao floor.

    Each panel shows one method's relative errors (percent) over the runs
    done, the ±10 % lines of the paper's criterion, and the density of the
    best possible estimator, a normal with relative standard deviation
    ``sqrt(2/n)``, scaled to the run count.

    Parameters
    ----------
    mc : MonteCarloResult
        A (possibly partial) Monte Carlo result.
    bins : int
        Histogram bins (shared edges across panels).
    cols : int
        Panels per row.
    title : str, optional
        Figure title.

    Returns
    -------
    go.Figure
    """
    k = len(mc.methods)
    cols = max(1, min(cols, k))
    rows = int(math.ceil(k / cols))
    summary = {r["method"]: r for r in mc.summary()}
    titles = [
        f"{m}: RMSE {100 * summary[m]['rmse']:.2f} %" if summary[m]["runs"] else f"{m}: no run"
        for m in mc.methods
    ]
    fig = make_subplots(
        rows=rows,
        cols=cols,
        shared_xaxes=True,
        subplot_titles=titles,
        vertical_spacing=min(0.12, 0.5 / rows),
        horizontal_spacing=0.06,
    )
    allerr = np.concatenate([e[np.isfinite(e)] for e in mc.relative_errors.values()] or [[0.0]])
    cr = mc.cr_floor
    span = max(0.12, 4 * cr, float(np.percentile(np.abs(allerr), 99.5)) if allerr.size else 0.12)
    edges = np.linspace(-span, span, bins + 1) * 100
    width = edges[1] - edges[0]
    xs = np.linspace(-span, span, 200)
    dens = np.exp(-0.5 * (xs / cr) ** 2) / (cr * math.sqrt(2 * math.pi))
    for i, m in enumerate(mc.methods):
        r, c = i // cols + 1, i % cols + 1
        e = mc.relative_errors[m]
        e = e[np.isfinite(e)] * 100
        counts, _ = np.histogram(np.clip(e, edges[0], edges[-1]), bins=edges)
        fig.add_trace(
            go.Bar(
                x=(edges[:-1] + edges[1:]) / 2,
                y=counts,
                width=width,
                marker={"color": PALETTE[i % len(PALETTE)]},
                name=m,
                showlegend=False,
                hovertemplate="%{x:.1f} %: %{y} runs<extra>" + m + "</extra>",
            ),
            row=r,
            col=c,
        )
        fig.add_trace(
            go.Scatter(
                x=xs * 100,
                y=dens * e.size * width / 100,
                mode="lines",
                line={"color": COLORS["truth"], "dash": "dot", "width": 1.2},
                name=f"Cramér-Rao floor (sd {100 * cr:.2f} %)",
                showlegend=i == 0,
                hoverinfo="skip",
            ),
            row=r,
            col=c,
        )
        for x in (-10, 10):
            fig.add_shape(
                type="line",
                x0=x,
                x1=x,
                y0=0,
                y1=1,
                yref="y domain",
                line={"dash": "dash", "color": "#bbb"},
                row=r,
                col=c,
            )
    fig.update_layout(**layout(title, 230 * rows + 150), bargap=0.0)
    fig.update_xaxes(title="relative error (%)", row=rows)
    return fig


# --------------------------------------------------------------- real sensors
def redundant_figure(
    sensors: ArrayLike,
    names: Sequence[str],
    result: RedundantEstimate | None = None,
    sample_period: float | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 620,
) -> go.Figure:
    """Several sensors of one quantity and their mutual differences ``ΔZi - ΔZj`` (eq. [8]).

    Parameters
    ----------
    sensors : array_like, shape (n, k)
        One column per sensor.
    names : sequence of str
        Sensor names.
    result : RedundantEstimate, optional
        Adds each pair's ``var_i + var_j`` to the legend.
    sample_period : float, optional
        Seconds per sample.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    s = np.asarray(sensors, dtype=float)
    n, k = s.shape
    data = []
    for j in range(k):
        data.append(
            line_trace(
                s[:, j],
                names[j],
                sample_period,
                max_points,
                line={"color": PALETTE[j % len(PALETTE)], "width": 1},
            )[0]
        )
    d = np.diff(s, axis=0)
    c = 0
    for i in range(k):
        for j in range(i + 1, k):
            label = f"Δ{names[i]} − Δ{names[j]}"
            if result is not None:
                label += f" (var sum {result.pair_sums[i, j]:.4g})"
            data.append(
                line_trace(
                    d[:, i] - d[:, j],
                    label,
                    sample_period,
                    max_points,
                    line={"color": PALETTE[(c + 3) % len(PALETTE)], "width": 1},
                    opacity=0.8,
                    yaxis="y2",
                )[0]
            )
            c += 1
    axes = stacked_axes([0.55, 0.45], titles=("sensors", "mutual differences ΔZi − ΔZj"))
    axes["xaxis"]["title"] = {"text": x_title(sample_period)}
    anns = axes.pop("annotations")
    note = downsample_note(n, max_points)
    if note:
        anns.append(note)
    return go.Figure(data=data, layout=layout(title, height, annotations=anns, **axes))


# ------------------------------------------------------------------------ tables
def estimate_rows(
    est: VarianceEstimate, true_variance: float | None = None
) -> list[dict[str, Any]]:
    """The final estimate as ``name, value`` rows (summary table, CSV).

    Parameters
    ----------
    est : VarianceEstimate
        An estimate.
    true_variance : float, optional
        Known variance.

    Returns
    -------
    list of dict
    """
    rows: list[dict[str, Any]] = [
        {"quantity": "method", "value": est.method},
        {"quantity": "variance", "value": est.variance},
        {"quantity": "std", "value": est.std},
        {"quantity": "ci95_low", "value": est.ci95[0]},
        {"quantity": "ci95_high", "value": est.ci95[1]},
        {"quantity": "n_used", "value": est.n_used},
        {"quantity": "n_total", "value": est.n_total},
        {"quantity": "dof", "value": est.dof},
    ]
    if est.details is not None and est.details.selection is not None:
        for key, val in est.details.selection.rejection_summary().items():
            rows.append({"quantity": f"windows_{key}", "value": val})
    if true_variance is not None:
        rows.append({"quantity": "true_variance", "value": true_variance})
        rows.append({"quantity": "relative_error", "value": est.variance / true_variance - 1.0})
    for k, v in est.params.items():
        if k != "method":
            rows.append({"quantity": f"param_{k}", "value": v})
    return rows


def window_rows(est: VarianceEstimate, sample_period: float | None = None) -> list[dict[str, Any]]:
    """One row per window of a SOMD estimate: position, tests, status, variance.

    Parameters
    ----------
    est : VarianceEstimate
        A SOMD estimate (empty list for other methods).
    sample_period : float, optional
        Seconds per sample (adds ``start_s``).

    Returns
    -------
    list of dict
    """
    d = est.details
    if d is None:
        return []
    m = int(est.params.get("window", 40))
    sel = d.selection
    status = window_status(sel) if sel is not None else None
    ratios = amplitude_ratios(sel) if sel is not None else None
    rows = []
    for i in range(d.kept_windows.size):
        row: dict[str, Any] = {"window": i, "start_sample": i * m}
        if sample_period:
            row["start_s"] = i * m * sample_period
        row["kept"] = bool(d.kept_windows[i])
        if sel is not None and status is not None and ratios is not None:
            row["status"] = status[i]
            for label, x in zip(amplitude_ratio_labels(sel), ratios[i], strict=True):
                row["ratio_" + label.replace("/", "_")] = float(x)
            row["angle_diff_deg"] = float(sel.angle_diff_deg[i])
        row["variance"] = float(d.window_variance[i])
        rows.append(row)
    return rows
