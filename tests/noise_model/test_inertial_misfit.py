"""The IEEE-952 misfit check (docs/algorithms.md §E4): a record with a signal in it gets a
note and its filter files a warning; model-true records get neither (issue 26)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.exports import imu_model
from noisevar.noise_model.inertial_misfit import MISFIT
from noisevar.noise_model.kalibr import kalibr_imu, read_kalibr
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


def test_the_filter_files_warn_of_a_fit_that_describes_nothing():
    moving = inertial_noise(_sine(), RATE, unit="rad/s")
    still = inertial_noise(
        simulate_inertial(5000, RATE, random_walk=1e-3, seed=2), RATE, unit="m/s^2"
    )
    warning = "NOT A STILL SENSOR'S NOISE: gyroscope axis 0: " + MISFIT
    assert kalibr_imu(moving, still).notes[0].startswith(warning)
    assert imu_model(moving, still).notes[0].startswith(warning)
    assert not any("NOT A STILL" in n for n in kalibr_imu(still, still).notes)


def test_noisevar_imu_says_it_and_its_kalibr_file_warns(tmp_path, capsys):
    rng = np.random.default_rng(3)
    path = tmp_path / "moving.csv"
    data = np.column_stack([_sine(), 0.01 * rng.normal(size=5000)])
    np.savetxt(path, data, delimiter=",", header="gx,ax", comments="")
    argv = ["imu", str(path), "--rate", str(RATE), "--gyro", "gx", "--accel", "ax"]
    assert main(argv) == 0
    assert capsys.readouterr().out.count(f"note: {MISFIT}") == 1  # the moving axis only
    out_yaml = tmp_path / "imu.yaml"
    for regimes, advice in (("all", "--regimes still"), ("still", "its still stretch too")):
        assert main([*argv, "--kalibr", str(out_yaml), "--regimes", regimes]) == 0
        capsys.readouterr()
        warned = [n for n in read_kalibr(out_yaml).notes if n.startswith("NOT A STILL")]
        assert len(warned) == 1 and advice in warned[0]
