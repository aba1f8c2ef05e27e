"""A unit pint does not read (a misspelt ``Celcius`` in a header or a units row) was dropped
without a word: the values were read unitless and nothing said so (issue 26)."""

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.io import load_table


def _write(path, header: str) -> None:
    rng = np.random.default_rng(3)
    z = 20.0 + np.cumsum(rng.normal(0.0, 0.01, 300)) + rng.normal(0.0, 0.1, 300)
    path.write_text(header + "".join(f"{i},{v:.4f}\n" for i, v in enumerate(z)))


@pytest.mark.parametrize("header", ["time,temp [Celcius]\n", "time,temp\ns,Celcius\n"])
def test_a_unit_pint_does_not_read_is_said_on_load(tmp_path, header):
    path = tmp_path / "t.csv"
    _write(path, header)
    said = [n for n in load_table(path).notes if "Celcius" in n]
    assert len(said) == 1 and "not understood" in said[0] and "never converted" in said[0]


def test_a_unit_pint_reads_is_not_noted(tmp_path):
    path = tmp_path / "t.csv"
    _write(path, "time,temp [degC]\n")
    assert not [n for n in load_table(path).notes if "understood" in n]


def test_the_cli_says_the_unit_was_not_understood(tmp_path, capsys):
    path = tmp_path / "t.csv"
    _write(path, "time,temp [Celcius]\n")
    assert main(["estimate", str(path), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["unit"] == "Celcius"  # as written: a label, never converted
    assert any("'Celcius'" in n and "never converted" in n for n in out["notes"])


def test_a_unit_pint_does_not_read_labels_every_surface(tmp_path, capsys):
    """LAS's ``GAPI`` (real_audit18) was shown ``u``: the results are now labelled as
    written on the CLI, in batch rows and on the Signal page; converting it is refused
    saying to give the unit, and a long or unprintable unit is no label."""
    from noisevar.units import unit_label

    path = tmp_path / "gr.csv"
    _write(path, "depth,GR [GAPI]\n")
    assert main(["estimate", str(path), "--column", "GR [GAPI]"]) == 0
    out = capsys.readouterr().out
    assert "GAPI²" in out and " u²" not in out, out
    assert main(["batch", str(path), "--columns", "GR [GAPI]", "--quiet"]) == 0
    assert ",GAPI," in capsys.readouterr().out
    assert main(["estimate", str(path), "--column", "GR [GAPI]", "--unit-out", "m"]) == 2
    err = capsys.readouterr().err
    assert "'GAPI' is not one pint reads: give --unit" in err and err.count("\n") == 1, err
    assert unit_label("x" * 40) is None and unit_label("a\x1bb") is None
    assert unit_label("deg/s") == "deg/s" and unit_label(None) is None
