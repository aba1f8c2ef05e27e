"""The unit of a record's times, as the user states it (``load_table(time_unit=)``,
``--time-unit``, a config's ``time_unit``): real_audit19's Kepler ``koi2133.csv`` (``times``
in days, no unit stated) read a period of 0.0204 s, and nothing could say "days".

Before: ``load_table`` took no ``time_unit`` and the CLI no ``--time-unit``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table
from noisevar.io.table import NO_UNIT_NOTE

#: Kepler's long cadence, in days (29.4 min), and in seconds
STEP_D = 0.0204338
STEP_S = STEP_D * 86400.0


def _rows(t, y, sep=","):
    return "".join(f"{a!r}{sep}{b!r}\n" for a, b in zip(t, y, strict=True))


def _light_curve(tmp_path, head="times,flux\n", name="lc.csv", n=300):
    rng = np.random.default_rng(0)
    t = (120.5590984 + STEP_D * np.arange(n)).tolist()
    p = tmp_path / name
    p.write_text(head + _rows(t, (1 + 1e-4 * rng.normal(size=n)).tolist()))
    return p


def test_days_stated_on_a_named_column_without_a_unit(tmp_path):
    p = _light_curve(tmp_path)
    table = load_table(p, time_unit="d")
    assert abs(table.sample_period / STEP_S - 1) < 1e-6, table.sample_period
    assert abs(1 / table.sample_period - 5.664e-4) < 1e-6
    assert any("in d (the time unit given)" in n for n in table.notes), table.notes
    assert not any("no unit stated" in n for n in table.notes), table.notes
    # any unit of time pint reads: minutes are 1/1440 of a day
    minutes = load_table(p, time_unit="min").sample_period
    assert abs(minutes * 1440 / table.sample_period - 1) < 1e-6  # (periods cut to the digits)


def test_a_time_unit_stated_on_a_headerless_x_y_file(tmp_path):
    rng = np.random.default_rng(1)
    t = (5000 + 125 * np.arange(400)).tolist()  # milliseconds
    p = tmp_path / "xy.txt"
    p.write_text(_rows(t, rng.normal(size=400).tolist(), " "))
    assert load_table(p).sample_period == 125.0  # read as seconds, said
    table = load_table(p, time_unit="ms")
    assert table.time_column == "col0" and table.sample_period == 0.125


def test_a_name_that_states_another_unit_is_refused_the_same_is_read(tmp_path):
    body = _rows([0.5 * i for i in range(200)], [float(np.sin(i)) for i in range(200)])
    for head, said, other in (("time_ms", "ms", "s"), ("BJD", "d", "h"), ("seconds", "s", "d")):
        p = tmp_path / f"{said}.csv"
        p.write_text(f"{head},x\n" + body)
        with pytest.raises(NoisevarError, match=f"states its unit, {said} \\(its name\\)"):
            load_table(p, time_unit=other)
        assert load_table(p, time_unit=said).sample_period == load_table(p).sample_period


def test_date_times_state_their_own_unit(tmp_path):
    p = tmp_path / "dates.csv"
    p.write_text("time,x\n" + "".join(f"2024-01-01T00:00:{i:02d},{i % 3}\n" for i in range(40)))
    with pytest.raises(NoisevarError, match="date-times"):
        load_table(p, time_unit="d")
    assert load_table(p, time_unit="s").sample_period == 1.0


@pytest.mark.parametrize("bad", ["garbage", "m", "m/s", "-1 s", "furlong", "1/s"])
def test_garbage_or_a_unit_not_of_time_is_refused_in_one_line(tmp_path, bad, capsys):
    p = _light_curve(tmp_path)
    with pytest.raises(NoisevarError, match="is not a unit of time: give one pint reads, e.g. s"):
        load_table(p, time_unit=bad)
    assert main(["estimate", str(p), "--time-unit", bad]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not a unit of time" in err, err


def test_the_note_on_an_unstated_unit_names_the_option(tmp_path):
    table = load_table(_light_curve(tmp_path))
    assert "--time-unit d" in NO_UNIT_NOTE and "Time column's unit" in NO_UNIT_NOTE
    assert any("--time-unit d (Signal page: Time column's unit)" in n for n in table.notes)


def test_a_file_without_a_time_column_says_the_unit_is_not_used(tmp_path):
    p = tmp_path / "x.csv"
    p.write_text("x\n" + "".join(f"{float(np.sin(i))!r}\n" for i in range(100)))
    assert any("not used" in n for n in load_table(p, time_unit="d").notes)


def test_an_hdf5_step_is_the_period_only_when_its_unit_is_stated(tmp_path):
    h5py = pytest.importorskip("h5py")
    p = tmp_path / "strain.h5"
    with h5py.File(p, "w") as f:
        ds = f.create_dataset("strain", data=np.random.default_rng(2).normal(size=4096))
        ds.attrs["dx"] = 1.0 / 4096
    plain = load_table(p)
    assert plain.sample_period is None
    assert any("--time-unit s" in n for n in plain.notes), plain.notes
    told = load_table(p, time_unit="s")
    assert told.sample_period == 1.0 / 4096
    assert any("read in s (the time unit given)" in n for n in told.notes), told.notes
    assert load_table(p, time_unit="ms").sample_period == 1e-3 / 4096


def test_cli_commands_and_their_config_read_the_unit(tmp_path, capsys):
    p = _light_curve(tmp_path, n=2000)
    assert main(["allan", str(p), "--time-unit", "d", "--format", "json"]) == 0
    rate = json.loads(capsys.readouterr().out)["rate"]
    assert abs(rate - 1 / STEP_S) < 1e-9
    cfg = tmp_path / "cfg.json"
    cfg.write_text(json.dumps({"method": "auto", "time_unit": "d"}))
    assert main(["estimate", str(p), "--config", str(cfg), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert any("in d (the time unit given)" in n for n in out["notes"]), out["notes"]
    cfg.write_text(json.dumps({"method": "auto", "time_unit": "parsec"}))
    assert main(["estimate", str(p), "--config", str(cfg)]) == 2
    assert "not a unit of time" in capsys.readouterr().err


def test_batch_rows_take_the_unit(tmp_path):
    from noisevar.batch import batch

    p = _light_curve(tmp_path, n=2000)
    days = batch([str(p)], time_unit="d", progress=False)
    plain = batch([str(p)], progress=False)
    assert abs(days["sample_rate_hz"].iloc[0] * STEP_S - 1) < 1e-6
    assert days["variance"].iloc[0] == plain["variance"].iloc[0]  # R is per sample


def test_a_tuned_filter_config_carries_the_unit_and_fit_applies_it(tmp_path, capsys):
    p = _light_curve(tmp_path, n=2000)
    cfg = tmp_path / "tuned.json"
    args = ["fit", str(p), "--model", "rw", "--format", "json"]
    assert main([*args, "--time-unit", "d", "--save-config", str(cfg)]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert json.loads(cfg.read_text())["time_unit"] == "d"
    assert main(["fit", str(p), "--config", str(cfg), "--format", "json"]) == 0  # its rate
    applied = json.loads(capsys.readouterr().out)
    assert applied["q"] == fitted["q"] and abs(applied["rate"] * STEP_S - 1) < 1e-6
