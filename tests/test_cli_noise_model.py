"""Command line: ``noisevar allan`` and ``noisevar imu`` (§E4), and their bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.noise_model import allan
from noisevar.noise_model.kalibr import read_kalibr
from noisevar.noise_model.simulate import simulate_inertial

RATE = 50.0


@pytest.fixture(scope="module")
def imu_csv(tmp_path_factory) -> tuple[str, dict[str, np.ndarray]]:
    cols = {
        "gx": simulate_inertial(20_000, RATE, random_walk=1e-3, rate_random_walk=1e-4, seed=1),
        "gy": simulate_inertial(20_000, RATE, random_walk=3e-3, rate_random_walk=1e-4, seed=2),
        "ax": simulate_inertial(20_000, RATE, random_walk=2e-2, rate_random_walk=1e-3, seed=3),
    }
    path = tmp_path_factory.mktemp("imu") / "imu.csv"
    np.savetxt(
        path,
        np.column_stack(list(cols.values())),
        delimiter=",",
        header=",".join(cols),
        comments="",
    )
    return str(path), cols


def test_allan_table(capsys, imu_csv) -> None:
    path, cols = imu_csv
    assert main(["allan", path, "--rate", str(RATE), "--data", "rate", "--column", "gy"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("oadev of gy (rate data, 20000 samples at 50 Hz)")
    first = out.splitlines()[2].split()
    expected = allan(cols["gy"], RATE, data="rate")
    assert float(first[0]) == pytest.approx(expected.taus[0])
    assert float(first[1]) == pytest.approx(expected.deviation[0], rel=1e-4)
    assert first[4] == "WFM"


def test_allan_json(capsys, imu_csv) -> None:
    path, cols = imu_csv
    argv = ["allan", path, "--rate", "50", "--data", "rate", "--kind", "hdev", "--format", "json"]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["column"] == "gx" and d["kind"] == "hdev"
    expected = allan(cols["gx"], RATE, data="rate", kind="hdev")
    np.testing.assert_allclose(d["deviation"], expected.deviation, rtol=1e-12)


def test_imu_table_json_and_kalibr(capsys, imu_csv, tmp_path) -> None:
    path, _ = imu_csv
    out_yaml = tmp_path / "imu.yaml"
    argv = [
        "imu",
        path,
        "--rate",
        "50",
        "--gyro",
        "gx",
        "gy",
        "--accel",
        "ax",
        "--kalibr",
        str(out_yaml),
        "--inflation",
        "4",
        "--format",
        "json",
    ]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert list(d["columns"]) == ["gx", "gy", "ax"] and d["kalibr"] == str(out_yaml)
    gy_n = d["columns"]["gy"]["terms"]["random_walk"]["value"]
    assert gy_n == pytest.approx(3e-3, rel=0.05)
    imu = read_kalibr(out_yaml)
    assert imu.gyroscope_noise_density == pytest.approx(4 * gy_n, rel=1e-9)
    assert imu.update_rate == 50.0
    assert main(["imu", path, "--rate", "50", "--columns", "ax"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("ax: 20000 samples at 50 Hz") and "random_walk" in out


def _error(capsys, argv: list[str]) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("noisevar: error: ")
    return lines[0]


@pytest.mark.parametrize(
    "extra, message",
    [
        ([], "give the sample rate with --rate"),
        (["--rate", "0"], "--rate must be a positive"),
        (["--rate", "-5"], "--rate must be a positive"),
        (["--rate", "fast"], "invalid float value"),
    ],
)
@pytest.mark.parametrize("command", ["allan", "imu"])
def test_bad_rate(capsys, imu_csv, command: str, extra: list[str], message: str) -> None:
    assert message in _error(capsys, [command, imu_csv[0], *extra])


def test_too_short_a_record(capsys, tmp_path) -> None:
    path = tmp_path / "short.csv"
    path.write_text("z\n1\n2\n3\n")
    assert "too short" in _error(capsys, ["allan", str(path), "--rate", "1", "--data", "phase"])
    assert "too short" in _error(capsys, ["imu", str(path), "--rate", "1"])


def test_kalibr_needs_both_sensors(capsys, imu_csv, tmp_path) -> None:
    argv = ["imu", imu_csv[0], "--rate", "50", "--gyro", "gx", "--kalibr", str(tmp_path / "a")]
    assert "--accel" in _error(capsys, argv)
    assert not (tmp_path / "a").exists()


def test_imu_model_auto_table_and_json(capsys, imu_csv) -> None:
    path, _ = imu_csv
    assert main(["imu", path, "--rate", "50", "--columns", "gx", "--model", "auto"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("gx: model WN+RW at 50 Hz")
    assert "<- chosen" in out and "WVIC" in out and "K_eq" in out
    argv = ["imu", path, "--rate", "50", "--columns", "gx", "gy", "--model", "WN,WN+RW"]
    assert main([*argv, "--format", "json", "--robust"]) == 0
    d = json.loads(capsys.readouterr().out)["columns"]
    assert set(d) == {"gx", "gy"} and d["gy"]["robust"]
    assert [r["model"] for r in d["gx"]["table"]] == ["WN", "WN+RW"]
    assert "Unknown process" in _error(capsys, [*argv[:-1], "WN+ZZ"])
    assert "--kalibr" in _error(capsys, [*argv, "--gyro", "gx", "--kalibr", "x.yaml"])
