"""Every estimator figure (signal, windows, envelope, compare modules) from a seeded signal."""

from __future__ import annotations

import numpy as np
import pytest
from figure_checks import axis_titles, longest_trace, trace_names

import noisevar
from noisevar.estimators.compare import MonteCarloResult, compare_methods, monte_carlo
from noisevar.figures import estimator
from noisevar.figures.compare import compare_figure, monte_carlo_figure, redundant_figure
from noisevar.figures.envelope import envelope_figure, scan_figure, window_variance_figure
from noisevar.figures.estimator import estimate_rows, signal_figure, window_rows
from noisevar.figures.windows import (
    STATUS,
    amplitude_deviation,
    amplitude_ratio_labels,
    amplitude_ratios,
    somd_figure,
    window_status,
    window_tests_figure,
)
from noisevar.filters.envelope import detrend_windows, noise_amplitude, scan_h

N = 3000


@pytest.fixture(scope="module")
def signal() -> noisevar.signals.GeneratedSignal:
    return noisevar.generate("fast-slow", seed=0)


@pytest.fixture(scope="module")
def z(signal) -> np.ndarray:
    return np.asarray(signal.measured[:N])


@pytest.fixture(scope="module")
def est(z) -> noisevar.VarianceEstimate:
    return noisevar.estimate(z, method="somd")


def test_old_module_path_re_exports_every_builder() -> None:
    for name in estimator.__all__:
        assert getattr(estimator, name) is not None
    assert estimator.somd_figure is somd_figure
    assert estimator.compare_figure is compare_figure
    assert estimator.scan_figure is scan_figure


def test_signal_figure(signal, z) -> None:
    fig = signal_figure(z, signal.sample_period, clean=signal.clean[:N])
    assert trace_names(fig) == ["signal", "clean"]
    assert axis_titles(fig)["xaxis"] == "time (s)"
    assert longest_trace(fig) == N
    small = signal_figure(z, signal.sample_period, max_points=200)
    assert longest_trace(small) <= 200
    assert signal_figure(z).layout.xaxis.title.text == "sample"


def test_somd_figure(signal, z, est) -> None:
    fig = somd_figure(z, est, signal.sample_period)
    names = trace_names(fig)
    assert names[:2] == ["kept windows", "raw samples"]
    assert names[2].startswith("smooth output") and names[3].startswith("tracking output")
    assert axis_titles(fig)["xaxis"] == "time (s)"
    assert longest_trace(somd_figure(z, est, signal.sample_period, max_points=300)) <= 300


@pytest.mark.parametrize("method", ["somd", "auto"])
def test_somd_figure_y_axis_is_the_record(signal, z, method) -> None:
    """The y axis is titled with the record's name and unit: a loop over the lines shadowed
    ``name``, so it read "tracking output, h_T=0.0005 (m)" (somd) or "raw samples (m) (m)"
    (auto), seen in a browser screenshot of the Estimator page."""
    est = noisevar.estimate(z, method=method)
    fig = somd_figure(z, est, signal.sample_period, units="m", name="east_m")
    assert axis_titles(fig)["yaxis"] == "east_m (m)"


def test_window_tests_figure(signal, est) -> None:
    sel = est.details.selection
    fig = window_tests_figure(sel, 0.3, 0.3, signal.sample_period)
    names = trace_names(fig)
    assert [n.split(" (")[0] for n in names] == list(STATUS)
    titles = axis_titles(fig)
    assert titles["xaxis"].startswith("amplitude test") and titles["yaxis"].startswith("angle test")
    status = window_status(sel)
    assert set(np.unique(status)) <= set(STATUS)
    assert amplitude_ratios(sel).shape[1] == len(amplitude_ratio_labels(sel))
    assert amplitude_deviation(sel).shape == status.shape


def test_envelope_figure(signal, z) -> None:
    amp = noise_amplitude(z, 40)
    det = detrend_windows(z, 40).ravel()
    fig = envelope_figure(amp, det, None, signal.sample_period)
    assert trace_names(fig) == ["detrended raw", "upper envelope U", "lower envelope L", "|V| raw"]
    assert axis_titles(fig)["yaxis2"] == "|V|"
    small = envelope_figure(amp, det, None, signal.sample_period, max_points=300)
    assert longest_trace(small) <= 300
    # the panel title and the downsampling note do not share the top line (issue 28 §8)
    top = [a for a in small.layout.annotations if a.y == 1.0 and a.yanchor == "bottom"]
    assert len(top) == 1 and "downsampled" in top[0].text
    assert small.layout.margin.t > fig.layout.margin.t


def test_scan_figure(z) -> None:
    fig = scan_figure(scan_h(z, 40))
    assert trace_names(fig)[0] == "|V1| / |V2|"
    assert axis_titles(fig)["xaxis"] == "h = q / r"


def test_window_variance_figure(signal, est) -> None:
    fig = window_variance_figure(est, signal.sample_period, signal.true_variance)
    names = trace_names(fig)
    assert len(fig.data) == 3 and names[0].startswith("window variance")
    # the estimate and the truth are legend entries, not labels buried in the scatter
    assert names[1].startswith("estimate ") and names[2].startswith("true variance")
    assert fig.data[1].y[0] == est.variance
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "noise variance"}


def test_compare_figure(signal, z) -> None:
    comp = compare_methods(z, ["somd", "rice", "diff2"], true_variance=signal.true_variance)
    fig = compare_figure(comp)
    assert trace_names(fig) == ["SOMD family", "peers"]
    assert axis_titles(fig)["xaxis"] == "noise variance (95 % interval)"


def test_monte_carlo_figure() -> None:
    mc: MonteCarloResult = list(
        monte_carlo("fast-slow", runs=3, methods=["rice", "diff2"], n=1000)
    )[-1]
    fig = monte_carlo_figure(mc)
    names = trace_names(fig)
    assert names[0] == "rice" and names[2] == "diff2"
    assert axis_titles(fig)["xaxis"] == "relative error (%)"


def test_redundant_figure(signal) -> None:
    rng = np.random.default_rng(0)
    clean = np.asarray(signal.clean[:N])
    sensors = clean[:, None] + rng.standard_normal((N, 3)) * np.array([1.0, 2.0, 3.0])
    res = noisevar.estimate_redundant(sensors)
    fig = redundant_figure(sensors, ["a", "b", "c"], res, signal.sample_period)
    assert trace_names(fig)[:3] == ["a", "b", "c"]
    assert len(fig.data) == 6  # three sensors, three pairwise differences
    small = redundant_figure(sensors, ["a", "b", "c"], res, signal.sample_period, max_points=200)
    assert longest_trace(small) <= 200


def test_table_rows(signal, est) -> None:
    rows = window_rows(est, signal.sample_period)
    assert len(rows) == est.details.selection.n_windows
    assert {"window", "status", "variance"} <= set(rows[0])
    quantities = [r["quantity"] for r in estimate_rows(est, signal.true_variance)]
    assert quantities[:2] == ["method", "variance"]
