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
    assert len(said) == 1 and "not understood" in said[0] and "unitless" in said[0]


def test_a_unit_pint_reads_is_not_noted(tmp_path):
    path = tmp_path / "t.csv"
    _write(path, "time,temp [degC]\n")
    assert not [n for n in load_table(path).notes if "understood" in n]


def test_the_cli_says_the_unit_was_not_understood(tmp_path, capsys):
    path = tmp_path / "t.csv"
    _write(path, "time,temp [Celcius]\n")
    assert main(["estimate", str(path), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["unit"] == "u"
    assert any("'Celcius'" in n and "unitless" in n for n in out["notes"])
