"""A refusal of empty cells names a fix the command has (issue 26, real_audit10): `allan`
and `imu` told users to give --drop-nonfinite, which they refuse; `scan-h` takes it."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.cli import main


@pytest.fixture
def nan_csv(tmp_path):
    z = np.random.default_rng(0).normal(size=2000)
    z[100] = np.nan
    path = tmp_path / "nan.csv"
    np.savetxt(path, np.c_[np.arange(2000) * 0.01, z], delimiter=",", header="time,x", comments="")
    return path


@pytest.mark.parametrize("cmd", [["allan"], ["imu", "--rate", "100"]])
def test_commands_that_need_every_sample_do_not_offer_a_flag_they_lack(nan_csv, cmd, capsys):
    assert main([cmd[0], str(nan_csv), *cmd[1:]]) == 2
    err = capsys.readouterr().err.strip()
    assert "--drop-nonfinite" not in err and "every sample in its place" in err
    assert len(err.splitlines()) == 1


def test_scan_h_drops_empty_cells_when_asked(nan_csv, capsys):
    assert main(["scan-h", str(nan_csv)]) == 2
    assert "--drop-nonfinite" in capsys.readouterr().err
    assert main(["scan-h", str(nan_csv), "--drop-nonfinite"]) == 0
    assert "h chosen" in capsys.readouterr().out
