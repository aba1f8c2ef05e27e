"""``noisevar imu`` on a topic whose logger drops samples (the committed PX4 log's
``vehicle_angular_velocity``: 783 of 1811 steps are not the median one): the table prints
every note of the fit (it printed only the regime warning, so "N is not told from 0" and
the terms left out never reached a reader of the table), and one says that the Allan
variance took the samples as uniform at the topic's median rate."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from noisevar.cli import main

LOG = str(Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg")


def test_imu_table_says_the_times_are_not_uniform(capsys):
    argv = ["imu", LOG, "--topic", "vehicle_angular_velocity", "--gyro", "xyz[0]"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "steps of the times are not the median one" in out
    assert "note: left out, the data do not support them" in out


def test_uniform_times_add_no_note(capsys, tmp_path):
    rng = np.random.default_rng(0)
    t = np.arange(4000) / 100.0
    path = tmp_path / "gyro.csv"
    np.savetxt(path, np.c_[t, rng.normal(0, 0.01, t.size)], delimiter=",", header="time,gx",
               comments="")  # fmt: skip
    assert main(["imu", str(path), "--gyro", "gx"]) == 0
    out = capsys.readouterr().out
    assert "at 100 Hz" in out and "steps of the times are not the median one" not in out
