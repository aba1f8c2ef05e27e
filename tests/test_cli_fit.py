"""``noisevar fit``: table and JSON output, --save-config then --config, bad input exits 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main


@pytest.fixture(scope="module")
def track_csv(tmp_path_factory):
    rng = np.random.default_rng(4)
    n, T = 3000, 0.1
    v = np.cumsum(rng.normal(0, 0.3, n))
    x = np.cumsum(v) * T + rng.normal(0, 1.0, n)
    path = tmp_path_factory.mktemp("fit") / "track.csv"
    np.savetxt(
        path, np.column_stack([np.arange(n) * T, x]), delimiter=",", header="t,pos", comments=""
    )
    return str(path)


def test_table(track_csv, capsys):
    assert main(["fit", track_csv, "--column", "pos", "--model", "cv", "--rate", "10"]) == 0
    out = capsys.readouterr().out
    assert "model     cv   method mle" in out and "NIS mean" in out and "white" in out
    assert "gain      level " in out and ", rate " in out  # every gain named (issue 28 §8)
    assert "Ljung-Box p " in out


def test_json_then_config(track_csv, tmp_path, capsys):
    cfg = tmp_path / "tuned.json"
    args = ["fit", track_csv, "--column", "pos", "--rate", "10", "--format", "json"]
    assert main([*args, "--save-config", str(cfg)]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert fitted["model"] == "cv" and 0.5 < fitted["r"] < 2.0
    saved = json.loads(cfg.read_text())
    assert saved["kalman"]["q"] == fitted["q"]
    again = ["fit", track_csv, "--column", "pos", "--config", str(cfg), "--format", "json"]
    assert main(again) == 0
    applied = json.loads(capsys.readouterr().out)
    assert applied["method"] == "given"
    assert applied["q"] == fitted["q"] and applied["nis_mean"] == pytest.approx(fitted["nis_mean"])


@pytest.mark.parametrize(
    "extra,match",
    [
        (["--rate", "0"], "positive"),
        (["--rate", "-3"], "positive"),
        (["--rate", "10", "--model", "jerk"], "invalid choice"),
        (["--rate", "10", "--column", "nope"], "nope"),
    ],
)
def test_bad_input_exits_2_with_one_line(track_csv, capsys, extra, match):
    assert main(["fit", track_csv, *extra]) == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1


def test_rate_from_the_time_column_else_one_line_error(track_csv, tmp_path, capsys):
    assert main(["fit", track_csv, "--column", "pos", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["rate"] == pytest.approx(10.0)
    bare = tmp_path / "bare.csv"
    np.savetxt(bare, np.random.default_rng(0).normal(size=200))
    assert main(["fit", str(bare)]) == 2
    err = capsys.readouterr().err
    assert "give the sample rate with --rate HZ" in err and err.count("\n") == 1


def test_too_short_and_bad_config(tmp_path, capsys):
    short = tmp_path / "short.csv"
    np.savetxt(short, np.arange(12.0))
    assert main(["fit", str(short), "--rate", "1", "--model", "ca"]) == 2
    assert "needs at least" in capsys.readouterr().err
    bad = tmp_path / "bad.json"
    bad.write_text('{"method": "auto", "kalman": {"model": "cv", "q": -1, "r": 1}}')
    assert main(["fit", str(short), "--config", str(bad)]) == 2
    assert "positive" in capsys.readouterr().err


def test_the_json_units_of_q_and_r_are_the_data_s(tmp_path, capsys):
    """`noisevar fit --format json` said r in u² beside `unit: nT` (real_audit10); the table
    said nT²."""
    rng = np.random.default_rng(0)
    z = np.cumsum(np.cumsum(rng.normal(0, 0.01, 3000))) + rng.normal(0, 1, 3000)
    path = tmp_path / "mag.csv"
    rows = "\n".join(f"{0.1 * k:.1f},{v:.6f}" for k, v in enumerate(z))
    path.write_text("time [s],x [nT]\n" + rows + "\n")
    assert main(["fit", str(path), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["unit"] == "nT" and out["units"]["r"] == "nT²"
    assert out["units"]["q"].startswith("nT²/s^3")


def test_the_fits_record_r_is_estimates_on_the_files_times(tmp_path, capsys) -> None:
    # the record's answer beside r is `noisevar estimate`'s, which reads the time column (a
    # gap splits the record): it was estimate(z) without times (real_audit11's GENEActiv x:
    # 0.03569 against estimate's 0.03589)
    rng = np.random.default_rng(12)
    n = 1200
    t = np.arange(n) * 0.1
    t[n // 2 :] += 600.0  # a 10-minute gap
    z = np.cumsum(rng.normal(0, 0.05, n)) + rng.normal(0, 1, n)
    z[n // 2 :] += 40.0  # the level moved during the gap
    path = tmp_path / "gap.csv"
    rows = (f"{a:.1f},{b:.6f}" for a, b in zip(t, z, strict=True))
    path.write_text("t,x\n" + "\n".join(rows) + "\n")
    assert main(["estimate", str(path), "--column", "x", "--format", "json"]) == 0
    said = json.loads(capsys.readouterr().out)
    assert main(["fit", str(path), "--column", "x", "--format", "json"]) == 0
    fit = json.loads(capsys.readouterr().out)
    assert fit["record"]["variance"] == pytest.approx(said["variance"], rel=1e-12)
