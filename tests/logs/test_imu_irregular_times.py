"""``noisevar imu`` on a topic whose logger drops samples (the committed PX4 log's
``vehicle_angular_velocity``: 783 of 1811 steps are not the median one): the table prints
every note of the fit (it printed only the regime warning, so "N is not told from 0" and
the terms left out never reached a reader of the table), and one says how the samples
were placed: on their base period when the steps are whole periods (samples dropped), as
uniform at the median rate otherwise."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from noisevar.cli import main

LOG = str(Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg")


def test_imu_table_says_the_dropped_samples_were_placed_on_their_period(capsys):
    argv = ["imu", LOG, "--topic", "vehicle_angular_velocity", "--gyro", "xyz[0]"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "848 of 2660 samples dropped (the times are whole multiples of 0.002444 s)" in out
    assert "steps of the times are not the median one" not in out
    assert "note: left out, the data do not support them" in out
    # the same table from ``noisevar allan``, in the record's seconds
    assert main(["allan", LOG, "--topic", "vehicle_angular_velocity", "--column", "xyz[0]"]) == 0
    out = capsys.readouterr().out
    assert "samples dropped" in out and "1812 samples at 409.165 Hz" in out
    # --rate: the samples taken as uniform at it, and said
    argv += ["--rate", "409"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "of 2660 samples dropped" not in out and "steps of the times are not the median" in out


def test_uniform_times_add_no_note(capsys, tmp_path):
    rng = np.random.default_rng(0)
    t = np.arange(4000) / 100.0
    path = tmp_path / "gyro.csv"
    np.savetxt(path, np.c_[t, rng.normal(0, 0.01, t.size)], delimiter=",", header="time,gx",
               comments="")  # fmt: skip
    assert main(["imu", str(path), "--gyro", "gx"]) == 0
    out = capsys.readouterr().out
    assert "at 100 Hz" in out and "steps of the times are not the median one" not in out


def test_steps_that_are_not_whole_periods_are_taken_as_uniform_and_said(capsys, tmp_path):
    rng = np.random.default_rng(1)
    t = np.cumsum(np.tile([0.01, 0.01, 0.025], 1000))  # 2.5 periods: not dropped samples
    path = tmp_path / "gyro.csv"
    np.savetxt(path, np.c_[t, rng.normal(0, 0.01, t.size)], delimiter=",", header="time,gx",
               comments="")  # fmt: skip
    assert main(["imu", str(path), "--gyro", "gx"]) == 0
    out = capsys.readouterr().out
    assert "steps of the times are not the median one" in out and "of 3000 samples" not in out
    assert main(["allan", str(path), "--column", "gx"]) == 0
    assert "steps of the times are not the median one" in capsys.readouterr().out
