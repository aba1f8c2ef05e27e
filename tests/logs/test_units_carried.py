"""LoadedTable.units: a column's unit when the file states it (a log's message definition,
a text header's brackets, NMEA's own columns), carried as a string for noisevar.units."""

from __future__ import annotations

from pathlib import Path

from noisevar.io import drop_nonfinite_rows, load_table

ROOT = Path(__file__).resolve().parents[2]


def test_text_header_units():
    body = (
        b"time (s),gyro_x [rad/s],acc (m/s^2),plain,p[ Pa ]\n0,1,2,3,4\n0.1,2,3,,5\n0.2,1,2,2,6\n"
    )
    tab = load_table(body, "a.csv")
    assert tab.time_column == "time (s)"
    assert tab.units == {"gyro_x [rad/s]": "rad/s", "acc (m/s^2)": "m/s^2", "p[ Pa ]": "Pa"}
    assert drop_nonfinite_rows(tab).units == tab.units


def test_nmea_units():
    tab = load_table(ROOT / "sample_data" / "gps_track.nmea")
    assert tab.units["east_m"] == "m" and tab.units["speed_mps"] == "m/s"


def test_no_units_by_default():
    assert load_table(b"x,y\n1,2\n3,4\n5,6\n", "b.csv").units == {}
