"""One record, one answer: a table with a time column (a gap, a declared unit) gets the same
estimate from ``noisevar estimate --column``, ``--columns``, ``noisevar batch``, Python and
the dashboard, each in the unit the file declares.

Before, only ``--column`` split the record at its gap (the others spliced it: another R),
and only ``allan``/``imu`` carried the file's unit (``estimate`` and ``batch`` said ``u``).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main

N, RATE, GAP = 3000, 100.0, 5.0


@pytest.fixture(scope="module")
def record(tmp_path_factory) -> tuple[str, np.ndarray, np.ndarray]:
    """A gyro and an accelerometer at 100 Hz, 5 s missing in the middle, where the motion
    changes (spliced, the gap is a jump)."""
    rng = np.random.default_rng(7)
    t = np.arange(N) / RATE
    t[N // 2 :] += GAP
    first = np.arange(N) < N // 2
    gyro = np.where(first, np.sin(t), 3 + np.cos(2 * t)) + rng.normal(0, 0.05, N)
    acc = 9.8 + 0.3 * np.sin(0.5 * t) + rng.normal(0, 0.02, N)
    path = tmp_path_factory.mktemp("one_answer") / "rec.csv"
    rows = "\n".join(f"{a:.4f},{b:.6f},{c:.6f}" for a, b, c in zip(t, gyro, acc, strict=True))
    path.write_text("time,gyro [rad/s],acc [m/s^2]\n" + rows + "\n")
    return str(path), t, gyro


def _json(capsys, *argv: str) -> dict:
    assert main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_every_command_line_path_splits_at_the_gap(capsys, record, tmp_path):
    path, t, gyro = record
    table = nv.io.load_table(path, "rec.csv")
    z = np.asarray(table.columns["gyro [rad/s]"], dtype=float)
    truth = nv.estimate(z, t=t).variance  # the record split at its gap
    assert truth != nv.estimate(z).variance  # spliced: another answer
    one = _json(capsys, "estimate", path, "--column", "gyro [rad/s]", "--format", "json")
    many = _json(capsys, "estimate", path, "--columns", "all", "--format", "json")
    out = tmp_path / "rows.csv"
    assert main(["batch", path, "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    rows = pd.read_csv(out).set_index("channel")
    assert one["variance"] == truth and one["unit"] == "rad/s"
    assert [(c["column"], c["unit"]) for c in many["channels"]] == [
        ("gyro [rad/s]", "rad/s"),
        ("acc [m/s^2]", "m/s^2"),
    ]
    assert many["channels"][0]["variance"] == truth
    assert rows.loc["gyro [rad/s]", "variance"] == truth
    assert rows.loc["acc [m/s^2]", "unit"] == "m/s^2"
    assert rows.loc["acc [m/s^2]", "variance"] == many["channels"][1]["variance"]


def test_the_dashboard_gives_the_command_lines_answer(capsys, record):
    from dashboard import cache
    from dashboard.sections.channels import _estimates
    from dashboard.state import make_signal

    path, t, _ = record
    table = nv.io.load_table(path, "rec.csv")
    one = _json(capsys, "estimate", path, "--column", "gyro [rad/s]", "--format", "json")
    sig = make_signal(table, "gyro [rad/s]", table.sample_period, "upload", None)
    assert np.array_equal(sig.times, table.time())
    assert cache.estimate(sig, "auto", {}).variance == one["variance"]
    assert cache.column_estimate(sig, "gyro [rad/s]").variance == one["variance"]
    est, names, errors = _estimates.__wrapped__("k", ("gyro [rad/s]", "acc [m/s^2]"), table)
    assert names == ["gyro [rad/s]", "acc [m/s^2]"] and not errors
    assert est[0].variance == one["variance"]
    rows = cache.fast_rows(sig, ["auto"], {})
    assert rows[0].estimate.variance == one["variance"]
    # another sample period set by the user: the samples are taken as uniform
    uniform = make_signal(table, "gyro [rad/s]", 0.02, "upload", None)
    assert uniform.times is None and uniform.digest != sig.digest


def test_columns_all_reports_a_channel_it_cannot_estimate(capsys, tmp_path):
    rng = np.random.default_rng(1)
    path = tmp_path / "flat.csv"
    z = np.cumsum(rng.normal(size=500)) * 0.01 + rng.normal(0, 0.1, 500)
    path.write_text("x,flag\n" + "\n".join(f"{v:.6f},1" for v in z) + "\n")
    data = _json(capsys, "estimate", str(path), "--columns", "all", "--format", "json")
    x, flag = data["channels"]
    assert x["variance"] == nv.estimate(np.loadtxt(path, delimiter=",", skiprows=1)[:, 0]).variance
    assert "constant" in flag["error"] and "variance" not in flag
    assert main(["estimate", str(path), "--columns", "flag"]) == 2  # nothing to estimate
    assert "constant" in capsys.readouterr().err


def test_imu_export_verdicts_split_at_the_gap(capsys, record, tmp_path):
    """``noisevar imu --export``'s files and report say the verdict of the record split at its
    gap (the answer every other path gives); before, they spliced it. The IEEE-952 fits
    still run on the spliced samples (an Allan variance needs one uniform record)."""
    path, t, gyro = record
    truth = nv.estimate(gyro, t=t).diagnostics.verdict
    assert truth != nv.estimate(gyro).diagnostics.verdict
    out = tmp_path / "exports"
    argv = ["imu", path, "--gyro", "gyro [rad/s]", "--accel", "acc [m/s^2]"]
    argv += ["--export", "px4", "--out", str(out), "--format", "json"]
    data = _json(capsys, *argv)
    assert data["model"]["verdicts"]["gyro [rad/s]"] == truth
    text = (out / "px4_ekf2.params").read_text(encoding="utf-8")
    assert "verdict, column gyro [rad/s]: " + truth.split(":")[0] in text
