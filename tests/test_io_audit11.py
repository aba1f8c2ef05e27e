"""Files of the eleventh real-record audit (benchmarks/real_audit11.py) as users have them:
a GENEActiv accelerometer's CSV export (gaitpy's demo file: NUL-padded text fields, a block
of metadata above a table with no header, milliseconds after a colon) was refused as "a
binary file"; sweat's TCX, GPX and FIT activities were refused blaming a cell, a row's field
count or NUL bytes, none saying what the file is or what to do."""

import numpy as np
import pytest

from noisevar import NoisevarError
from noisevar.cli import main
from noisevar.io import channel_record, load_table
from noisevar.io.text_times import parse_time_strings


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


_META = [
    "Device Type,GENEActiv           ",
    "Device Model,1.1                 ",
    "Measurement Frequency,50.0 Hz",
    "Subject Notes," + "\0" * 40,
    "Sensor type,MEMS accelerometer x-axis",
    "Resolution,0.0039              ",
    "Units,g                   ",
    "Config Notes," + "\0" * 40,
    "",
]


def _geneactiv(n: int, seed: int, header: bool = False) -> tuple[str, np.ndarray]:
    """A GENEActiv-like export: metadata (NUL-padded notes), then ``n`` rows at 50 Hz of a
    time stamp with its milliseconds after a colon and x (g, on the 0.0039 g grid)."""
    rng = np.random.default_rng(seed)
    x = np.round(rng.normal(0.0, 0.02, n) / 0.0039) * 0.0039
    rows = [f"2019-08-06 10:{25 + i // 3000:02d}:{i // 50 % 60:02d}:{i % 50 * 20:03d},{v:.4f},31.6"
            for i, v in enumerate(x)]  # fmt: skip
    lines = (["time,x,temperature"] if header else _META) + rows
    return "\r\n".join(lines) + "\r\n", x


def test_milliseconds_after_a_colon_are_read_in_a_date_time():
    t = parse_time_strings(["2019-08-06 10:25:50:000", "2019-08-06 10:25:50:020",
                            "2019-08-06 10:25:51:000"])  # fmt: skip
    np.testing.assert_allclose(t, [0.0, 0.02, 1.0])


def test_a_geneactiv_table_is_read_with_its_times(tmp_path):
    text, x = _geneactiv(600, 1, header=True)
    path = tmp_path / "geneactiv.csv"
    path.write_text(text)
    table = load_table(path)
    assert table.time_column == "time" and table.sample_period == pytest.approx(0.02)
    z, t = channel_record(table, "x")
    np.testing.assert_allclose(z, np.round(x, 4))
    assert t[-1] == pytest.approx(599 * 0.02)


def test_nul_padded_text_fields_are_not_a_binary_file(tmp_path):
    text, _x = _geneactiv(300, 2, header=True)
    path = tmp_path / "padded.csv"
    path.write_bytes(("Notes," + "\0" * 60 + "\r\n").encode() + text.encode())
    with pytest.raises(NoisevarError) as e:  # the notes line above the header: the block
        load_table(path)
    assert "binary" not in str(e.value)
    path.write_bytes(text.replace("31.6", "31.6\0\0", 5).encode())  # NULs in 5 cells
    table = load_table(path)
    assert any("NUL bytes" in n for n in table.notes)
    assert np.all(table.columns["temperature"] == 31.6)
    path.write_bytes(bytes(np.random.default_rng(3).integers(0, 256, 4000, dtype=np.uint8)))
    with pytest.raises(NoisevarError, match="binary"):  # a binary file is still one
        load_table(path)


def test_a_block_of_metadata_above_a_headerless_table_says_where_it_starts(tmp_path, capsys):
    text, _x = _geneactiv(300, 4)
    path = tmp_path / "demo_data.csv"
    path.write_bytes(text.encode())
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "binary" not in err and "thousands separators" not in err
    assert "metadata" in err and "rows start at line 10" in err and "skiprows=9" in err
    path = tmp_path / "money.csv"  # rows of numbers above: thousands separators, no block
    path.write_text("a,b\n" + "".join(f"{i},{i}.5\n" for i in range(8)) + "4,867.69,3\n")
    assert main(["estimate", str(path)]) == 2
    assert "thousands separators" in _one_line(capsys)


_TCX = """<?xml version="1.0" encoding="UTF-8"?>
<TrainingCenterDatabase xmlns="http://www.garmin.com/xmlschemas/TrainingCenterDatabase/v2">
  <Activities><Activity Sport="Biking"><Lap><Track><Trackpoint>
    <Time>2020-04-18T11:10:44.000Z</Time><AltitudeMeters>6.8</AltitudeMeters>
  </Trackpoint></Track></Lap></Activity></Activities></TrainingCenterDatabase>
"""
_GPX = """<?xml version="1.0" encoding="UTF-8"?>
<gpx creator="Garmin Connect" version="1.1"
  xmlns="http://www.topografix.com/GPX/1/1">
  <trk><trkseg><trkpt lat="52.1" lon="6.6"><ele>6.8</ele></trkpt></trkseg></trk></gpx>
"""


@pytest.mark.parametrize(("suffix", "text", "what"), [
    (".tcx", _TCX, "TCX activity"), (".gpx", _GPX, "GPX track"),
    (".xml", "<data><v>1</v></data>\n", "an XML file")])  # fmt: skip
def test_an_xml_track_is_refused_saying_what_it_is(tmp_path, capsys, suffix, text, what):
    path = tmp_path / f"ride{suffix}"
    path.write_text(text)
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert what in err and "CSV" in err and "not a number" not in err


def test_a_fit_file_is_refused_saying_what_it_is(tmp_path, capsys):
    header = bytes([14, 0x10, 0x5D, 0x08, 0x10, 0, 0, 0]) + b".FIT" + b"\0\0"
    path = tmp_path / "2020-06-01-16-52-40.fit"
    path.write_bytes(header + bytes(np.random.default_rng(5).integers(0, 256, 500, np.uint8)))
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "FIT file" in err and "CSV" in err


def _indexed(n: int, seed: int, first: str) -> tuple[str, np.ndarray]:
    """A table as pandas writes a frame indexed by time: an unnamed first column of
    date-times (with their UTC offset), then one measured column, as pvanalytics ships."""
    rng = np.random.default_rng(seed)
    z = rng.normal(0.0, 1.0, n)
    stamps = [f"2022-01-20 {i // 60:02d}:{i % 60:02d}:00-07:00" for i in range(n)]
    if first == "us":
        stamps = [f"1/20/2022 {i // 60}:{i % 60:02d}" for i in range(n)]
    rows = [f"{s},{v:.6f}" for s, v in zip(stamps, z, strict=True)]
    return ",Global CMP22 (vent/cor) [W/m^2]\n" + "\n".join(rows) + "\n", z


@pytest.mark.parametrize("first", ["iso", "us"])
def test_an_unnamed_first_column_of_date_times_is_the_time(tmp_path, first):
    text, z = _indexed(300, 6, first)
    path = tmp_path / "midc.csv"
    path.write_text(text)
    table = load_table(path)
    assert table.time_column == "col0" and table.sample_period == pytest.approx(60.0)
    assert not any("left out" in n for n in table.notes)
    got, t = channel_record(table, "Global CMP22 (vent/cor) [W/m^2]")
    np.testing.assert_allclose(got, np.round(z, 6))
    assert t[-1] == pytest.approx(299 * 60.0)


def test_the_json_names_the_one_column_it_read(tmp_path, capsys):
    import json

    text, _z = _indexed(300, 7, "iso")
    path = tmp_path / "midc.csv"
    path.write_text(text)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    js = json.loads(capsys.readouterr().out)
    assert js["column"] == "Global CMP22 (vent/cor) [W/m^2]" and js["unit"] == "W/m^2"


def test_rows_repeated_whole_are_left_out_and_the_times_kept(tmp_path):
    """Garmin's TCX repeats a track point at a pause (sweat's smart recording: 4 of 100):
    the time column was not increasing, so its times and its pause were not used."""
    rng = np.random.default_rng(8)
    t = np.r_[np.arange(60), 92 + np.arange(60)]  # a 32 s pause
    z = np.round(rng.normal(0.0, 0.1, t.size), 3)
    stamps = [f"2020-06-01T14:{52 + s // 60:02d}:{s % 60:02d}.000Z" for s in t]
    rows = [f"{s},{v}" for s, v in zip(stamps, z, strict=True)]
    for i in (20, 40, 70, 90):  # each repeated, time and value
        rows.insert(i, rows[i - 1])
    path = tmp_path / "smart.csv"
    path.write_text("time,speed\n" + "\n".join(rows) + "\n")
    table = load_table(path)
    assert table.sample_period == pytest.approx(1.0)
    assert any("4 rows repeat the row before" in n for n in table.notes)
    got, times = channel_record(table, "speed")
    np.testing.assert_allclose(got, z)
    np.testing.assert_allclose(times, t)
    path.write_text("speed\n" + "\n".join(f"{v}" for v in np.repeat(z, 2)) + "\n")
    assert load_table(path).columns["speed"].size == 2 * z.size  # no time: held values are data


def test_rows_repeated_with_no_time_are_data(tmp_path):
    """A GPX track whose first fixes have no time (real_audit3's korita-zbevnica): a fix held
    while still, repeated with an empty time, is data, not a duplicated record."""
    rng = np.random.default_rng(9)
    ele = np.round(300 + np.cumsum(rng.normal(0.0, 0.5, 200)), 1)
    ele[10:14] = ele[9]  # held while still, untimed
    stamps = ["" if i < 100 else f"2020-06-01T15:{i // 60:02d}:{i % 60:02d}Z" for i in range(200)]
    path = tmp_path / "partly_timed.csv"
    lines = [f"{s},{v}" for s, v in zip(stamps, ele, strict=True)]
    path.write_text("time,ele\n" + "\n".join(lines) + "\n")
    table = load_table(path)
    assert table.columns["ele"].size == 200
    assert not any("repeat the row before" in n for n in table.notes)
