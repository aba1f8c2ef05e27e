"""Each exported config runs through the one command that reads it (issue 28 item 3).

The Noise model page's tuned filter: ``noisevar fit FILE --config tuned.json`` gives the
page's q and r on the column it names, refuses another column or a file without it, and
``noisevar estimate --config`` refuses it in one line naming ``noisevar fit``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.config import filter_config_json
from noisevar.noise_model import fit_kalman
from noisevar.noise_model.export import APPLY_COMMAND


@pytest.fixture(scope="module")
def imu_csv(tmp_path_factory):
    rng = np.random.default_rng(28)
    n, rate = 2000, 10.0
    v = np.cumsum(rng.normal(0, 0.3, n))
    x = np.cumsum(v) / rate + rng.normal(0, 1.0, n)
    other = rng.normal(0, 5.0, n)
    path = tmp_path_factory.mktemp("rt") / "imu.csv"
    table = np.column_stack([np.arange(n) / rate, other, x])
    np.savetxt(path, table, delimiter=",", header="t,Acc_X,Gyr_Z", comments="")
    return str(path), x, rate


@pytest.fixture(scope="module")
def page_config(imu_csv, tmp_path_factory):
    """The file the Noise model page downloads for Gyr_Z (the page's own builder)."""
    _, x, rate = imu_csv
    tuning = fit_kalman(x, model="cv", rate=rate, method="mle")
    path = tmp_path_factory.mktemp("cfg") / "tuned.json"
    path.write_text(filter_config_json(tuning, "Gyr_Z", "rad/s"), encoding="utf-8")
    return path, tuning


def _one_line_error(capsys, match: str) -> None:
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1, err


def test_the_page_config_names_column_unit_and_the_method_used(page_config):
    cfg = json.loads(page_config[0].read_text())
    assert cfg["column"] == "Gyr_Z"
    assert cfg["kalman"]["unit"] == "rad/s" and cfg["kalman"]["method"] == "mle"
    assert "method" not in cfg  # no estimator method ("auto") it was not fitted with
    assert APPLY_COMMAND.startswith("noisevar fit ")


def test_noisevar_fit_applies_it_to_its_column_with_the_page_numbers(imu_csv, page_config, capsys):
    path, tuning = page_config
    assert main(["fit", imu_csv[0], "--config", str(path), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["column"] == "Gyr_Z" and out["method"] == "given"
    assert out["q"] == tuning.q and out["r"] == tuning.r
    assert out["nis_mean"] == pytest.approx(tuning.nis_mean, rel=1e-9)


@pytest.mark.parametrize(
    "args,match",
    [
        (["--column", "Acc_X"], "fitted on column 'Gyr_Z', not 'Acc_X'"),
        (["--column", "0"], "not 'Acc_X'"),
    ],
)
def test_another_column_is_refused(imu_csv, page_config, capsys, args, match):
    assert main(["fit", imu_csv[0], "--config", str(page_config[0]), *args]) == 2
    _one_line_error(capsys, match)


def test_a_file_without_the_column_is_refused(page_config, tmp_path, capsys):
    other = tmp_path / "other.csv"
    np.savetxt(
        other,
        np.random.default_rng(1).normal(size=(500, 2)),
        delimiter=",",
        header="a,b",
        comments="",
    )
    assert main(["fit", str(other), "--config", str(page_config[0])]) == 2
    _one_line_error(capsys, "does not have")


def test_a_config_naming_no_column_needs_one_on_a_file_of_several(
    imu_csv, page_config, tmp_path, capsys
):
    cfg = json.loads(page_config[0].read_text())
    del cfg["column"]
    old = tmp_path / "old.json"
    old.write_text(json.dumps(cfg))
    assert main(["fit", imu_csv[0], "--config", str(old)]) == 2
    _one_line_error(capsys, "give --column")
    assert main(["fit", imu_csv[0], "--config", str(old), "--column", "Gyr_Z"]) == 0


def test_noisevar_estimate_refuses_it_naming_noisevar_fit(imu_csv, page_config, capsys):
    assert main(["estimate", imu_csv[0], "--config", str(page_config[0])]) == 2
    _one_line_error(capsys, "noisevar fit FILE --config tuned.json")


def test_save_config_carries_the_column_and_method(imu_csv, tmp_path, capsys):
    out = tmp_path / "saved.json"
    args = ["fit", imu_csv[0], "--column", "1", "--rate", "10", "--save-config", str(out)]
    assert main(args) == 0
    capsys.readouterr()
    cfg = json.loads(out.read_text())
    assert cfg["column"] == "Gyr_Z" and cfg["kalman"]["method"] == "mle"
    assert main(["fit", imu_csv[0], "--config", str(out)]) == 0


def test_the_estimator_upload_refuses_it_naming_noisevar_fit(page_config):
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from dashboard.sections.estimator_tuning import _parse_with_column
    from noisevar.errors import NoisevarError

    with pytest.raises(NoisevarError, match="noisevar fit FILE --config tuned.json"):
        _parse_with_column(page_config[0].read_bytes(), "tuned.json")
