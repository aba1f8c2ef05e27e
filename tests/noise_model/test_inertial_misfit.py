"""The IEEE-952 misfit check (docs/algorithms.md §E4): a record with a signal in it gets a
note and no filter file; model-true records get neither (issue 26)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.exports import imu_model
from noisevar.noise_model.inertial_misfit import APPROXIMATE, MISFIT
from noisevar.noise_model.kalibr import kalibr_imu
from noisevar.noise_model.simulate import simulate_inertial

RATE = 50.0


def _sine(n: int = 5000, seed: int = 0) -> np.ndarray:
    """0.3 Hz motion of 5x the white noise's std (the issue's reproduction, shorter)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / RATE
    return 0.1 * np.sin(2 * np.pi * 0.3 * t) + 0.02 * rng.normal(size=n)


def _noted(fit) -> list[str]:
    return [n for n in fit.notes if n.startswith(MISFIT)]


def test_a_sine_record_gets_the_misfit_note():
    fit = inertial_noise(_sine(), RATE, unit="rad/s")
    (note,) = _noted(fit)
    assert "regimes='still'" in note and "not the sensor's noise" in note
    assert fit.to_dict()["notes"][0] == note  # said first, after how the samples were placed


@pytest.mark.parametrize(
    "terms",
    [
        {"random_walk": 1e-3, "rate_random_walk": 1e-4},  # the first attempt's false alarm
        {
            "quantization": 1e-4,
            "random_walk": 1e-3,
            "bias_instability": 1e-3,
            "rate_random_walk": 1e-4,
            "rate_ramp": 1e-6,
        },
        {"random_walk": 1e-3, "bias_instability": 3e-3},
    ],
)
@pytest.mark.parametrize("seed", [0, 1])
def test_model_true_records_get_no_note(terms, seed):
    y = simulate_inertial(20000, RATE, seed=seed, **terms)
    assert not _noted(inertial_noise(y, RATE, unit="rad/s"))


def test_the_filter_files_refuse_a_fit_that_describes_nothing():
    moving = inertial_noise(_sine(), RATE, unit="rad/s")
    still = inertial_noise(
        simulate_inertial(5000, RATE, random_walk=1e-3, seed=2), RATE, unit="m/s^2"
    )
    with pytest.raises(NoisevarError, match="No Kalibr imu.yaml is written: gyroscope axis 0"):
        kalibr_imu(moving, still)
    with pytest.raises(NoisevarError, match="No filter config is written: gyroscope axis 0"):
        imu_model(moving, still)
    assert kalibr_imu(still, still).gyroscope_noise_density > 0  # a still record still writes


def test_noisevar_imu_says_it_and_writes_no_kalibr_file(tmp_path, capsys):
    rng = np.random.default_rng(3)
    path = tmp_path / "moving.csv"
    data = np.column_stack([_sine(), 0.01 * rng.normal(size=5000)])
    np.savetxt(path, data, delimiter=",", header="gx,ax", comments="")
    argv = ["imu", str(path), "--rate", str(RATE), "--gyro", "gx", "--accel", "ax"]
    assert main(argv) == 0
    assert capsys.readouterr().out.count(f"note: {MISFIT}") == 1  # the moving axis only
    out_yaml = tmp_path / "imu.yaml"
    for regimes, advice in (("all", "--regimes still"), ("still", "its still stretch too")):
        assert main([*argv, "--kalibr", str(out_yaml), "--regimes", regimes]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and "No Kalibr imu.yaml is written" in err and advice in err
    assert not out_yaml.exists()


def test_a_gauss_markov_bias_is_approximate_not_refused():
    """A still sensor's bias E4.1 has no term for: its sigma^2 tau never falls, so the
    fit is said to be approximate and the files are still written."""
    y = simulate_inertial(400_000, 100.0, random_walk=1e-3, gauss_markov=((1e-3, 10.0),), seed=1)
    fit = inertial_noise(y, 100.0, unit="rad/s")
    assert not _noted(fit)
    assert any(n.startswith(APPROXIMATE) for n in fit.notes)
    assert kalibr_imu(fit, fit).gyroscope_noise_density > 0
