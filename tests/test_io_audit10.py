"""Files of the tenth real-record audit (benchmarks/real_audit10.py) as users have them:
geomagpy's IAGA-2002 files of the Conrad Observatory (a magnetometer's 1-second data, the
format INTERMAGNET's observatories publish) were refused blaming a row's field count, and
their 99999 / 88888 codes would have been read as values."""

import json

import numpy as np
import pytest

from noisevar import NoisevarError
from noisevar.cli import main
from noisevar.io import channel_record, load_table


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


_HEAD = """\
 Format                 IAGA-2002                                    |
 Source of Data         Some Observatory                             |
 IAGA Code              XYZ                                          |
 Reported               EHZF                                         |
 Data Interval Type     1-second (501-1500)                          |
 # gaussian filter with 0.3 Hz passband                              |
DATE       TIME         DOY     XYZE      XYZH      XYZZ      XYZF   |
"""


def _iaga(n: int, seed: int, f_code: str | None = None) -> tuple[str, np.ndarray]:
    """An IAGA-2002 file of ``n`` seconds; sample 5 of every element is 99999 (missing),
    and F is ``f_code`` throughout when given (88888: not recorded)."""
    rng = np.random.default_rng(seed)
    h = np.round(21027.0 + np.cumsum(rng.normal(0, 0.01, n)) + rng.normal(0, 0.02, n), 2)
    rows = []
    for i in range(n):
        s = f"2018-08-29 {i // 3600:02d}:{i // 60 % 60:02d}:{i % 60:02d}.000 241"
        e, hh, z, f = (16.5, h[i], 43859.3, 48632.9) if i != 5 else (99999.0,) * 4
        f = float(f_code) if f_code else f
        rows.append(f"{s} {e:12.2f}{hh:10.2f}{z:10.2f}{f:10.2f}")
    return _HEAD + "\n".join(rows) + "\n", h


def test_an_iaga_2002_file_is_read_with_its_times_units_and_codes(tmp_path):
    text, h = _iaga(400, 1)
    path = tmp_path / "wic20180829vsec.sec"
    path.write_text(text)
    table = load_table(path)
    assert table.time_column == "time" and table.sample_period == pytest.approx(1.0)
    assert table.units["XYZH"] == "nT" and "DOY" not in table.columns
    z, t = channel_record(table, "XYZH", drop_nonfinite=True)
    assert np.flatnonzero(np.isnan(z)).tolist() == [5] and t[-1] == pytest.approx(399.0)
    np.testing.assert_allclose(np.delete(z, 5), np.delete(h, 5))
    assert any("IAGA-2002" in n for n in table.notes)


def test_an_iaga_file_s_angles_are_in_minutes_of_arc(tmp_path):
    """D and I (a DHIF file) are in minutes of arc; H and F in nT."""
    text, _ = _iaga(50, 3)
    text = text.replace("XYZE      XYZH      XYZZ      XYZF", "XYZD      XYZH      XYZI      XYZF")
    path = tmp_path / "dhif.sec"
    path.write_text(text)
    units = load_table(path).units
    assert (units["XYZD"], units["XYZI"], units["XYZH"], units["XYZF"]) == (
        "arcmin", "arcmin", "nT", "nT")  # fmt: skip


def test_the_cli_answers_an_iaga_file_and_an_element_not_recorded_is_empty(tmp_path, capsys):
    text, _ = _iaga(400, 2, f_code="88888.00")
    path = tmp_path / "wic20230712vsec.sec"
    path.write_text(text)
    assert main(["estimate", str(path), "--column", "XYZH", "--drop-nonfinite",
                 "--format", "json"]) == 0  # fmt: skip
    js = json.loads(capsys.readouterr().out)
    assert js["unit"] == "nT" and js["variance"] < 1.0
    assert np.all(np.isnan(load_table(path).columns["XYZF"]))


def test_an_iaga_file_without_its_column_line_is_refused_in_one_line(tmp_path):
    path = tmp_path / "cut.sec"
    path.write_text(_HEAD.splitlines()[0] + "\n2018-08-29 00:00:00.000 241 1 2 3 4\n")
    with pytest.raises(NoisevarError, match="DATE TIME"):
        load_table(path)


@pytest.mark.parametrize(
    ("value", "unit", "shown"),
    [(0.004924, "nT", "0.004924 nT"), (2.5e-5, "nT", "25×10⁻⁶ nT"), (4e-4, "ms", "400×10⁻⁶ ms"),
     (3.628e-9, "s", "3.628 ns"), (4e-4, "m", "400 µm"), (0.0049, "min", "0.0049 min"),
     (1e-5, "ft", "10×10⁻⁶ ft"), (2e-6, "g", "2 µg")],
)  # fmt: skip
def test_a_unit_that_has_a_prefix_takes_no_second_one(value, unit, shown):
    from noisevar.format import eng

    assert eng(value, unit) == shown


def test_the_magnetometer_std_is_not_shown_in_milli_nanotesla(tmp_path, capsys):
    text, _ = _iaga(400, 3)
    path = tmp_path / "wic.sec"
    path.write_text(text)
    assert main(["estimate", str(path), "--column", "XYZH", "--drop-nonfinite"]) == 0
    out = capsys.readouterr().out
    assert "nT" in out and "mnT" not in out and "µnT" not in out


def test_a_column_of_the_clock_s_steps_is_not_read_as_the_signal(tmp_path, capsys):
    """gtsam's KITTI IMU file: ``Time dt accelX ...``, the first row's dt its own time."""
    rng = np.random.default_rng(4)
    t = 46534.48 + np.r_[0.0, 1.92 + 0.01 * np.arange(299)] + rng.normal(0, 1e-4, 300)
    dt = np.r_[t[0], np.diff(t)]
    rows = [f"{a:.9f} {b:.9f} {c:.6f}" for a, b, c in zip(t, dt, rng.normal(0, 0.02, 300),
                                                           strict=True)]  # fmt: skip
    path = tmp_path / "KittiEquivBiasedImu.txt"
    path.write_text("Time dt accelX\n" + "\n".join(rows) + "\n")
    assert load_table(path).first_signal == "accelX"
    assert main(["estimate", str(path), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["column"] == "accelX"
    assert main(["estimate", str(path), "--column", "dt", "--format", "json"]) == 0  # named


def test_a_file_of_rows_of_several_kinds_is_refused_saying_to_keep_one_kind(tmp_path, capsys):
    """gtsam's EuRoC excerpt: ``imu``, ``vision_feature`` and ``meta`` rows in one CSV."""
    rng = np.random.default_rng(5)
    lines = ["row_type,t_abs,gx,u_norm,key,value", "meta,,,,format_version,1",
             "meta,,,,measurement_space,normalized"]  # fmt: skip
    for i in range(200):
        t = 1403715273.26 + 0.005 * i
        lines.append(f"imu,{t:.4f},{rng.normal(0, 0.01):.6f},,,")
        if i % 4 == 0:
            lines += [f"vision_feature,{t:.4f},,{rng.uniform():.5f},," for _ in range(3)]
    path = tmp_path / "eqvio_processed_30s.csv"
    path.write_text("\n".join(lines) + "\n")
    assert main(["estimate", str(path), "--column", "gx"]) == 2
    err = _one_line(capsys)
    assert "3 kinds" in err and "'row_type'" in err and "keep the rows of one kind" in err


def test_fit_takes_the_drop_nonfinite_its_refusal_of_empty_cells_tells_users_to_give(
    tmp_path, capsys
):
    """geomagpy's magnetometer day has one 99999 (an empty cell once read): ``noisevar
    fit`` refused it saying "(CLI: --drop-nonfinite)", then refused that flag."""
    text, _ = _iaga(400, 6)
    path = tmp_path / "wic.sec"
    path.write_text(text)
    assert main(["fit", str(path), "--column", "XYZH", "--format", "json"]) == 2
    assert "--drop-nonfinite" in _one_line(capsys)
    assert main(["fit", str(path), "--column", "XYZH", "--drop-nonfinite",
                 "--format", "json"]) == 0  # fmt: skip
    js = json.loads(capsys.readouterr().out)
    assert js["dropped"] == 1 and js["unit"] == "nT" and js["r"] > 0
