"""The shared result/run checks of the figures (as_list, check_run) and the downsampling."""

from __future__ import annotations

import numpy as np
import pytest
from plotly.subplots import make_subplots

from noisevar.errors import NoisevarError
from noisevar.figures._common import (
    MAX_POINTS,
    as_list,
    base_layout,
    check_run,
    downsample_indices,
    layout,
    line_trace,
)
from noisevar.kalman import FixedR
from noisevar.systems.base import RunResult, check_run_index
from noisevar.systems.fusion import FusionData, FusionScenario, simulate_fusion
from noisevar.systems.scenarios import noise_step


@pytest.fixture(scope="module")
def data() -> FusionData:
    return simulate_fusion(FusionScenario(n_steps=20), seed=0, runs=3)


def test_as_list_accepts_one_result_or_a_sequence(data: FusionData) -> None:
    assert as_list(data, FusionData) == [data]
    assert as_list([data, data], FusionData) == [data, data]
    assert as_list((data,), FusionData) == [data]


@pytest.mark.parametrize("bad", [[], [object()], ["x"]])
def test_as_list_refuses_empty_or_foreign(data: FusionData, bad: list) -> None:
    with pytest.raises(NoisevarError, match="FusionData"):
        as_list(bad, FusionData)


def test_as_list_names_the_argument(data: FusionData) -> None:
    with pytest.raises(NoisevarError, match="^noisy: "):
        as_list([], FusionData, "noisy")


def test_protocol_and_check_run(data: FusionData) -> None:
    assert isinstance(data, RunResult)
    assert data.runs == 3
    assert data.label == "fusion/none"
    for run in range(3):
        check_run(data, run)
        data.check_run(run)
    for bad in (-1, 3, 10):
        with pytest.raises(NoisevarError, match="out of range"):
            check_run(data, bad)
        with pytest.raises(NoisevarError, match="3 runs"):
            data.check_run(bad)


def test_check_run_index() -> None:
    check_run_index(0, 1)
    with pytest.raises(NoisevarError):
        check_run_index(1, 1)


def test_check_run_on_filter_results() -> None:
    sc = noise_step(runs=2, seed=0, n_steps=300)
    assert sc.runs == 2 and sc.label == sc.name
    batched = sc.run(FixedR())
    check_run(batched, 1)
    with pytest.raises(NoisevarError, match="out of range"):
        check_run(batched, 2)
    sc.check_run(1)
    with pytest.raises(NoisevarError):
        sc.check_run(2)


def test_downsampling_caps_points() -> None:
    y = np.random.default_rng(1).standard_normal(MAX_POINTS * 3)
    idx = downsample_indices(y)
    assert idx.size <= MAX_POINTS
    assert np.all(np.diff(idx) > 0)
    assert downsample_indices(y[:100]).size == 100
    tr, reduced = line_trace(y, "y", 0.1, max_points=500)
    assert reduced
    assert len(tr.x) <= 500 and len(tr.y) == len(tr.x)
    tr, reduced = line_trace(y[:200], "y", max_points=500)
    assert not reduced and len(tr.y) == 200


def test_exports_of_a_figure_without_template_get_plotlys():
    # the dashboard builds figures without a template (its own colours on the page)
    import plotly.graph_objects as go
    import plotly.io as pio

    from noisevar.figures.export import _styled

    default, pio.templates.default = pio.templates.default, None
    try:
        bare = go.Figure(go.Scatter(y=[1.0, 2.0]))
    finally:
        pio.templates.default = default
    assert not bare.layout.template.to_plotly_json()
    styled = _styled(bare)
    assert styled.layout.template.layout.colorway == pio.templates["plotly"].layout.colorway
    assert not bare.layout.template.to_plotly_json()  # the figure itself is left alone
    dark = go.Figure(layout={"template": "plotly_dark"})
    assert _styled(dark) is dark


#: A sample period, or the samples' own times with a one-second gap mid-record.
GAPPED = np.arange(100) * 0.5 + np.r_[np.zeros(50), np.ones(50)]


@pytest.mark.parametrize("timing", [None, 0.5, GAPPED], ids=["index", "period", "times"])
def test_a_box_selection_maps_back_to_the_samples_it_covers(timing):
    from noisevar.figures.axes import range_to_slice, x_axis

    x = x_axis(np.arange(100), timing)
    assert range_to_slice(x[10], x[60], 100, timing) == slice(10, 61)
    assert range_to_slice(x[60], x[10], 100, timing) == slice(10, 61)  # either order
    assert range_to_slice(-1e9, 1e9, 100, timing) == slice(0, 100)  # clipped


def test_html_export_is_a_whole_page():
    import plotly.graph_objects as go

    from noisevar.figures.export import to_html

    page = to_html(go.Figure(go.Scatter(y=[1.0, 2.0])), self_contained=False)
    assert page.lstrip().lower().startswith("<!doctype html>") and "</html>" in page


def test_the_legend_reserves_its_rows_under_the_x_axis_title():
    """A legend placed in plot fractions rose onto the x-axis title once its rows (four
    two-line entries on a phone) had shrunk the plot (issue 28): it sits at the figure's
    bottom edge in pixels, where Plotly reserves its height under the x axis's own room,
    on every x axis of a figure with panels too."""
    lay = layout("t", 420, xaxis={"title": "time (s)"})
    assert lay["legend"]["yref"] == "container"
    assert (lay["legend"]["yanchor"], lay["legend"]["y"]) == ("bottom", 0.0)
    assert lay["xaxis"] == {"automargin": True, "title": "time (s)"}
    fig = base_layout(make_subplots(rows=2, cols=1), "t")
    assert fig.layout.xaxis.automargin and fig.layout.xaxis2.automargin
