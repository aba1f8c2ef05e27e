"""Figures (and the tables beside them) of the variance estimators.

Every builder takes noisevar results and returns a ``go.Figure``; none
computes an estimate. Long records are drawn downsampled, with a note on the
figure. This module holds :func:`signal_figure` and the table rows
(:func:`window_rows`, :func:`estimate_rows`) and re-exports the builders of
:mod:`~noisevar.figures.windows` (SOMD steps, window tests),
:mod:`~noisevar.figures.envelope` (envelopes, h scan, window variances) and
:mod:`~noisevar.figures.compare` (methods side by side, redundant sensors).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike

from noisevar.estimators.results import VarianceEstimate
from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    capped,
    downsample_note,
    layout,
    line_trace,
    unit_name,
    x_title,
)
from noisevar.figures.compare import compare_figure, monte_carlo_figure, redundant_figure
from noisevar.figures.envelope import envelope_figure, scan_figure, window_variance_figure
from noisevar.figures.windows import (
    STATUS,
    amplitude_deviation,
    amplitude_ratio_labels,
    amplitude_ratios,
    somd_figure,
    window_status,
    window_tests_figure,
)

__all__ = [
    "STATUS",
    "amplitude_deviation",
    "amplitude_ratio_labels",
    "amplitude_ratios",
    "compare_figure",
    "envelope_figure",
    "estimate_rows",
    "monte_carlo_figure",
    "redundant_figure",
    "scan_figure",
    "signal_figure",
    "somd_figure",
    "window_rows",
    "window_status",
    "window_tests_figure",
    "window_variance_figure",
]


# ---------------------------------------------------------------------- signal
def signal_figure(
    z: ArrayLike,
    sample_period: float | None = None,
    name: str = "signal",
    clean: ArrayLike | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 420,
    units: str = "",
    t: ArrayLike | None = None,
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
    units : str
        Units of the samples (axis title).
    t : array_like, shape (n,), optional
        The record's own time stamps (seconds): drawn against them, so gaps show.

    Returns
    -------
    go.Figure
    """
    z = np.asarray(z, dtype=float)
    if t is not None:
        sample_period = np.asarray(t, dtype=float)
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
        yaxis={"title": {"text": unit_name(units, name)}},
        annotations=[note] if note else [],
    )
    return capped(go.Figure(data=data, layout=lay))


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
