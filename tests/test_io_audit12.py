"""Files of the twelfth real-record audit (benchmarks/real_audit12.py) as users have them:
brightwind's met-mast records. Its day-first dates (``09/01/2016 23:50``) were read
month-first, a 29-day gap that is not there; its Campbell Scientific TOA5 export was refused
for its width (the environment line read as the header); its Windographer export was
refused saying only that the rows' widths differ."""

import numpy as np
import pytest

from noisevar import NoisevarError
from noisevar.cli import main
from noisevar.io import channel_record, load_table
from noisevar.io.text_times import parse_time_strings


def _speeds(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.round(8.0 + np.cumsum(rng.normal(0.0, 0.1, n)) + rng.normal(0.0, 0.2, n), 3)


def test_ambiguous_dates_are_read_in_the_order_that_steps_evenly():
    t = parse_time_strings(["09/01/2016 23:40", "09/01/2016 23:50", "10/01/2016 00:00",
                            "10/01/2016 00:10"])  # fmt: skip
    np.testing.assert_allclose(t, [0.0, 600.0, 1200.0, 1800.0])
    t = parse_time_strings(["01/09/2016 23:50", "01/10/2016 00:00", "01/10/2016 00:10"])
    np.testing.assert_allclose(t, [0.0, 600.0, 1200.0])


def test_a_day_first_met_mast_file_has_no_gap(tmp_path):
    z = _speeds(300, 1)
    stamps = np.datetime64("2016-01-09T15:30") + np.arange(300) * np.timedelta64(10, "m")
    rows = [f"{s.astype(object):%d/%m/%Y %H:%M},{v}" for s, v in zip(stamps, z, strict=True)]
    path = tmp_path / "mast.csv"
    path.write_text("Timestamp,Spd80mN\n" + "\n".join(rows) + "\n")
    table = load_table(path)
    _, t = channel_record(table, "Spd80mN")
    assert table.sample_period == pytest.approx(600.0)
    assert np.all(np.diff(t) == 600.0)


def _toa5(n: int, seed: int) -> tuple[str, np.ndarray]:
    """A Campbell Scientific TOA5 export: environment, names, units, processing, rows."""
    z = _speeds(n, seed)
    stamps = np.datetime64("2016-01-09T15:30") + np.arange(n) * np.timedelta64(10, "m")
    head = ['"TOA5","some_site","CR1000","E7000","CR1000.Std.22","CPU:mast.CR1","123","mast"',
            '"TIMESTAMP","RECORD","Site","Spd80mN","P2m"',
            '"TS","RN","","Metres/Second","Millibars"',
            '"","","Smp","Avg","Avg"']  # fmt: skip
    rows = [f'"{s.astype(object):%Y-%m-%d %H:%M:%S}",{i},"mast",{v},{935 + i % 3}'
            for i, (s, v) in enumerate(zip(stamps, z, strict=True))]  # fmt: skip
    return "\r\n".join(head + rows) + "\r\n", z


def test_a_toa5_file_is_read_with_its_units(tmp_path):
    text, z = _toa5(400, 2)
    path = tmp_path / "CR1000_Table1.dat"
    path.write_text(text)
    table = load_table(path)
    assert table.time_column == "TIMESTAMP" and table.sample_period == pytest.approx(600.0)
    np.testing.assert_allclose(channel_record(table, "Spd80mN")[0], z)
    assert table.units["Spd80mN"] == "metres/second" and table.units["P2m"] == "millibars"
    assert "RECORD" not in table.units  # TOA5's record-number mark, no unit
    assert table.first_signal == "Spd80mN"


def test_the_cli_reads_a_toa5_file(tmp_path, capsys):
    text, _ = _toa5(400, 3)
    path = tmp_path / "mast.csv"
    path.write_text(text)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    out = capsys.readouterr().out
    assert '"column": "Spd80mN"' in out and '"unit": "metres/second"' in out


def test_a_windographer_export_is_refused_saying_to_delete_its_metadata(tmp_path, capsys):
    z = _speeds(100, 4)
    meta = ["Created 10-05-2019 14:36 by Windographer 4.1.14", "", "Latitude = N 0.000000",
            "Longitude = E 0.000000", "Elevation = 0 m", "Calm threshold = 0 m/s", "",
            "Included flags: <Unflagged data>", "Excluded flags: Low quality", "",
            "Time stamps indicate the beginning of the time step.", ""]  # fmt: skip
    rows = [f"2016-01-{9 + i // 144:02d} {i % 144 // 6:02d}:{i % 6 * 10:02d}:00\t{v}\t{v + 0.1}"
            for i, v in enumerate(z)]  # fmt: skip
    path = tmp_path / "windographer.txt"
    path.write_text("\n".join([*meta, "Date/Time\tSpd80mN\tSpd80mS", *rows]) + "\n")
    with pytest.raises(NoisevarError, match="skiprows=12"):
        load_table(path)
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "delete those lines" in err and "line 13" in err


def _vane(n: int, seed: int) -> np.ndarray:
    """A wind vane around north (0/360), read from 0 to 360 on a 0.1 degree grid."""
    rng = np.random.default_rng(seed)
    angle = np.cumsum(rng.normal(0.0, 3.0, n)) + rng.normal(0.0, 2.0, n)
    return np.round(np.mod(angle, 360.0), 1)


def test_a_wrapping_wind_vane_is_noted(tmp_path, capsys):
    z = _vane(2000, 5)
    assert np.sum(np.abs(np.diff(z)) > 180) >= 3
    path = tmp_path / "vane.csv"
    path.write_text("Dir78mS,T2m\n" + "\n".join(f"{v},{5 + i % 7 * 0.01}" for i, v in
                                                 enumerate(z)) + "\n")  # fmt: skip
    table = load_table(path)
    assert any("'Dir78mS' wraps" in n and "period=360" in n for n in table.notes)
    assert not any("'T2m' wraps" in n for n in table.notes)
    assert main(["estimate", str(path), "--column", "Dir78mS", "--format", "json"]) == 0
    assert "numpy.unwrap" in capsys.readouterr().out
    rng = np.random.default_rng(6)  # an angle that swings but does not wrap: no note
    swing = np.round(180 + 60 * np.sin(np.linspace(0, 20, 2000)) + rng.normal(0, 2, 2000), 1)
    path.write_text("Dir\n" + "\n".join(map(str, swing)) + "\n")
    assert not any("wraps" in n for n in load_table(path).notes)
    # a 0/5 V logic channel steps by over half a radian turn, but is no angle: no note
    logic = np.repeat(np.tile([0.0, 5.0], 20), 10) + rng.normal(0, 0.01, 400)
    path.write_text("Trig\n" + "\n".join(map(str, logic)) + "\n")
    assert not any("wraps" in n for n in load_table(path).notes)
