"""Command line: estimate (CSV with/without header, .npy, --config), methods, scan-h, errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main
from noisevar.format import eng

N = 3000


@pytest.fixture(scope="module")
def clean():
    rng = np.random.default_rng(0)
    return np.cumsum(rng.normal(0.0, 0.1, N)) + 100.0


@pytest.fixture(scope="module")
def signal(clean):
    """The clean random walk with noise of variance 4."""
    return clean + np.random.default_rng(1).normal(0.0, 2.0, N)


@pytest.fixture(scope="module")
def second(clean):
    """A second sensor of the same quantity, independent noise of variance 1."""
    return clean + np.random.default_rng(2).normal(0.0, 1.0, N)


def _write_csv(path, columns, header=None):
    data = np.column_stack(columns)
    with open(path, "w") as fh:
        if header:
            fh.write(",".join(header) + "\n")
        for row in data:
            fh.write(",".join(repr(float(v)) for v in row) + "\n")
    return str(path)


@pytest.fixture
def files(tmp_path, signal, second):
    t = np.arange(N) * 0.1
    with_nan = signal.copy()
    with_nan[[10, 700, 701]] = np.nan
    out = {
        "header": _write_csv(tmp_path / "header.csv", [t, signal, second], ["t", "z", "z2"]),
        "noheader": _write_csv(tmp_path / "noheader.csv", [signal]),
        "nan": _write_csv(tmp_path / "nan.csv", [t, with_nan], ["t", "z"]),
        "constant": _write_csv(tmp_path / "constant.csv", [np.full(500, 4.0)]),
        "short": _write_csv(tmp_path / "short.csv", [signal[:300]]),
        "text": str(tmp_path / "text.csv"),
        "empty": str(tmp_path / "empty.csv"),
        "npy": str(tmp_path / "signal.npy"),
        "npy3d": str(tmp_path / "cube.npy"),
        "bad_json": str(tmp_path / "bad.json"),
        "unknown_key": str(tmp_path / "unknown.json"),
        "bad_value": str(tmp_path / "badvalue.json"),
    }
    (tmp_path / "text.csv").write_text("name,colour\nalpha,red\nbeta,blue\n")
    (tmp_path / "empty.csv").write_text("")
    np.save(out["npy"], signal)
    np.save(out["npy3d"], np.zeros((4, 5, 6)))
    (tmp_path / "bad.json").write_text('{"method": "somd", "window": 40,,}')
    (tmp_path / "unknown.json").write_text('{"method": "somd", "h_smoth": 1e-5}')
    (tmp_path / "badvalue.json").write_text('{"method": "somd", "gamma_amp": 3}')
    return out


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys, *argv):
    code, out, err = run(capsys, *argv, "--format", "json")
    assert code == 0, err
    return json.loads(out)


# ---------------------------------------------------------------------------- estimate
def test_estimate_csv_with_header_table(capsys, files, signal):
    code, out, err = run(capsys, "estimate", files["header"], "--column", "z")
    assert code == 0, err
    assert err == ""
    assert "method    auto" in out
    expected = nv.estimate(signal)
    assert f"variance  {eng(expected.variance, 'u²')}" in out  # the page's formatter
    assert "95 % CI" in out


def test_estimate_json_keys_and_values(capsys, files, signal):
    data = run_json(capsys, "estimate", files["header"], "--column", "z", "--method", "somd")
    assert {"variance", "std", "ci95_low", "ci95_high", "method", "n_used", "params"} <= set(data)
    expected = nv.estimate(signal, method="somd")
    assert data["method"] == "somd"
    assert data["variance"] == pytest.approx(expected.variance, rel=1e-12)
    assert data["std"] == pytest.approx(np.sqrt(expected.variance), rel=1e-12)
    assert [data["ci95_low"], data["ci95_high"]] == pytest.approx(list(expected.ci95), rel=1e-12)
    assert data["n_used"] == expected.n_used
    assert data["params"]["method"] == "somd"
    assert data["params"]["window"] == 40


def test_estimate_first_data_column_by_default_and_by_index(capsys, files, signal):
    default = run_json(capsys, "estimate", files["header"])
    by_index = run_json(capsys, "estimate", files["header"], "--column", "0")
    other = run_json(capsys, "estimate", files["header"], "--column", "z2")
    assert default["variance"] == by_index["variance"]
    assert default["variance"] == pytest.approx(nv.estimate(signal).variance, rel=1e-12)
    assert other["variance"] < default["variance"] / 2  # z2 is the quieter sensor


def test_estimate_csv_without_header(capsys, files, signal):
    data = run_json(capsys, "estimate", files["noheader"], "--method", "diff2")
    assert data["variance"] == pytest.approx(
        nv.estimate(signal, method="diff2").variance, rel=1e-12
    )


def test_estimate_npy(capsys, files, signal):
    data = run_json(capsys, "estimate", files["npy"], "--method", "rice")
    assert data["variance"] == pytest.approx(nv.estimate(signal, method="rice").variance)
    assert data["n_used"] == N - 1


def test_estimate_somd_flags_reach_the_estimator(capsys, files, signal):
    data = run_json(
        capsys,
        "estimate",
        files["npy"],
        "--method",
        "somd-paper",
        "--h-smooth",
        "2e-5",
        "5e-5",
        "--h-track",
        "1e-3",
        "--window",
        "50",
        "--gamma-amp",
        "0.7",
        "--gamma-ang",
        "15",
        "--angle",
        "scaled",
    )
    params = data["params"]
    assert params["h_smooth"] == [2e-5, 5e-5]
    assert params["h_track"] == 1e-3
    assert params["window"] == 50
    assert params["gamma_amp"] == 0.7 and params["gamma_ang"] == 15.0
    assert params["angle"] == "scaled"
    expected = nv.estimate(
        signal,
        method="somd-paper",
        h_smooth=[2e-5, 5e-5],
        h_track=1e-3,
        window=50,
        gamma_amp=0.7,
        gamma_ang=15.0,
        angle="scaled",
    )
    assert data["variance"] == pytest.approx(expected.variance, rel=1e-12)
    no_select = run_json(capsys, "estimate", files["npy"], "--method", "somd", "--no-select")
    assert no_select["params"]["select"] is False


def test_estimate_redundant_with_reference_column(capsys, files, signal, second):
    argv = ["estimate", files["header"], "--column", "z2", "--method", "somd-redundant"]
    pair = run_json(capsys, *argv, "--reference-column", "z")
    # eq. 8 with both noises kept: var(z2 noise) + var(z noise) = 1 + 4
    assert pair["variance"] == pytest.approx(5.0, rel=0.08)
    expected = nv.estimate(second, method="somd-redundant", reference=signal)
    assert pair["variance"] == pytest.approx(expected.variance, rel=1e-12)
    known = run_json(capsys, *argv, "--reference-column", "z", "--reference-variance", "4.0")
    assert known["variance"] == pytest.approx(pair["variance"] - 4.0, rel=1e-9)
    assert known["params"]["reference_variance"] == 4.0


# ------------------------------------------------------------------------------ config
@pytest.mark.parametrize(
    "argv",
    [
        ["--method", "somd", "--h-smooth", "3e-5", "--window", "50", "--gamma-amp", "0.6"],
        ["--method", "somd", "--h-smooth", "1e-5", "4e-5"],
        ["--method", "auto"],
        ["--method", "wavelet-mad"],
    ],
)
def test_config_round_trip(capsys, tmp_path, files, argv):
    """The JSON's params are the config: --config with them reproduces the estimate."""
    first = run_json(capsys, "estimate", files["npy"], *argv)
    cfg = tmp_path / "tuned.json"
    cfg.write_text(json.dumps(first["params"]))
    again = run_json(capsys, "estimate", files["npy"], "--config", cfg)
    assert again["method"] == first["method"]
    assert again["variance"] == first["variance"]
    assert again["params"] == first["params"]


def test_config_from_the_config_module_and_flags_override_it(capsys, tmp_path, files, signal):
    from noisevar.config import config_to_json

    cfg = tmp_path / "tuned.json"
    cfg.write_text(
        config_to_json({"method": "somd", "h_smooth": 4e-5, "window": 48, "gamma_ang": 12.0})
    )
    data = run_json(capsys, "estimate", files["npy"], "--config", cfg)
    assert data["method"] == "somd"
    assert data["params"]["h_smooth"] == 4e-5 and data["params"]["window"] == 48
    expected = nv.estimate(signal, method="somd", h_smooth=4e-5, window=48, gamma_ang=12.0)
    assert data["variance"] == pytest.approx(expected.variance, rel=1e-12)
    flags = run_json(capsys, "estimate", files["npy"], "--config", cfg, "--window", "60")
    assert flags["params"]["window"] == 60
    assert flags["params"]["h_smooth"] == 4e-5
    other = run_json(capsys, "estimate", files["npy"], "--config", cfg, "--method", "somd-paper")
    assert other["method"] == "somd-paper" and other["params"]["window"] == 48


# ------------------------------------------------------------------------ non-finite
def test_nan_in_a_file_is_refused_naming_the_row(capsys, files):
    code, out, err = run(capsys, "estimate", files["nan"])
    assert code == 2
    assert out == ""
    assert err.startswith("noisevar: error:")
    assert "3 empty or NaN values" in err and "row 11" in err and "--drop-nonfinite" in err


@pytest.mark.parametrize("fmt", ["table", "json"])
def test_drop_nonfinite_reports_the_count(capsys, files, signal, fmt):
    code, out, err = run(capsys, "estimate", files["nan"], "--drop-nonfinite", "--format", fmt)
    assert code == 0, err
    assert "dropped 3 non-finite samples" in out
    gappy = signal.copy()
    gappy[[10, 700, 701]] = np.nan  # dropped samples are gaps: the same as the API's answer
    clean = nv.estimate(gappy, drop_nonfinite=True)
    if fmt == "json":
        data = json.loads(out)
        assert data["n_total"] == N - 3
        assert data["variance"] == pytest.approx(clean.variance, rel=1e-12)
        assert any("dropped 3" in note for note in data["notes"])


# ---------------------------------------------------------------------- bad input: CLI
BAD = [
    (["estimate", "{missing}"], "no such file"),
    (["estimate", "{empty}"], "is empty"),
    (["estimate", "{text}"], "not a number"),
    (["estimate", "{npy3d}"], "give a 1-D signal or a 2-D"),
    (["estimate", "{header}", "--column", "nope"], "no column 'nope'"),
    (["estimate", "{nan}"], "NaN"),
    (["estimate", "{constant}"], "variance is 0"),
    (["estimate", "{short}", "--method", "somd", "--window", "400"], "too few samples"),
    (["estimate", "{short}", "--method", "somd"], "too few samples"),
    (["estimate", "{npy}", "--method", "somd", "--h-smooth", "0.5"], "outside the stable range"),
    (["estimate", "{npy}", "--method", "somd", "--h-smooth", "0"], "outside the stable range"),
    (["estimate", "{npy}", "--method", "somd", "--h-smooth=-1e-5"], "outside the stable"),
    (["estimate", "{npy}", "--method", "somd", "--h-track", "1"], "h_track=1 is outside"),
    (["estimate", "{npy}", "--method", "somd", "--window", "3"], "window must be an integer"),
    (["estimate", "{npy}", "--method", "somd", "--window", "4.5"], "invalid int value"),
    (["estimate", "{npy}", "--method", "somd", "--gamma-amp", "2"], "gamma_amp=2.0 is out of"),
    (["estimate", "{npy}", "--method", "somd", "--gamma-ang", "120"], "gamma_ang=120.0 is out"),
    (["estimate", "{npy}", "--method", "somd", "--gamma-amp", "1e-4"], "no window kept"),
    (["estimate", "{npy}", "--method", "kalman"], "invalid choice: 'kalman'"),
    (["estimate", "{npy}", "--h-smoth", "1e-5"], "unrecognized arguments: --h-smoth"),
    (["estimate", "{npy}", "--config", "{unknown_key}"], "unknown config key 'h_smoth'"),
    (["estimate", "{npy}", "--config", "{bad_json}"], "not valid JSON"),
    (["estimate", "{npy}", "--config", "{bad_value}"], "'gamma_amp': gamma_amp=3 is out of range"),
    (["estimate", "{npy}", "--config", "{missing}"], "no such config file"),
    (["estimate", "{npy}", "--method", "somd-redundant"], "needs --reference-column"),
    (["estimate", "{npy}", "--format", "xml"], "invalid choice: 'xml'"),
    (["estimate"], "the following arguments are required: file"),
    (["scan-h", "{constant}"], "constant"),
    (["scan-h", "{missing}"], "no such file"),
    (["experiment", "monte-carlo", "--runs", "0"], "--runs must be at least 1"),
    (["experiment", "no-such-experiment"], "invalid choice"),
    (["frobnicate"], "invalid choice: 'frobnicate'"),
    ([], "the following arguments are required"),
]


@pytest.mark.parametrize(("argv", "phrase"), BAD)
def test_bad_input_exit_2_and_one_line(capsys, tmp_path, files, argv, phrase):
    paths = {**files, "missing": str(tmp_path / "missing.csv")}
    argv = [a.format(**paths) for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2, err
    assert out == ""
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert lines[0].startswith("noisevar: error: ")
    assert phrase in lines[0]
    assert "Traceback" not in err
    assert "internal error" not in err


def test_missing_file_subprocess_has_no_traceback(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(tmp_path / "nope.csv")],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NOISEVAR_DEBUG": ""},
    )
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.count("\n") == 1
    assert proc.stderr.startswith("noisevar: error: no such file")


# --------------------------------------------------------------------- methods, scan-h
def test_methods_table(capsys):
    code, out, err = run(capsys, "methods")
    assert code == 0 and err == ""
    lines = out.strip().splitlines()
    assert [line.split()[0] for line in lines] == nv.methods()


def test_methods_json(capsys):
    data = run_json(capsys, "methods")
    assert list(data["methods"]) == nv.methods()
    assert data["methods"] == nv.describe_methods()


def test_python_dash_m_noisevar_methods():
    proc = subprocess.run(
        [sys.executable, "-m", "noisevar", "methods"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    names = [line.split()[0] for line in proc.stdout.strip().splitlines()]
    assert names == nv.methods()


def test_scan_h_json_and_table(capsys, files, signal):
    data = run_json(capsys, "scan-h", files["npy"])
    from noisevar.filters.envelope import scan_h

    expected = scan_h(signal)
    assert data["h"] == pytest.approx(expected.h.tolist())
    assert data["ratio"] == pytest.approx(expected.ratio.tolist())
    assert data["h_chosen"] == expected.h_chosen
    assert data["band"] == [0.05, 0.1]
    code, out, err = run(capsys, "scan-h", files["header"], "--column", "z", "--window", "50")
    assert code == 0, err
    assert "h chosen" in out and "h range" in out
    assert out.count("*") >= 1  # grid points inside the band are marked


def test_experiment_monte_carlo_json(capsys):
    data = run_json(
        capsys,
        "experiment",
        "monte-carlo",
        "--runs",
        "3",
        "--seed",
        "1",
        "--n",
        "2000",
        "--methods",
        "auto,somd,rice",
    )
    assert data["runs"] == 3
    assert set(data["methods"]) == {"auto", "somd", "rice"}
    for stats in data["methods"].values():
        assert {"within_10pct", "max_abs_rel_error", "bias", "rmse"} <= set(stats)
        assert 0.0 <= stats["within_10pct"] <= 1.0
    assert data["methods"]["auto"]["max_abs_rel_error"] < 0.2


# ------------------------------------------------------------- flags made from the specs
@pytest.mark.parametrize(
    ("flags", "params"),
    [
        (["--span", "21"], {"span": 21}),
        (["--order", "2"], {"order": 2}),
        (["--trim", "4"], {"trim": 4.0}),
        (["--trim", "inf"], {"trim": float("inf")}),
        (["--span", "41", "--order", "4", "--trim", "6"], {"span": 41, "order": 4, "trim": 6.0}),
    ],
)
def test_auto_flags_match_the_api(capsys, files, signal, flags, params):
    out = run_json(capsys, "estimate", files["npy"], *flags)
    expected = nv.estimate(signal, **params)
    assert out["variance"] == pytest.approx(expected.variance, rel=1e-12)
    for key, value in params.items():
        assert float(out["params"][key]) == value  # strict JSON writes inf as "inf"


def test_wavelet_flag(capsys, files, signal):
    out = run_json(capsys, "estimate", files["npy"], "--method", "wavelet-mad", "--wavelet", "sym8")
    assert out["params"]["wavelet"] == "sym8"
    expected = nv.estimate(signal, method="wavelet-mad", wavelet="sym8").variance
    assert out["variance"] == pytest.approx(expected, rel=1e-12)


def test_select_flag_pair(capsys, files, signal):
    off = run_json(capsys, "estimate", files["npy"], "--method", "somd", "--no-select")
    on = run_json(capsys, "estimate", files["npy"], "--method", "somd", "--select")
    assert off["params"]["select"] is False and on["params"]["select"] is True
    assert off["variance"] == nv.estimate(signal, method="somd", select=False).variance


@pytest.mark.parametrize(
    ("argv", "phrase"),
    [
        (["--method", "rice", "--window", "40"], "'rice' does not take parameter(s) window"),
        (["--span", "20"], "span must be odd"),
        (["--order", "0"], "order=0 is out of range"),
        (["--trim", "1"], "trim=1.0 is out of range"),
        (["--method", "somd", "--span", "21"], "'somd' does not take parameter(s) span"),
    ],
)
def test_flags_a_method_does_not_take_exit_2(capsys, files, argv, phrase):
    code, out, err = run(capsys, "estimate", files["npy"], *argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and phrase in err


def test_every_spec_with_a_flag_is_on_the_estimate_parser():
    from noisevar.cli import build_parser
    from noisevar.estimators.params import PARAMS

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices["estimate"]
    flags = {s for a in sub._actions for s in a.option_strings}
    for spec in PARAMS.values():
        assert (spec.flag in flags) == spec.cli, spec.name


def test_text_output_uses_the_pages_formatter(tmp_path, signal, capsys):
    """A tiny variance reads 106.8×10⁻²⁴ s² on the page and in the CLI, not 1.06807e-22."""
    path = tmp_path / "tiny.csv"
    _write_csv(path, [signal * 1e-11], header="x")
    assert main(["estimate", str(path), "--unit", "s"]) == 0
    out = capsys.readouterr().out
    expected = nv.estimate(signal * 1e-11)
    assert f"variance  {eng(expected.variance, 's²')}" in out and "e-2" not in out


def test_a_column_index_is_answered_with_the_columns_name(capsys, tmp_path):
    """MIDC's CSV (real_audit5) has a date and a clock as text, left out of the data
    columns: ``--column 1`` read the second *data* column, and the answer named it "1",
    which is the file's clock column. It names the column it read."""
    rng = np.random.default_rng(3)
    rows = "".join(
        f"10/14/2018,{k // 60:02d}:{k % 60:02d},{rng.normal():.5f},{10 + rng.normal():.5f}\n"
        for k in range(600)
    )
    path = tmp_path / "midc.csv"
    path.write_text("DATE,MST,Global PSP [W/m^2],Temperature [degC]\n" + rows)
    data = run_json(capsys, "estimate", str(path), "--column", "1")
    assert data["column"] == "Temperature [degC]"
    assert main(["estimate", str(path), "--column", "1"]) == 0
    assert "column Temperature [degC]" in capsys.readouterr().out


def test_the_channels_table_writes_one_unit_form(capsys, tmp_path):
    """--columns all: the std's unit is written as the variance's (m/s², not m/s^2)."""
    rng = np.random.default_rng(4)
    path = tmp_path / "phyphox.csv"
    rows = np.c_[np.arange(600) * 0.01, rng.normal(size=(600, 2))]
    np.savetxt(path, rows, delimiter=",", comments="", fmt="%.6f",
               header='"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)"')  # fmt: skip
    assert main(["estimate", str(path), "--columns", "all"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("units"))
    assert line.split() == ["units", "variance", "(m/s²)²,", "std", "m/s²"]
