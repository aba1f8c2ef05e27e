"""Command line: ``noisevar imu FILE --temperature COLUMN`` (§E9) and its bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.noise_model.simulate import simulate_thermal

RATE = 20.0


@pytest.fixture(scope="module")
def thermal_csv(tmp_path_factory) -> str:
    n = int(1800 * RATE)
    temp = np.linspace(15.0, 35.0, n)
    cols = {
        "gx": simulate_thermal(
            temp, RATE, polynomial=(1e-3, 2e-4), warmup=(3e-3, 120.0), random_walk=1e-3, seed=1
        ),
        "gy": simulate_thermal(temp, RATE, polynomial=(0.0, -1e-4), random_walk=1e-3, seed=2),
        "temp_c": temp,
    }
    path = tmp_path_factory.mktemp("thermal") / "imu_temp.csv"
    data = np.column_stack(list(cols.values()))
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="")
    return str(path)


def test_table_prints_bias_warmup_and_process_noise(capsys, thermal_csv) -> None:
    assert main(["imu", thermal_csv, "--rate", "20", "--temperature", "temp_c"]) == 0
    out = capsys.readouterr().out
    assert "gx against temp_c: bias(T)" in out and "gy against temp_c" in out
    assert "temp_c:" not in out.split("gx against")[0]  # not analysed as a rate column
    assert "u/°C" in out and "warm-up: A" in out and "bias process noise" in out
    assert "u/s/√Hz" in out


def test_json_has_the_temperature_models(capsys, thermal_csv) -> None:
    argv = ["imu", thermal_csv, "--rate", "20", "--columns", "gx", "--temperature", "temp_c"]
    assert main([*argv, "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert list(doc["columns"]) == ["gx"]
    b = doc["temperature"]["gx"]["coefficients"]["b"]
    assert b["value"] == pytest.approx(2e-4, rel=0.12)  # about 3 standard errors
    assert doc["temperature"]["gx"]["warmup"]["time_constant"] == pytest.approx(120.0, rel=0.3)


def test_bad_temperature_column_is_one_line(capsys, thermal_csv) -> None:
    argv = ["imu", thermal_csv, "--rate", "20", "--temperature", "nope"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "nope" in err
    assert (
        main(["imu", thermal_csv, "--rate", "20", "--columns", "temp_c", "--temperature", "temp_c"])
        == 2
    )
    assert "besides the temperature" in capsys.readouterr().err
