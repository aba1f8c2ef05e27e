"""``--regimes {all,still}`` on ``noisevar fit``, ``imu`` and ``allan`` (issue 26, item 5)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.estimators.regimes import longest_still_stretch
from noisevar.noise_model.kalibr import read_kalibr

#: the whole motion record's r interval reaches past a float (an infinite upper bound)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")

SIGMA = 0.15
RATE = 100.0


@pytest.fixture(scope="module")
def still_then_motion(tmp_path_factory) -> tuple[str, np.ndarray]:
    """Two columns of white noise (std 0.15), still for 2000 samples, then a large oscillation."""
    rng = np.random.default_rng(1)
    n, still = 6000, 2000
    k = np.arange(still, n)
    cols = []
    for _ in range(2):
        z = SIGMA * rng.standard_normal(n)
        z[still:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
        cols.append(z)
    data = np.column_stack(cols)
    path = tmp_path_factory.mktemp("regimes") / "imu.csv"
    np.savetxt(path, data, delimiter=",", header="g,a", comments="")
    return str(path), data


def _one_error_line(capsys, argv: list[str]) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and lines[0].startswith("noisevar: error: ")
    return lines[0]


def test_fit_on_the_still_stretch(still_then_motion, capsys) -> None:
    path, data = still_then_motion
    base = ["fit", path, "--column", "g", "--model", "rw", "--rate", "100"]
    assert main([*base, "--regimes", "still"]) == 0
    out = capsys.readouterr().out
    s = longest_still_stretch(data[:, 0])
    assert f"samples {s.stop - s.start}   regimes still" in out
    assert f"note      {s.note}" in out
    assert main([*base, "--regimes", "still", "--format", "json"]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert fitted["regimes"] == "still" and fitted["r"] == pytest.approx(SIGMA**2, rel=0.15)
    assert main([*base, "--format", "json"]) == 0
    whole = json.loads(capsys.readouterr().out)
    assert whole["regimes"] == "all" and whole["r"] > 10 * SIGMA**2


def test_fit_saves_the_choice_in_its_config(still_then_motion, tmp_path, capsys) -> None:
    path, _ = still_then_motion
    cfg = tmp_path / "tuned.json"
    argv = ["fit", path, "--column", "g", "--rate", "100", "--regimes", "still"]
    assert main([*argv, "--save-config", str(cfg)]) == 0
    capsys.readouterr()
    saved = json.loads(cfg.read_text())["kalman"]
    assert saved["regimes"] == "still" and saved["notes"][0].startswith("regimes='still'")
    again = ["fit", path, "--column", "g", "--config", str(cfg), "--regimes", "still"]
    assert "drop it with --config" in _one_error_line(capsys, again)


def test_imu_and_its_kalibr_file(still_then_motion, tmp_path, capsys) -> None:
    path, data = still_then_motion
    out_yaml = tmp_path / "imu.yaml"
    argv = ["imu", path, "--rate", "100", "--gyro", "g", "--accel", "a", "--regimes", "still"]
    assert main([*argv, "--kalibr", str(out_yaml)]) == 0
    out = capsys.readouterr().out
    assert out.count("note (every column): regimes='still'") == 1  # both columns' stretch
    imu = read_kalibr(out_yaml)
    assert imu.regimes == "still" and "# regimes: still" in out_yaml.read_text()
    assert imu.gyroscope_noise_density == pytest.approx(SIGMA / np.sqrt(RATE), rel=0.1)
    # K from the composite fit of the same still stretch, as with --regimes all
    assert any(n.startswith("random walks from: the composite fit") for n in imu.notes)
    assert main([*argv, "--format", "json"]) == 0
    cols = json.loads(capsys.readouterr().out)["columns"]
    assert cols["g"]["regimes"] == "still" and cols["a"]["regimes"] == "still"


def test_allan_on_the_still_stretch(still_then_motion, capsys) -> None:
    path, data = still_then_motion
    argv = ["allan", path, "--rate", "100", "--data", "rate", "--column", "a"]
    assert main([*argv, "--regimes", "still"]) == 0
    out = capsys.readouterr().out
    s = longest_still_stretch(data[:, 1])
    assert f"{s.stop - s.start} samples" in out.splitlines()[0]
    assert out.splitlines()[1] == f"note: {s.note}"
    assert main([*argv, "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["regimes"] == "all"


@pytest.mark.parametrize(
    "argv",
    [
        ["fit", "{path}", "--rate", "100"],
        ["imu", "{path}", "--rate", "100"],
        ["allan", "{path}", "--rate", "100"],
    ],
    ids=["fit", "imu", "allan"],
)
@pytest.mark.parametrize("bad", ["moving", "STILL", ""])
def test_a_bad_choice_exits_2_with_one_line(still_then_motion, capsys, argv, bad) -> None:
    argv = [a.format(path=still_then_motion[0]) for a in argv]
    line = _one_error_line(capsys, [*argv, "--regimes", bad])
    assert "--regimes" in line and "invalid choice" in line


def test_still_too_short_exits_2_with_the_rule(tmp_path, capsys) -> None:
    """A still start too short for R's method: ``--regimes still`` says so (issue 26)."""
    from noisevar import estimate
    from noisevar.estimators.regimes import still_gap

    rng = np.random.default_rng(0)
    t = np.arange(500)
    cols = []
    for _ in range(2):  # white noise (std 0.03) still for 64 samples, then motion
        z = 0.03 * rng.normal(size=500)
        z[64:] += 2.0 * np.sin(2 * np.pi * t[64:] / 25.0) + 0.3 * rng.normal(size=436)
        cols.append(z)
    path = tmp_path / "short.csv"
    np.savetxt(path, np.column_stack(cols), delimiter=",", header="g,a", comments="")
    est = estimate(cols[0])
    gap = still_gap(est.diagnostics, est.variance, est.still)
    assert gap is not None  # the case reproduced
    for argv in (
        ["imu", str(path), "--rate", "100", "--gyro", "g", "--accel", "a"],
        ["fit", str(path), "--column", "g", "--rate", "100"],
    ):
        line = _one_error_line(capsys, [*argv, "--regimes", "still"])
        assert "record the sensor still for longer" in line, line
        assert main(argv) == 0  # regimes all: the whole record
        capsys.readouterr()
