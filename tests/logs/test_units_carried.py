"""LoadedTable.units: a column's unit when the file states it (a log's message definition,
a text header's brackets, NMEA's own columns), carried as a string for noisevar.units."""

from __future__ import annotations

from pathlib import Path

import numpy as np

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


def test_ulog_gps_integers_magnetometer_and_local_position_units():
    """PX4 logs positions as integers (1e-7 deg, mm) before v1.14: R of ``alt`` is in mm²,
    not in an unnamed unit (real_audit3: the committed log's GPS, mag and position)."""
    from noisevar.io import log_topics

    px4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"
    units = {t.name: t.units for t in log_topics(px4)}
    gps = units["vehicle_gps_position"]
    assert gps["lat"] == gps["lon"] == "1e-7 deg" and gps["alt"] == "mm"
    assert units["vehicle_magnetometer"]["magnetometer_ga[0]"] == "gauss"
    local = units["vehicle_local_position"]
    assert (local["z"], local["vz"], local["az"]) == ("m", "m/s", "m/s**2")


def test_ulog_float_positions_keep_degrees():
    from noisevar.io.logs import ulog

    assert ulog._unit("sensor_gps", "lat", "f") is None  # a float lat is not 1e-7 deg
    assert ulog._unit("sensor_gps", "latitude_deg", "f") == "deg"
    assert ulog._unit("sensor_gps", "altitude_msl_m", "f") == "m"
    assert ulog._unit("sensor_gps", "alt", "i") == "mm"


def test_a_named_bracket_before_the_unit():
    """NREL MIDC's logger CSV (real_audit5): ``Global Horiz (tracker) [W/m^2]`` lost its unit
    (shown as 'u') while ``Direct Normal [W/m^2]`` beside it kept it; the unit is in the
    header's last brackets, an earlier bracketed word is part of the name."""
    body = b"Direct Normal [W/m^2],Global Horiz (tracker) [W/m^2],Temp CM22 (tracker) [deg C]\n"
    body += b"1,2,3\n2,3,4\n3,4,5\n"
    tab = load_table(body, "midc.csv")
    assert tab.units == {
        "Direct Normal [W/m^2]": "W/m^2",
        "Global Horiz (tracker) [W/m^2]": "W/m^2",
        "Temp CM22 (tracker) [deg C]": "deg C",
    }


def test_a_netcdf_udunits_unit_reaches_the_answer(tmp_path, capsys):
    """A netCDF4 file's ``units = "W/m2"`` (UDUNITS, as GOES's X-ray files write it:
    benchmarks/real_audit6.py) is the unit the CLI answers in, not ``u``."""
    import json

    import h5py

    from noisevar.cli import main

    path = tmp_path / "xrs.nc"
    rng = np.random.default_rng(6)
    with h5py.File(path, "w") as f:
        f["time"] = np.arange(600) * 2.0
        f["b_flux"] = 1e-7 + 3e-9 * rng.normal(size=600)
        f["b_flux"].attrs["units"] = np.bytes_(b"W/m2")
    assert main(["estimate", str(path), "--column", "b_flux", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["unit"] == "W/m2"
