"""Distributed VB fusion with fault isolation (docs/algorithms.md §B2)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.experiments.fusion import EXPERIMENT
from noisevar.systems.fusion import (
    FusionScenario,
    Sensor,
    run_centralized,
    run_fusion,
    simulate_fusion,
)


@pytest.mark.parametrize("feedback", [True, False])
def test_fusion_equals_the_centralised_filter(feedback: bool) -> None:
    data = simulate_fusion(FusionScenario(n_steps=300), seed=11, runs=4)
    central = run_centralized(data)
    fused = run_fusion(data, local="fixed", feedback=feedback)
    assert np.max(np.abs(fused.x - central.x)) < 1e-8
    assert not fused.isolated.any()


def test_equivalence_holds_with_a_single_sensor() -> None:
    pos = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    scen = FusionScenario(n_steps=100, sensors=(Sensor("gps", pos, [5.0, 5.0]),))
    data = simulate_fusion(scen, seed=1, runs=2)
    assert np.max(np.abs(run_fusion(data, local="fixed").x - run_centralized(data).x)) < 1e-8


def test_simulation_is_seeded() -> None:
    a = simulate_fusion(FusionScenario(n_steps=50, fault="bias"), seed=3, runs=2)
    b = simulate_fusion(FusionScenario(n_steps=50, fault="bias"), seed=3, runs=2)
    c = simulate_fusion(FusionScenario(n_steps=50, fault="bias"), seed=4, runs=2)
    np.testing.assert_array_equal(a.measurements[0], b.measurements[0])
    assert not np.array_equal(a.measurements[0], c.measurements[0])


@pytest.mark.parametrize("fault", ["bias", "frozen"])
def test_isolation_removes_a_failing_sensor(fault: str) -> None:
    data = simulate_fusion(FusionScenario(n_steps=300, fault=fault), seed=5, runs=8)
    with_iso = run_fusion(data, local="fixed", isolation=True)
    without = run_fusion(data, local="fixed", isolation=False)
    assert with_iso.rmse() < 0.2 * without.rmse()
    # the failing sensor is isolated throughout its fault, the others hardly ever
    assert with_iso.isolated[:, data.fault_mask, 0].mean() > 0.95
    assert with_iso.isolated[:, :, 1:].mean() < 0.01


def test_vb_tracks_a_noise_step_and_beats_fixed_r() -> None:
    data = simulate_fusion(FusionScenario(n_steps=500, fault="noise-step"), seed=7, runs=8)
    vb = run_fusion(data, local="vb")
    fixed = run_fusion(data, local="fixed")
    assert vb.rmse() < fixed.rmse()
    true_r = data.true_R(0)[-1, 0]
    late = np.nanmean(vb.R_track[0][:, -100:, 0])
    assert abs(late / true_r - 1.0) < 0.35
    assert vb.R_track[0].shape == (8, 500, 2)


def test_isolated_samples_do_not_train_the_vb_strategy() -> None:
    data = simulate_fusion(FusionScenario(n_steps=200, fault="bias"), seed=2, runs=3)
    res = run_fusion(data, local="vb", isolation=True)
    nominal = data.true_R(0)[0, 0]
    r_during = res.R_track[0][:, data.fault_mask, 0]
    # during the fault all samples are rejected (NaN in the track) ...
    assert np.isnan(r_during).mean() > 0.95
    # ... and before it the estimate is of the nominal size
    before = np.nanmean(res.R_track[0][:, 50 : int(np.argmax(data.fault_mask)), 0])
    assert 0.5 < before / nominal < 1.5


@pytest.mark.parametrize(
    "make",
    [
        lambda: simulate_fusion(FusionScenario(sensors=())),
        lambda: simulate_fusion(FusionScenario(fault="meltdown")),
        lambda: simulate_fusion(FusionScenario(faulty_sensor=5)),
        lambda: simulate_fusion(FusionScenario(fault_start=0.8, fault_end=0.2)),
        lambda: simulate_fusion(FusionScenario(), runs=0),
        lambda: Sensor("bad", np.eye(2), [1.0, 1.0]),
        lambda: Sensor("bad", np.eye(4)[:2], [1.0, -1.0]),
        lambda: run_fusion(simulate_fusion(FusionScenario(n_steps=10)), local="magic"),
        lambda: run_fusion(simulate_fusion(FusionScenario(n_steps=10)), false_alarm=2.0),
    ],
)
def test_bad_parameters_are_refused(make) -> None:
    with pytest.raises(NoisevarError):
        make()


def test_zero_sensors_message() -> None:
    with pytest.raises(NoisevarError, match="zero sensors"):
        simulate_fusion(FusionScenario(sensors=()))


def test_experiment_reports_the_issue_metrics() -> None:
    result = EXPERIMENT.run(runs=2, seed=0, steps=150).to_dict()
    m = result["metrics"]
    assert m["max_abs_diff_vs_centralized"] < 1e-8
    for key in (
        "rmse_with_isolation",
        "rmse_without_isolation",
        "rmse_vb_fusion",
        "rmse_fixed_fusion",
    ):
        assert np.isfinite(m[key])
    track = m["vb_r_track"]
    assert len(track["time_s"]) == len(track["r_estimate"]) == len(track["r_true"])
    assert "fusion" in EXPERIMENT.format_table(result)
