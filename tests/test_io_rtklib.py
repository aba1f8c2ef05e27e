"""RTKLIB solution files (``.pos``): tracklib's GNSS records (RTKPOST's header block of
``%`` lines, a time of two fields, latitude/longitude/height in degrees) were refused as an
unknown comment marker, or, with only the column line, read with ``%`` as a date column and
the position in degrees."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.io import load_table

_HEAD = """% program   : RTKPOST ver.2.4.2
% inp file  : rover.obs
% pos mode  : single
%
% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,ns=# of satellites)
"""
_COLS = (
    "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   "
    "sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio"
)
#: metres of a degree of latitude near 47.5° N (WGS-84), about
_M_PER_DEG = 111_180.0


def _static(n: int, sd: float, seed: int, week: bool = False, eol: str = "\n") -> str:
    """A still receiver's solution file: ``n`` epochs at 1 s, white noise of ``sd`` metres on
    latitude, longitude and height."""
    rng = np.random.default_rng(seed)
    lat = 47.5147 + rng.normal(0, sd, n) / _M_PER_DEG
    lon = -0.9905 + rng.normal(0, sd, n) / (_M_PER_DEG * np.cos(np.radians(47.5147)))
    h = 104.0 + rng.normal(0, sd, n)
    rows = []
    for i in range(n):
        t = f"2168 {284819 + i:.3f}" if week else f"2021/04/15 17:40:{i % 60:02d}.000"
        if not week and i >= 60:
            t = f"2021/04/15 17:{40 + i // 60:02d}:{i % 60:02d}.000"
        rows.append(
            f"{t}   {lat[i]:.9f}   {lon[i]:.9f}   {h[i]:.4f}   5   8   2.0   1.5   "
            "4.0   0.3   -0.2   0.5   0.00    0.0"
        )
    return eol.join([*_HEAD.splitlines(), _COLS, *rows]) + eol


@pytest.mark.parametrize("week", [False, True])
def test_rtklib_positions_in_metres(tmp_path, week):
    path = tmp_path / "rover.pos"
    path.write_text(_static(600, 0.5, seed=3, week=week))
    table = load_table(path)
    assert table.time_column == "time"
    assert table.sample_period == pytest.approx(1.0)
    assert table.first_signal == "east_m"
    assert table.units["up_m"] == "m"
    assert "RTKLIB" in table.notes[0]
    up = np.asarray(table.columns["up_m"]) * 1e4  # the height's 0.1 mm grid kept
    np.testing.assert_allclose(up, np.round(up), atol=1e-6)
    for col in ("east_m", "north_m", "up_m"):
        est = nv.estimate(np.asarray(table.columns[col], float))
        assert est.ci95[0] < 0.25 < est.ci95[1], col  # sd 0.5 m: R 0.25 m²


def test_rtklib_column_line_only_and_cr_endings(tmp_path):
    """rover1.pos's shape: only the column line, rows ended by a lone carriage return."""
    text = _static(300, 0.5, seed=4, eol="\r")
    path = tmp_path / "rover1.pos"
    path.write_text(text[text.index("%  GPST") :], newline="")
    table = load_table(path)
    assert "%" not in table.columns
    assert list(table.columns)[:4] == ["time", "east_m", "north_m", "up_m"]


def test_rtklib_ecef_kept(tmp_path):
    path = tmp_path / "ecef.pos"
    cols = "%  GPST                      x-ecef(m)      y-ecef(m)      z-ecef(m)   Q  ns"
    rows = [
        f"2021/07/28 07:07:{i:02d}.000   4203099.5{i}   179114.5   4778081.0   5   6"
        for i in range(40)
    ]
    path.write_text("\n".join(["% pos mode  : single", cols, *rows]) + "\n")
    table = load_table(path)
    assert list(table.columns)[:4] == ["time", "x-ecef(m)", "y-ecef(m)", "z-ecef(m)"]
    assert table.units["x-ecef(m)"] == "m"


def test_rtklib_short_row_one_line(tmp_path):
    path = tmp_path / "cut.pos"
    text = _static(20, 0.5, seed=5)
    path.write_text(text.rsplit(" ", 6)[0] + "\n")
    with pytest.raises(NoisevarError, match="RTKLIB solution has"):
        load_table(path)


def test_rtklib_column_line_run_on_the_line_above(tmp_path):
    """tracklib's sol.pos: ``% ref pos : ...`` and the column line with no line end between
    them were read as columns ``%``, ``pos``, ``:`` and numbers."""
    text = _static(120, 0.5, seed=6, eol="\r")
    path = tmp_path / "sol.pos"
    path.write_text("% ref pos   : 47.5 -0.99 99.2" + text[text.index("%  GPST") :], newline="")
    table = load_table(path)
    assert list(table.columns)[:4] == ["time", "east_m", "north_m", "up_m"]


@pytest.mark.parametrize(
    "row",
    [
        "9999999999 1e308 48.1 -1.2 55.1 2 10 0.01",  # a GPS week past any date
        "2168 nan 48.1 -1.2 55.1 2 10 0.01",  # seconds not a number
        "2021/13/45 25:61:61 48.1 -1.2 55.1 2 10 0.01",  # no such date
        "2168 284819 x -1.2 55.1 2 10 0.01",  # a latitude not a number
        "2168 284819 95 -1.2 55.1 2 10 0.01",  # a latitude past the pole
        "2168 284819 48.1 inf 55.1 2 10 0.01",  # a longitude not finite
    ],
)
def test_a_damaged_solution_row_is_refused_in_one_line(row: str) -> None:
    """Untrusted rows raised OverflowError / ValueError tracebacks (76 of 210 fuzzed files)."""
    head = "% program : RTKPOST\n%  GPST  latitude(deg) longitude(deg) height(m) Q ns sdn(m)\n"
    good = "2168 284818.000 48.1 -1.2 55.1 2 10 0.01\n"
    if "/" in row:  # a file of dates
        good = "2021/03/22 15:20:44.000 48.1 -1.2 55.1 2 10 0.01\n"
    with pytest.raises(NoisevarError, match="RTKLIB"):
        load_table((head + good * 5 + row + "\n" + good * 5).encode(), "bad.pos")


def test_the_solutions_own_standard_deviations_are_no_signals(tmp_path, capsys):
    """RTKLIB writes each solution's own standard deviations (``sdn(m)``) and its quality
    flag, satellite count, age and ratio beside the position: they were read as signals (the
    Signal page's channels and the Two sensors page's sensors opened on ``sdn(m)``,
    ``sde(m)``, ``sdne(m)``). They are side columns now, read only when named, and not
    paired with R (a GNSS solution's covariance covers slow errors R does not see)."""
    import json

    from noisevar.batch.channels import table_channels
    from noisevar.cli import main

    path = tmp_path / "rover.pos"
    path.write_text(_static(600, 0.5, seed=3))
    table = load_table(path)
    assert table.signals == ["east_m", "north_m", "up_m"]
    assert set(table.side_columns) == {"Q", "ns", "sdn(m)", "sde(m)", "sdu(m)", "sdne(m)",
                                       "sdeu(m)", "sdun(m)", "age(s)", "ratio"}  # fmt: skip
    assert not table.declared_variance
    assert main(["estimate", str(path), "--columns", "all", "--format", "json"]) == 0
    rows = json.loads(capsys.readouterr().out)["channels"]
    assert [c["column"] for c in rows if "error" not in c] == ["east_m", "north_m", "up_m"]
    left = {c["column"]: c["error"] for c in rows if "error" in c}
    assert "the solution's own standard deviation" in left["sdn(m)"]
    assert "the number of satellites" in left["ns"]
    assert table_channels(table, ["sdn(m)"]) == ["sdn(m)"]  # named, it is read
