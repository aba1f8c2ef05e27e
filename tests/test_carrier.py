"""Adaptive-EKF carrier tracking of a weak GPS signal (spec B1)."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

from noisevar.carrier import CarrierScenario, cn0_sweep, run_carrier, simulate_channel
from noisevar.errors import NoisevarError
from noisevar.experiments.carrier import EXPERIMENT

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
    both = run_carrier(scen, "aekf", seed=0, runs=3, window=20)
    # eq. (26) moves Q off the model's (upwards: our finding, see the module docs)
    assert np.all(both.Q_phase_track[:, -1] > 10 * both.Q_phase_track[:, 0])


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
    ],
)
def test_bad_parameters_are_refused(make) -> None:
    with pytest.raises(NoisevarError):
        make()


def test_negative_cn0_message() -> None:
    with pytest.raises(NoisevarError, match="C/N0"):
        run_carrier(CarrierScenario(cn0_dbhz=-5.0))


def test_experiment_reports_the_issue_metrics() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    EXPERIMENT.add_arguments(parser)
    args = parser.parse_args(["--cn0", "30", "--duration", "2", "--sweep", "30,40"])
    result = EXPERIMENT.run(args)
    m = result["metrics"]
    for key in (
        "rms_phase_error_ekf_rad",
        "rms_phase_error_aekf_rad",
        "loss_of_lock_ekf",
        "loss_of_lock_aekf",
    ):
        assert np.isfinite(m[key])
    assert m["sweep"]["cn0_dbhz"] == [30.0, 40.0]
    assert "AEKF" in EXPERIMENT.format_table(result)
