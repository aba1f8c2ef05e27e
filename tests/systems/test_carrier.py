"""Adaptive-EKF carrier tracking of a weak GPS signal (docs/algorithms.md §B1)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.experiments.carrier import EXPERIMENT
from noisevar.systems.carrier import (
    JERK_PSD,
    AdaptiveCarrierQR,
    CarrierScenario,
    cn0_sweep,
    compare,
    comparison_variants,
    nominal_jerk_psd,
    nominal_measurement_variance,
    run_carrier,
    simulate_channel,
    slip_rates,
    wilson_interval,
)

SHORT = {"duration_s": 4.0, "manoeuvres_s": (1.0, 2.5)}


def test_amplitude_follows_cn0_and_integration_time() -> None:
    scen = CarrierScenario(cn0_dbhz=30.0, integration_s=0.01)
    assert scen.amplitude**2 / 2 == pytest.approx(1000.0 * 0.01)
    assert scen.n_steps == 1000


def test_aekf_with_the_true_r_and_q_is_the_ekf() -> None:
    scen = CarrierScenario(cn0_dbhz=32.0, **SHORT)
    ekf = run_carrier(scen, "ekf", seed=3, runs=4)
    aekf = run_carrier(scen, "aekf", seed=3, runs=4, adapt_r=False, adapt_q=False)
    np.testing.assert_allclose(aekf.estimate, ekf.estimate, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(aekf.slipped, ekf.slipped)


def test_runs_are_seeded() -> None:
    scen = CarrierScenario(**SHORT)
    a = run_carrier(scen, "ekf", seed=1, runs=2)
    b = run_carrier(scen, "ekf", seed=1, runs=2)
    c = run_carrier(scen, "ekf", seed=2, runs=2)
    np.testing.assert_array_equal(a.iq, b.iq)
    assert not np.array_equal(a.iq, c.iq)


def test_ekf_tracks_through_the_manoeuvres() -> None:
    scen = CarrierScenario(cn0_dbhz=35.0, **SHORT)
    res = run_carrier(scen, "ekf", seed=0, runs=8)
    assert res.loss_of_lock == 0.0
    assert res.rms_phase_error < 0.15
    assert np.sqrt(np.mean(res.doppler_error_hz[:, res.settle_steps :] ** 2)) < 2.0


def test_phase_error_shrinks_with_cn0() -> None:
    sweep = cn0_sweep((25.0, 35.0, 45.0), runs=6, seed=0, scenario=CarrierScenario(**SHORT))
    rms = sweep.rms_phase_error_rad["ekf"]
    assert rms[0] > rms[1] > rms[2]
    assert set(sweep.loss_of_lock) == {"ekf", "aekf"}


def test_data_bits_are_wiped_off() -> None:
    scen = CarrierScenario(cn0_dbhz=38.0, data_bits=True, **SHORT)
    res = run_carrier(scen, "ekf", seed=2, runs=4)
    assert res.loss_of_lock == 0.0
    assert res.rms_phase_error < 0.15


def test_aekf_adapts_r_and_q() -> None:
    scen = CarrierScenario(cn0_dbhz=30.0, **SHORT)
    r_only = run_carrier(scen, "aekf", seed=0, runs=3, window=20, adapt_q=False)
    # eq. (22) recovers the unit I/Q noise variance while the loop is locked
    assert 0.7 < np.median(r_only.R_track[:, -100:]) < 1.4
    both = run_carrier(scen, "aekf", seed=0, runs=3, window=20)  # q_rule="paper"
    # eq. (26) moves Q off the model's (upwards: our finding, see the module docs)
    assert np.all(both.Q_phase_track[:, -1] > 10 * both.Q_phase_track[:, 0])


def test_nominal_design_settings() -> None:
    # phase-noise variance R/A^2 = 1/(2 (C/N0)_nom T): R = (C/N0)/(C/N0)_nom
    assert nominal_measurement_variance(30.0, 45.0) == pytest.approx(10**-1.5)
    assert nominal_measurement_variance(45.0, 45.0) == 1.0
    scen = CarrierScenario(doppler_rate_hz_s=25.0)
    assert nominal_jerk_psd(scen, 25.0) == JERK_PSD
    assert nominal_jerk_psd(scen, 50.0) == pytest.approx(4 * JERK_PSD)
    res = run_carrier(
        CarrierScenario(cn0_dbhz=30.0, **SHORT),
        "ekf",
        runs=2,
        nominal_cn0_dbhz=45.0,
        nominal_doppler_rate_hz_s=5.0,
    )
    assert res.measurement_variance == pytest.approx(10**-1.5)
    assert res.jerk_psd == pytest.approx(JERK_PSD / 25)
    np.testing.assert_allclose(res.R_track, 10**-1.5)
    assert res.q_rule == "none"


def test_aekf_from_the_nominal_design_equals_its_ekf_without_adaptation() -> None:
    scen = CarrierScenario(cn0_dbhz=30.0, **SHORT)
    kw = {"seed": 4, "runs": 3, "nominal_cn0_dbhz": 45.0, "nominal_doppler_rate_hz_s": 40.0}
    ekf = run_carrier(scen, "ekf", **kw)
    aekf = run_carrier(scen, "aekf", adapt_r=False, adapt_q=False, **kw)
    np.testing.assert_allclose(aekf.estimate, ekf.estimate, rtol=1e-12, atol=1e-9)


def test_weak_signal_against_a_strong_signal_design() -> None:
    """The scenario the paper implies: design 45 dB-Hz, signal at 27 dB-Hz."""
    scen = CarrierScenario(cn0_dbhz=27.0, **SHORT)
    res = compare(scen, comparison_variants(45.0), seed=1, runs=12)
    assert set(res) == {"ekf", "aekf", "ekf_matched", "aekf_r_only", "aekf_paper_q"}
    # same signals for every filter
    for r in res.values():
        np.testing.assert_array_equal(r.true_doppler_hz, res["ekf"].true_doppler_hz)
    # the fixed design is over-confident (R 63x too small): noisier than the matched EKF
    assert res["ekf"].rms_phase_error > 1.15 * res["ekf_matched"].rms_phase_error
    # eq. (22) finds the true I/Q noise from the design's R
    assert res["aekf"].R_track[0, 0, 0] == pytest.approx(10**-1.8)
    assert 0.7 < np.median(res["aekf"].R_track[:, -100:]) < 1.4
    # the paper's eq. (26) runs away; the scaled Q stays near the (right) design
    paper = res["aekf_paper_q"]
    assert np.median(paper.Q_phase_track[:, -1]) > 1e3 * paper.Q_phase_track[0, 0]
    scale = res["aekf"].Q_phase_track[:, -1] / res["aekf"].Q_phase_track[:, 0]
    assert 0.3 < np.median(scale) < 3.0


def test_scaled_q_grows_when_the_design_dynamics_are_too_small() -> None:
    scen = CarrierScenario(cn0_dbhz=40.0, **SHORT)
    res = run_carrier(
        scen,
        "aekf",
        seed=2,
        runs=6,
        q_rule="scaled",
        nominal_cn0_dbhz=40.0,
        nominal_doppler_rate_hz_s=1.0,
    )
    scale = res.Q_phase_track[:, -1] / res.Q_phase_track[:, 0]
    assert res.q_rule == "scaled"
    assert np.median(scale) > 2.0
    assert np.all(scale <= 1e3 * (1 + 1e-12))  # the bound


def test_scaled_q_band_and_bounds() -> None:
    strat = AdaptiveCarrierQR(window=50, q_rule="scaled", coverage=0.99)
    lo, hi = strat._band
    assert 0.5 < lo < 0.6 and 1.5 < hi < 1.7  # chi-square(50)/50, 99 %
    for bad in (
        {"q_rule": "mehra"},
        {"q_bound": 1.0},
        {"q_bound": np.inf},
        {"coverage": 1.0},
        {"r_start": "zero"},
    ):
        with pytest.raises(NoisevarError):
            AdaptiveCarrierQR(**bad)


@pytest.mark.parametrize(
    "make",
    [
        lambda: CarrierScenario(cn0_dbhz=-30.0).validate(),
        lambda: CarrierScenario(cn0_dbhz=0.0).validate(),
        lambda: CarrierScenario(integration_s=0.05).validate(),
        lambda: CarrierScenario(integration_s=0.003, data_bits=True).validate(),
        lambda: CarrierScenario(duration_s=0.05).validate(),
        lambda: run_carrier(CarrierScenario(**SHORT), "pll"),
        lambda: run_carrier(CarrierScenario(**SHORT), "ekf", runs=0),
        lambda: run_carrier(CarrierScenario(**SHORT), "ekf", jerk_psd=0.0),
        lambda: simulate_channel(CarrierScenario(cn0_dbhz=-1.0)),
        lambda: run_carrier(CarrierScenario(**SHORT), "aekf", q_rule="eq25"),
        lambda: run_carrier(CarrierScenario(**SHORT), "aekf", r_start="empty"),
        lambda: slip_rates((30.0,), runs=0),
        lambda: wilson_interval(3, 2),
        lambda: run_carrier(CarrierScenario(**SHORT), "ekf", nominal_cn0_dbhz=-45.0),
        lambda: run_carrier(CarrierScenario(**SHORT), "ekf", nominal_doppler_rate_hz_s=0.0),
        lambda: nominal_jerk_psd(CarrierScenario(doppler_rate_hz_s=0.0), 25.0),
    ],
)
def test_bad_parameters_are_refused(make) -> None:
    with pytest.raises(NoisevarError):
        make()


def test_negative_cn0_message() -> None:
    with pytest.raises(NoisevarError, match="C/N0"):
        run_carrier(CarrierScenario(cn0_dbhz=-5.0))


def test_experiment_reports_the_issue_metrics() -> None:
    result = EXPERIMENT.run(runs=2, seed=0, cn0=30.0, duration=2.0, sweep=[30.0, 40.0]).to_dict()
    m = result["metrics"]
    for key in (
        "rms_phase_error_ekf_rad",
        "rms_phase_error_aekf_rad",
        "loss_of_lock_ekf",
        "loss_of_lock_aekf",
        "rms_phase_error_ekf_matched_rad",
        "loss_of_lock_ekf_matched",
        "rms_phase_error_aekf_r_only_rad",
        "rms_phase_error_aekf_paper_q_rad",
        "loss_of_lock_aekf_paper_q",
        "q_phase_aekf_paper_q_growth",
    ):
        assert np.isfinite(m[key])
    assert m["sweep"]["cn0_dbhz"] == [30.0, 40.0]
    assert len(m["sweep"]["rms_phase_error_ekf_matched_rad"]) == 2
    # ekf = the nominal (45 dB-Hz) design, said so next to the numbers
    assert m["r_design"] == pytest.approx(10**-1.5)
    assert result["settings"]["nominal_cn0_dbhz"] == 45.0
    assert {"ekf", "aekf", "ekf_matched"} <= set(result["definitions"])
    assert "AEKF" in EXPERIMENT.format_table(result)


def test_experiment_with_the_matched_design() -> None:
    result = EXPERIMENT.run(runs=2, seed=0, cn0=35.0, nominal_cn0=35.0, duration=1.0, sweep=[])
    m = result.to_dict()["metrics"]
    # designed for the actual C/N0 and dynamics, the fixed EKF is the matched one
    assert m["rms_phase_error_ekf_rad"] == m["rms_phase_error_ekf_matched_rad"]
    assert m["sweep"]["cn0_dbhz"] == []


def test_design_start_blends_the_design_r_into_the_first_window() -> None:
    """``r_start="design"``: after k < W residuals, R = (1 - k/W) R_design + (k/W) R_eq22."""
    scen = CarrierScenario(cn0_dbhz=30.0, **SHORT)
    kw = {"seed": 5, "runs": 3, "window": 20, "nominal_cn0_dbhz": 45.0, "q_rule": "scaled"}
    running = run_carrier(scen, "aekf", r_start="running", **kw)
    design = run_carrier(scen, "aekf", **kw)
    r_design = 10**-1.5
    # step 0 uses the design R in both; step 1 uses one residual (same in both)
    np.testing.assert_allclose(design.R_track[:, 0], r_design)
    np.testing.assert_allclose(
        design.R_track[:, 1], (1 - 1 / 20) * r_design + running.R_track[:, 1] / 20, rtol=1e-12
    )
    # the Q scale is not moved before its NIS window holds 20 steps of pure eq. (22) R
    assert np.all(design.Q_phase_track[:, :41] == design.Q_phase_track[:, :1])


def test_design_start_prevents_the_pull_in_lock_out() -> None:
    """Seeded pull-in where the paper's running mean inflates R and the loop slips."""
    scen = CarrierScenario(cn0_dbhz=30.0, duration_s=2.0, manoeuvres_s=(1.0, 1.5))
    v = comparison_variants(45.0)
    res = compare(
        scen,
        {"running": {**v["aekf"], "r_start": "running"}, "design": v["aekf"]},
        seed=2054,
        runs=8,
    )
    running, design = res["running"], res["design"]
    assert running.slipped[7] and not design.slipped.any()
    # the lock-out: a few pull-in residuals take the running R far above the truth (1)
    assert running.R_track[7, 2:10, 0].max() > 2.0
    assert design.R_track[7, 2:10, 0].max() < 1.0


def test_wilson_interval() -> None:
    lo, hi = wilson_interval(0, 1000)
    assert lo == 0.0 and hi == pytest.approx(0.00383, abs=1e-5)
    lo, hi = wilson_interval(10, 100)
    assert (lo, hi) == pytest.approx((0.0552, 0.1744), abs=1e-4)
    assert wilson_interval(100, 100)[1] == 1.0


def test_slip_rates_count_the_runs_that_slipped() -> None:
    scen = CarrierScenario(**SHORT)
    v = comparison_variants(45.0)
    variants = {"ekf": v["ekf"], "aekf": v["aekf"], "ekf_again": v["ekf"]}
    rates = slip_rates((24.0,), runs=6, seed=3, variants=variants, scenario=scen, chunk=4)
    # chunks of 4 and 2 runs, seeds 3 and 4
    direct = [
        compare(CarrierScenario(**{**SHORT, "cn0_dbhz": 24.0}), variants, seed=s, runs=b)
        for s, b in ((3, 4), (4, 2))
    ]
    for name in variants:
        assert rates.slipped[name][0] == sum(int(d[name].slipped.sum()) for d in direct)
        lo, hi = rates.ci95[name][0]
        assert lo <= rates.slipped[name][0] / 6 <= hi
        assert rates.before_manoeuvre[name][0] <= rates.slipped[name][0]
        assert rates.unlocked_at_end[name][0] <= rates.slipped[name][0]
        pooled = np.concatenate(
            [d[name].phase_error[:, d[name].settle_steps :].ravel() for d in direct]
        )
        assert rates.rms_phase_error_rad[name][0] == pytest.approx(np.sqrt(np.mean(pooled**2)))
    assert rates.slipped["ekf"][0] > 0  # 24 dB-Hz against a 45 dB-Hz design
    np.testing.assert_array_equal(rates.discordant["ekf_again"], [[0, 0]])
    assert rates.p_value["ekf_again"][0] == 1.0
    d = rates.discordant["aekf"][0]
    assert rates.slipped["aekf"][0] - rates.slipped["ekf"][0] == d[1] - d[0]
