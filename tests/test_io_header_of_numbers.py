"""A headerless table whose first row is a header written in numbers (UO SRML's day files)."""

from __future__ import annotations

import numpy as np

import noisevar
from noisevar.io import channel_record, load_table


def _srml_like(path, header: str | None, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    n = 1440
    minute = np.arange(n)
    hhmm = (minute // 60) * 100 + minute % 60 + 1
    sun = np.clip(300 * np.sin(np.pi * (minute - 420) / 600), 0, None)
    ghi = np.round(sun + rng.normal(0, 1.5, n) * (sun > 0), 0)
    temp = np.round(5 + 4 * np.sin(2 * np.pi * minute / n) + rng.normal(0, 0.2, n), 1)
    body = "\n".join(
        f"1\t{h}\t{g:g}\t12\t{t:g}\t12" for h, g, t in zip(hhmm, ghi, temp, strict=True)
    )
    path.write_text((header + "\n" if header else "") + body + "\n")


def test_a_header_of_numbers_is_left_out_with_a_note(tmp_path) -> None:
    with_head, without = tmp_path / "srml.txt", tmp_path / "plain.txt"
    _srml_like(with_head, "94255\t2018\t1000\t0\t7008\t0")
    _srml_like(without, None)
    t, plain = load_table(with_head), load_table(without)
    assert any("a header of numbers" in n for n in t.notes)
    for c in ("col2", "col4"):
        a = noisevar.estimate(channel_record(t, c)[0])
        b = noisevar.estimate(channel_record(plain, c)[0])
        # was: the row read as data, a glitch holding most of R (SRML's col4: 3,519 for 0.04)
        assert a.variance == b.variance


def test_a_first_row_near_the_rest_stays(tmp_path) -> None:
    path = tmp_path / "plain.txt"
    _srml_like(path, None)
    t = load_table(path)
    assert not any("header of numbers" in n for n in t.notes)
    assert channel_record(t, "col2")[0].size == 1440


def test_a_start_up_value_in_one_column_stays(tmp_path) -> None:
    rng = np.random.default_rng(1)
    z = rng.normal(size=(500, 3))
    z[0, 1] = 80.0  # one column's glitch: the policy counts it in R (not a header)
    path = tmp_path / "imu.csv"
    np.savetxt(path, np.c_[np.arange(500) * 0.01, z], delimiter=",")
    t = load_table(path)
    assert not any("header of numbers" in n for n in t.notes)
    assert channel_record(t, "col2")[0][0] == 80.0
