"""Every carrier figure built from a small seeded run."""

from __future__ import annotations

import pytest
from figure_checks import (
    axis_titles,
    log_axes_labelled,
    longest_trace,
    trace_length,
    trace_names,
)

from noisevar.errors import NoisevarError
from noisevar.figures.carrier import (
    adaptation_figure,
    doppler_figure,
    iq_figure,
    phase_error_figure,
    sweep_figure,
)
from noisevar.systems.carrier import (
    CarrierResult,
    CarrierScenario,
    CarrierSweep,
    cn0_sweep,
    compare,
    comparison_variants,
)

SCEN = CarrierScenario(duration_s=2.0, manoeuvres_s=(0.5, 1.2), ramp_s=0.2, hold_s=0.2)


@pytest.fixture(scope="module")
def results() -> list[CarrierResult]:
    variants = comparison_variants()
    chosen = {k: variants[k] for k in ("ekf", "aekf")}
    return list(compare(SCEN, chosen, seed=0, runs=2).values())


@pytest.fixture(scope="module")
def sweep() -> CarrierSweep:
    return cn0_sweep((30.0, 40.0), runs=2, scenario=SCEN)


def test_results_follow_the_protocol(results: list[CarrierResult]) -> None:
    assert [r.runs for r in results] == [2, 2]
    assert [r.label for r in results] == ["ekf/none", "aekf/scaled"]


def test_phase_error_figure(results: list[CarrierResult]) -> None:
    fig = phase_error_figure(results)
    names = trace_names(fig)
    assert len(names) == 2
    assert names[0].startswith("EKF, nominal design") and names[1].startswith(
        "AEKF (R from residuals"
    )
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "phase error (rad)"}
    assert longest_trace(fig) == SCEN.n_steps
    assert longest_trace(phase_error_figure(results, max_points=50)) <= 50


def test_doppler_figure(results: list[CarrierResult]) -> None:
    fig = doppler_figure(results)
    assert trace_names(fig)[0] == "true" and len(fig.data) == 3
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "Doppler (Hz)"}
    assert longest_trace(doppler_figure(results, max_points=50)) <= 50


def test_adaptation_figure(results: list[CarrierResult]) -> None:
    fig = adaptation_figure(results)
    names = trace_names(fig)
    assert len(names) == 4 and names[0].endswith(" R") and names[1].endswith(" Q")
    titles = axis_titles(fig)
    assert titles["yaxis"] == "R (I/Q noise)" and titles["xaxis2"] == "time (s)"
    assert log_axes_labelled(fig) == []
    assert longest_trace(adaptation_figure(results, max_points=50)) <= 50


def test_iq_figure(results: list[CarrierResult]) -> None:
    fig = iq_figure(results[1])
    assert trace_names(fig)[0] == "I, Q" and len(fig.data) == 2
    assert axis_titles(fig) == {"xaxis": "I", "yaxis": "Q"}
    assert trace_length(iq_figure(results[1], max_points=50), "I, Q") <= 50


def test_sweep_figure(sweep: CarrierSweep) -> None:
    fig = sweep_figure(sweep)
    assert len(fig.data) == 4
    titles = axis_titles(fig)
    assert titles["yaxis"] == "RMS phase error (rad)" and titles["xaxis2"] == "C/N0 (dB-Hz)"
    assert log_axes_labelled(fig) == []
    assert longest_trace(fig) == 2


@pytest.mark.parametrize(
    "build", [phase_error_figure, doppler_figure, adaptation_figure, iq_figure]
)
def test_bad_run_is_refused(results: list[CarrierResult], build) -> None:
    arg = results[0] if build is iq_figure else results
    with pytest.raises(NoisevarError, match="out of range"):
        build(arg, run=2)


def test_foreign_results_are_refused() -> None:
    with pytest.raises(NoisevarError, match="CarrierResult"):
        phase_error_figure([])
