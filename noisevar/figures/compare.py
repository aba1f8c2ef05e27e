"""Figures comparing estimation methods and sensors.

* :func:`compare_figure`, :func:`monte_carlo_figure` - methods side by side.
* :func:`redundant_figure` - several real sensors and their mutual differences.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike
from plotly.subplots import make_subplots

from noisevar.estimators.compare import Comparison, MonteCarloResult
from noisevar.estimators.results import RedundantEstimate
from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    downsample_note,
    layout,
    line_trace,
    stacked_axes,
    vline,
    x_title,
)

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


def monte_carlo_figure(  # long: one figure, built trace by trace in drawing order
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
    # too few successful runs: the panel says "failed 97/100" and draws no histogram
    shown = {m: bool(np.isfinite(summary[m]["rmse"])) for m in mc.methods}
    titles = [
        f"{m}: RMSE {100 * summary[m]['rmse']:.2f} %"
        if shown[m]
        else f"{m}: {summary[m]['status'].split(':')[0] or 'no run'}"
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
        e = e[np.isfinite(e)] * 100 if shown[m] else np.array([])
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
