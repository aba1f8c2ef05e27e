"""Time columns without a stated unit (real_audit19: stingray's RXTE and Kepler light curves).

Before: a headerless x,y file's times were a channel and its period read 1 s (0.125 s
written); a ``time (d)`` or ``BJD`` column was read in seconds; a ``times`` column whose
unit nothing states was read in seconds without a word."""

from __future__ import annotations

import numpy as np

from noisevar.io import load_table


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return load_table(str(p))


def _xy(t, y):
    return "".join(f"{a:.18e} {b:.18e}\n" for a, b in zip(t, y, strict=True))


def test_a_headerless_x_y_files_x_is_its_times_in_seconds_said(tmp_path):
    rng = np.random.default_rng(0)
    t = 1.109110400703125e8 + 0.125 * np.arange(400)
    table = _write(tmp_path, "lc.txt", _xy(t, 4000 + 60 * rng.normal(size=t.size)))
    assert table.time_column == "col0" and table.sample_period == 0.125
    assert any("no unit stated" in n and "col0" in n for n in table.notes), table.notes


def test_a_counter_a_ramp_or_two_increasing_columns_are_not_times(tmp_path):
    rng = np.random.default_rng(1)
    n = np.arange(300.0)
    counter = _write(tmp_path, "c.txt", _xy(n, rng.normal(size=n.size)))
    ramp = _write(
        tmp_path, "r.txt", _xy(0.01 * n + rng.normal(size=n.size), rng.normal(size=n.size))
    )
    two = _write(tmp_path, "two.txt", _xy(0.5 * n, 3.0 * n + 7))
    assert counter.time_column is None and ramp.time_column is None and two.time_column is None


def test_a_time_column_in_days_is_read_in_days(tmp_path):
    t = (120.5590984 + 0.0204338 * np.arange(200)).tolist()
    y = np.random.default_rng(2).normal(size=len(t)).tolist()
    for head in ("time (d)", "BJD", "BTJD", "t [days]"):
        table = _write(
            tmp_path,
            "k.csv",
            f"{head},flux\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t, y, strict=True)),
        )
        assert table.time_column == head, head
        assert abs(table.sample_period / (0.0204338 * 86400) - 1) < 1e-6, (
            head,
            table.sample_period,
        )


def test_a_time_column_with_no_unit_says_seconds_and_one_that_states_it_does_not(tmp_path):
    body = "".join(f"{0.01 * i},{np.sin(i)}\n" for i in range(200))
    unstated = _write(tmp_path, "a.csv", "times,flux\n" + body)
    stated = _write(tmp_path, "b.csv", "time_s,flux\n" + body)
    assert any("no unit stated" in n for n in unstated.notes), unstated.notes
    assert not any("no unit stated" in n for n in stated.notes), stated.notes
    assert unstated.sample_period == stated.sample_period == 0.01


def test_a_dew_point_column_t_d_is_not_read_as_days(tmp_path):
    body = "".join(f"{i},{5 + 0.1 * np.sin(i)}\n" for i in range(100))
    table = _write(tmp_path, "w.csv", "time,t_d\n" + body)
    assert table.time_column == "time" and "t_d" in table.columns
