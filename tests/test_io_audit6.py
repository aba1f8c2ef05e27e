"""Files of the sixth real-record audit (benchmarks/real_audit6.py) as users have them:
OpenSignals text files (PLUX, BITalino) as the device writes them, their columns named from
the JSON header and the wrapping sequence counter not taken for the signal (pyhrv's
SampleECG.txt was read as col0..col6, nSeq first); another tool's comment lines."""

import json

import numpy as np

from noisevar.cli import main
from noisevar.io import load_table


def _opensignals(path, n: int = 600, seed: int = 6) -> np.ndarray:
    """A BITalino file: ``#`` header lines, the JSON header, tab-separated rows with a
    trailing tab; nSeq counts 0..15 and wraps, I1/I2/O1/O2 digital (O1 switched: pyhrv's
    file switches it for 262 samples, and it was read by default), A2 the ECG in counts."""
    ecg = np.round(500 + 3 * np.random.default_rng(seed).normal(size=n))
    cols = ["nSeq", "I1", "I2", "O1", "O2", "A2"]
    device = {"column": cols, "sampling rate": 1000, "label": ["A2"], "sensor": ["ECG"]}
    head = {"00:00:00:00:00:00": device}
    out = (np.arange(n) // 50) % 2  # O1: a digital output the recording switched
    cells = zip(out, ecg, strict=True)
    rows = [f"{(i + 1) % 16}\t1\t1\t{o}\t0\t{int(v)}\t" for i, (o, v) in enumerate(cells)]
    lines = ["# OpenSignals Text File Format", "# " + json.dumps(head), "# EndOfHeader"]
    path.write_text("\n".join([*lines, *rows]) + "\n")
    return ecg


def test_opensignals_header_names_the_columns(tmp_path):
    path = tmp_path / "ecg.txt"
    ecg = _opensignals(path)
    table = load_table(path)
    assert table.data_columns[:6] == ["nSeq", "I1", "I2", "O1", "O2", "A2"]
    np.testing.assert_array_equal(table.columns["A2"], ecg)
    assert table.first_signal == "A2"  # not the counter that wraps, nor a digital line


def test_opensignals_file_estimates_its_ecg_by_default(tmp_path, capsys):
    path = tmp_path / "ecg.txt"
    _opensignals(path)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["column"] == "A2"


def test_another_tools_comment_lines_are_named_in_the_refusal(tmp_path, capsys):
    """SDO/EVE's text files start with ``;`` comment lines (IDL's marker): the refusal blamed
    thousands separators; it names the marker now, in one line."""
    path = tmp_path / "eve.txt"
    prose = [
        "; DATA_list: 20160610_EVE_L0CS_DIODES_1m.txt",
        "; Origin: SDO/EVE Science Processing and Operations Center, LASP/CU",
        "; Units: W/m^2 for irradiance, dark is counts/(0.25s sample), quadrants are unitless",
        ";END_OF_HEADER",
        "2016 162 06 10",
    ]
    rows = [f"{i:04d}  2.18e-07  1.84e-10  4.98e-04" for i in range(200)]
    path.write_text("\n".join([*prose, *rows]) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "starts with ';'" in err and "thousands" not in err and "\n" not in err
