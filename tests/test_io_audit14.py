"""Files of the fourteenth real-record audit (benchmarks/real_audit14.py) as users have them:
NIST's StRD files (a report whose prose has commas above a table parted by spaces) were
refused blaming thousands separators; python-can's Vector ASC logs were refused as rows of
differing widths, and a Monash ``.tsf`` file was called a ``.ts`` file; the Daphnet set's
64 Hz stamps written to the millisecond were read as 62.5 Hz and as non-uniform sampling."""

import numpy as np
import pandas as pd
import pytest

from noisevar.cli import main
from noisevar.io import load_table


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


def _nist(n: int, seed: int) -> tuple[str, np.ndarray]:
    """A NIST StRD-like file: a report of 58 lines (prose with commas, parameter lines with
    '='), ``Data:   y   x``, then rows of two numbers parted by spaces."""
    rng = np.random.default_rng(seed)
    report = ["NIST/ITL StRD", "Dataset Name:  Test  (Test.dat)", ""]
    report += [
        f"Description:   line {i}: the data, measured by hand, in units of a, b and c"
        if i % 4
        else f"  b{i} =   {i}.0   {i}.5   1.0E+01  2.0E-01"
        for i in range(55)
    ]
    y = 10.0 + rng.normal(0.0, 1.0, n)
    rows = [f"   {v:10.5f}   {i + 1:10.6f}" for i, v in enumerate(y)]
    return "\n".join([*report, "Data:   y          x", *rows]) + "\n", y


def test_a_report_with_commas_above_a_spaced_table_is_refused_pointing_to_it(tmp_path, capsys):
    text, y = _nist(200, 3)
    path = tmp_path / "Test.dat"
    path.write_text(text)
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "thousands separators" not in err
    assert "report" in err and "rows start at line 60" in err and "sep=r'\\s+'" in err
    # the advice, followed, gives the table
    df = pd.read_csv(path, sep=r"\s+", index_col=False, skiprows=59, header=None,
                     names=["y", "x"])  # fmt: skip
    assert np.allclose(df["y"], y, atol=1e-5)


def _asc(n: int) -> str:
    """A Vector ASC CAN log's head and ``n`` frames of two message ids."""
    head = ["date Tue May 27 04:09:35.000 pm 2014", "base hex  timestamps absolute",
            "internal events logged", "// version 10.0.1"]  # fmt: skip
    frames = [f"   {0.01 * i:.6f} 1  {64 + i % 2:X}              Rx   d 4 {i % 256:02X} 00 00 00  "
              f"Length = 0 BitCount = 0 ID = {100 + i % 2}" for i in range(n)]  # fmt: skip
    return "\n".join([*head, *frames]) + "\n"


def test_a_vector_asc_can_log_is_refused_naming_it(tmp_path, capsys):
    path = tmp_path / "bus.asc"
    path.write_text(_asc(50))
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "Vector ASC file" in err and "DBC" in err and "CSV" in err


def test_a_monash_tsf_file_is_refused_naming_it(tmp_path, capsys):
    path = tmp_path / "series.tsf"
    path.write_text("# a comment\n@relation test\n@attribute series_name string\n"
                    "@frequency yearly\n@horizon 4\n@missing false\n@equallength false\n"
                    "@data\nT1:1.5,2.5,3.5,4.5\nT2:5.0,6.0,7.0\n")  # fmt: skip
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "a .tsf file" in err and "load_from_tsf_file" in err


def _stamps(rate: float, n: int, res: float, offset: float = 0.0) -> np.ndarray:
    """A uniform clock's stamps rounded to ``res`` (relative to the first)."""
    t = np.round((offset + np.arange(n) / rate) / res) * res
    return t - t[0]


@pytest.mark.parametrize(("rate", "res"), [(64.0, 1e-3), (3.0, 0.1), (128.0, 1e-3)])
def test_a_uniform_clock_with_rounded_stamps_gives_its_rate(tmp_path, rate, res):
    rng = np.random.default_rng(7)
    t = _stamps(rate, 2000, res, offset=0.0004)
    path = tmp_path / "clock.csv"
    pd.DataFrame({"time": t, "acc": rng.normal(0, 1, t.size)}).to_csv(path, index=False)
    table = load_table(path)
    assert table.sample_period == pytest.approx(1.0 / rate, rel=1e-9)
    assert not any("not uniform" in n for n in table.notes)
    assert any("written to" in n for n in table.notes)


def test_missed_samples_are_not_taken_for_rounded_stamps(tmp_path):
    """A 1 s logger that misses samples: its 2 s steps are gaps, said, not rounding; the
    same logger's stamps rounded to 0.1 s at 3 Hz are one clock."""
    rng = np.random.default_rng(8)
    gaps = np.cumsum(np.where(rng.random(600) < 0.05, 2.0, 1.0))
    for name, t in (("gaps", gaps), ("clock", _stamps(3.0, 600, 0.1))):
        pd.DataFrame({"time": t, "v": rng.normal(0, 1, t.size)}).to_csv(
            tmp_path / f"{name}.csv", index=False
        )
    table = load_table(tmp_path / "gaps.csv")
    assert table.sample_period == 1.0
    assert any("not uniform" in n for n in table.notes)
    assert load_table(tmp_path / "clock.csv").sample_period == pytest.approx(1 / 3.0)
