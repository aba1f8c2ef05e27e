"""Robust Huber EKF with a magnetic-variation state (docs/algorithms.md §B3)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.experiments.outliers import EXPERIMENT
from noisevar.systems.robust import (
    DEFAULT_KAPPA,
    PAPER_KAPPA,
    RobustScenario,
    kappa_tradeoff,
    paired_rmse_ratio,
    run_robust,
    simulate_robust,
    trajectory,
)


def test_trajectory_flies_over_and_past_the_station() -> None:
    scen = RobustScenario()
    _, states = trajectory(scen)
    horiz = np.hypot(states[:, 0], states[:, 1])
    assert horiz.min() < 2 * scen.overflight_offset_m
    speed = np.hypot(states[:, 2], states[:, 3])
    np.testing.assert_allclose(speed, scen.speed, rtol=1e-6)
    assert states[-1, 3] > 0.9 * scen.speed  # flies north after the turn


def test_simulation_is_seeded_and_outliers_stay_near_the_station() -> None:
    a = simulate_robust(seed=1, runs=3)
    b = simulate_robust(seed=1, runs=3)
    c = simulate_robust(seed=2, runs=3)
    np.testing.assert_array_equal(a.z, b.z)
    assert not np.array_equal(a.z, c.z)
    assert a.outlier.any()
    assert not a.outlier[:, ~a.near_station].any()


def test_huber_with_infinite_kappa_is_the_ekf() -> None:
    data = simulate_robust(RobustScenario(outliers=False, duration_s=200), seed=3, runs=2)
    res = run_robust(data, kappa=np.inf, filters=("ekf", "huber"))
    np.testing.assert_allclose(res.filters["huber"].x, res.filters["ekf"].x, rtol=1e-9, atol=1e-4)


def test_huber_without_outliers_is_close_to_the_ekf() -> None:
    data = simulate_robust(RobustScenario(outliers=False), seed=4, runs=10)
    res = run_robust(data, filters=("ekf", "huber"))
    ratio = res.rmse_position["huber"] / res.rmse_position["ekf"]
    # the default κ (2.5) costs little at the Gaussian; over 10 runs the far,
    # bearing-limited start makes the ratio scatter by a few %
    assert res.kappa == DEFAULT_KAPPA
    assert 0.95 < ratio < 1.15


def test_huber_resists_bearing_outliers_and_finds_the_magnetic_variation() -> None:
    data = simulate_robust(seed=5, runs=10)
    res = run_robust(data)
    rm = res.rmse_position
    assert rm["huber"] < 0.8 * rm["ekf"]
    assert rm["no-bias"] > 3 * rm["huber"]
    assert abs(np.mean(res.magvar_estimate_deg) - (-5.0)) < 0.5
    assert np.all(np.abs(res.magvar_estimate_deg + 5.0) < 1.0)


def test_other_magnetic_variation() -> None:
    data = simulate_robust(RobustScenario(magvar_deg=8.0, outliers=False), seed=6, runs=4)
    res = run_robust(data, filters=("huber",))
    assert abs(np.mean(res.magvar_estimate_deg) - 8.0) < 0.5


def test_paired_rmse_ratio() -> None:
    rng = np.random.default_rng(0)
    b = rng.exponential(1.0, 50)
    assert paired_rmse_ratio(b, b) == (1.0, 1.0, 1.0)
    ratio, lo, hi = paired_rmse_ratio(4.0 * b, b)  # same noise: no scatter at all
    assert ratio == pytest.approx(2.0) and lo == pytest.approx(2.0) and hi == pytest.approx(2.0)
    a = b * rng.uniform(0.5, 1.5, 50)
    ratio, lo, hi = paired_rmse_ratio(a, b, n_boot=500, seed=1)
    assert lo < ratio < hi
    assert np.isnan(paired_rmse_ratio(a[:1], b[:1])[1])
    with pytest.raises(NoisevarError):
        paired_rmse_ratio(a, b[:10])


def test_kappa_tradeoff_on_the_same_runs() -> None:
    scen = RobustScenario(duration_s=200.0, start_east_m=-12_000.0, turn_time_s=120.0)
    noisy = simulate_robust(scen, seed=7, runs=6)
    clean = simulate_robust(
        RobustScenario(duration_s=200.0, start_east_m=-12_000.0, turn_time_s=120.0, outliers=False),
        seed=7,
        runs=6,
    )
    table = kappa_tradeoff(noisy, clean, (PAPER_KAPPA, np.inf), n_boot=200)
    assert table.runs == 6
    # κ = inf is the plain update: ratio 1 with and without outliers
    assert table.ratio_outliers[1] == pytest.approx(1.0, abs=1e-6)
    assert table.ratio_clean[1] == pytest.approx(1.0, abs=1e-6)
    # the paper's κ resists the outliers
    assert table.ratio_outliers[0] < 0.9
    assert np.all(table.ci_outliers[:, 0] <= table.ratio_outliers + 1e-12)
    assert np.all(table.ratio_outliers <= table.ci_outliers[:, 1] + 1e-12)
    # results computed elsewhere are reused, not recomputed differently
    known = {
        PAPER_KAPPA: (
            run_robust(noisy, kappa=PAPER_KAPPA),
            run_robust(clean, kappa=PAPER_KAPPA, filters=("ekf", "huber")),
        )
    }
    again = kappa_tradeoff(noisy, clean, (PAPER_KAPPA,), n_boot=200, known=known)
    assert again.ratio_outliers[0] == pytest.approx(table.ratio_outliers[0], rel=1e-12)
    # pooling two batches doubles the runs
    assert kappa_tradeoff([noisy, noisy], [clean, clean], (3.0,), n_boot=50).runs == 12


@pytest.mark.parametrize(
    "make",
    [
        lambda: kappa_tradeoff(simulate_robust(RobustScenario(duration_s=20)), [], (1.0,)),
        lambda: kappa_tradeoff(
            simulate_robust(RobustScenario(duration_s=20)),
            simulate_robust(RobustScenario(duration_s=20)),
            (0.0,),
        ),
        lambda: simulate_robust(RobustScenario(burst_rate=2.0)),
        lambda: simulate_robust(RobustScenario(bearing_std_deg=-1.0)),
        lambda: simulate_robust(RobustScenario(burst_length=(5, 2))),
        lambda: simulate_robust(RobustScenario(magvar_deg=120.0)),
        lambda: simulate_robust(runs=0),
        lambda: run_robust(simulate_robust(RobustScenario(duration_s=20)), kappa=-1.0),
        lambda: run_robust(simulate_robust(RobustScenario(duration_s=20)), filters=("ukf",)),
    ],
)
def test_bad_parameters_are_refused(make) -> None:
    with pytest.raises(NoisevarError):
        make()


def test_experiment_reports_the_issue_metrics() -> None:
    sweep = [1.345, 1.5, 2.0, 2.5, 3.0]
    result = EXPERIMENT.run(runs=2, seed=0, kappa_sweep=sweep).to_dict()
    m = result["metrics"]
    for key in (
        "rmse_position_ekf",
        "rmse_position_huber",
        "rmse_position_no_bias_state",
        "magvar_estimate_deg",
        "magvar_true_deg",
    ):
        assert np.isfinite(m[key])
    assert m["magvar_true_deg"] == -5.0
    assert "Huber" in EXPERIMENT.format_table(result)
    # paired intervals, the paper's κ and the κ table on the same runs
    assert result["settings"]["kappa"] == DEFAULT_KAPPA
    lo, hi = m["huber_over_ekf_no_outliers_ci95"]
    assert lo <= m["huber_over_ekf_no_outliers"] <= hi
    assert np.isfinite(m["huber_paper_kappa_over_ekf_with_outliers"])
    sweep = m["kappa_sweep"]
    assert sweep["kappa"] == [PAPER_KAPPA, 1.5, 2.0, 2.5, 3.0]
    i = sweep["kappa"].index(DEFAULT_KAPPA)
    assert sweep["huber_over_ekf_with_outliers"][i] == pytest.approx(
        m["huber_over_ekf_with_outliers"], rel=1e-12
    )
    assert len(sweep["meets_both_targets_over_ci95"]) == 5
    assert "κ sweep" in EXPERIMENT.format_table(result)


def test_experiment_without_the_kappa_sweep() -> None:
    result = EXPERIMENT.run(runs=2, seed=0, kappa=1.345).to_dict()
    m = result["metrics"]
    assert m["kappa_sweep"]["kappa"] == []  # the table is on demand
    assert m["huber_paper_kappa_over_ekf_with_outliers"] == pytest.approx(
        m["huber_over_ekf_with_outliers"], rel=1e-12
    )
    with pytest.raises(NoisevarError, match="kappa_sweep"):
        EXPERIMENT.run(runs=2, seed=0, kappa_sweep=[1.0, -2.0])
