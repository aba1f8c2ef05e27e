"""Typed experiments: keyword runs, frozen results, validation, CLI flags, discovery."""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import textwrap
from typing import Any

import pytest

import noisevar.experiments as experiments
from noisevar.cli import build_parser, main
from noisevar.errors import NoisevarError
from noisevar.experiments import Experiment, ExperimentResult, ListParam, SwitchParam, discover
from noisevar.kalman.strategies import strategy_spec

#: Tiny keyword runs of every experiment.
CASES: dict[str, dict[str, Any]] = {
    "monte-carlo": {"runs": 2, "seed": 1, "n": 500, "methods": ("auto", "rice")},
    "noise-step": {"runs": 1, "steps": 1500, "settle": 100, "methods": ("oracle", "fixed", "rae")},
    "noise-ramp": {"runs": 1, "steps": 1500, "settle": 100, "methods": ("oracle", "vb")},
    "gps-circle": {"runs": 1, "duration": 300.0, "methods": ("oracle", "somd", "rae")},
    "outliers": {"runs": 2, "kappa_sweep": (1.345,), "iterations": 3},
    "carrier": {"runs": 2, "duration": 1.0, "sweep": (30.0,), "data_bits": True},
    "fusion": {"runs": 2, "steps": 100, "failure": "frozen"},
    "latency": {"runs": 1, "duration": 100.0},
}

#: Today's flags of every experiment (besides --runs, --seed, --format) and their defaults.
FLAGS: dict[str, dict[str, Any]] = {
    "monte-carlo": {"signal": "fast-slow", "n": 6000, "methods": None},
    "noise-step": {
        "steps": 6000,
        "factor": 3.0,
        "settle": 500,
        "window": 50,
        "forgetting": 0.98,
        "rho": 0.99,
        "somd_window": 500,
        "somd_every": 20,
        "jobs": 1,
        "methods": ("oracle", "fixed", "somd", "rae", "iae", "sage-husa", "vb", "rae-q"),
    },
    "gps-circle": {
        "duration": 3000.0,
        "window": 50,
        "forgetting": 0.98,
        "rho": 0.99,
        "somd_every": 100,
        "somd_window": None,
        "jobs": 1,
        "methods": (
            "oracle",
            "somd",
            "somd-paper",
            "rae",
            "iae",
            "sage-husa",
            "vb",
            "rae-q",
            "fixed",
        ),
    },
    "outliers": {
        "kappa": 2.5,
        "kappa_sweep": (),
        "iterations": 10,
        "magvar": -5.0,
        "burst_rate": 0.08,
    },
    "carrier": {
        "cn0": 30.0,
        "sweep": (25.0, 30.0, 35.0, 40.0, 45.0),
        "nominal_cn0": 45.0,
        "nominal_doppler_rate": None,
        "integration_ms": 10.0,
        "duration": 10.0,
        "window": 50,
        "data_bits": False,
    },
    "fusion": {
        "steps": 600,
        "failure": "bias",
        "local": "vb",
        "noise_factor": 4.0,
        "bias_sigmas": 20.0,
        "false_alarm": 1e-3,
    },
    "latency": {
        "delay": 0.3,
        "measurable": 0.1,
        "jitter": 0.05,
        "rate": 10.0,
        "duration": 550.0,
        "segment": 30.0,
        "max_delay": 2.0,
    },
}
FLAGS["noise-ramp"] = FLAGS["noise-step"]
DEFAULT_RUNS = {"monte-carlo": 200, "noise-step": 20, "noise-ramp": 20, "gps-circle": 20}


def _argv(exp: Experiment, kwargs: dict[str, Any]) -> list[str]:
    """Command-line arguments giving ``kwargs`` to ``exp``."""
    specs = {p.name: p for p in exp.parameters}
    argv: list[str] = []
    for name, value in kwargs.items():
        spec = specs[name]
        if isinstance(spec, SwitchParam):
            argv += [spec.flag] if value else []
        elif isinstance(spec, ListParam) and spec.sep is None:
            argv += [spec.flag, *map(str, value)]
        elif isinstance(spec, ListParam):
            argv.append(f"{spec.flag}={spec.sep.join(map(str, value))}")
        else:
            argv += [spec.flag, str(value)]
    return argv


def _cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_every_experiment_has_a_case() -> None:
    assert set(discover()) == set(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_keyword_run_matches_the_cli(capsys: pytest.CaptureFixture[str], name: str) -> None:
    exp = discover()[name]
    result = exp.run(**CASES[name])
    assert isinstance(result, ExperimentResult)
    assert dataclasses.is_dataclass(result)
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.runs = 99  # type: ignore[misc]
    data = result.to_dict()
    text = json.dumps(data, indent=2)  # plain JSON types only: no default= needed
    code, out, err = _cli(capsys, "experiment", name, *_argv(exp, CASES[name]), "--format", "json")
    assert code == 0, err
    assert out.strip() == text
    assert exp.format_table(result) == exp.format_table(data)


def test_table_format_and_module_level_run(capsys: pytest.CaptureFixture[str]) -> None:
    kwargs = CASES["latency"]
    result = experiments.run("latency", **kwargs)
    assert result == discover()["latency"].run(**kwargs)
    code, table, err = _cli(capsys, "experiment", "latency", "--runs", "1", "--duration", "100")
    assert code == 0, err
    assert table == discover()["latency"].format_table(result) + "\n"
    with pytest.raises(NoisevarError, match="unknown experiment 'nope'"):
        experiments.run("nope")


@pytest.mark.parametrize("name", sorted(FLAGS))
def test_cli_flags_and_defaults_are_todays(name: str) -> None:
    exp = discover()[name]
    assert exp.default_runs == DEFAULT_RUNS.get(name, 100)
    assert exp.defaults() == {"runs": exp.default_runs, "seed": 0, **FLAGS[name]}
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    esub = next(
        a for a in sub.choices["experiment"]._actions if isinstance(a, argparse._SubParsersAction)
    )
    flags = {s for a in esub.choices[name]._actions for s in a.option_strings}
    expected = {"-h", "--help", "--runs", "--seed", "--format"}
    expected |= {"--" + k.replace("_", "-") for k in FLAGS[name]}
    assert flags == expected


def test_strategy_defaults_come_from_the_registry() -> None:
    for name in ("noise-step", "gps-circle"):
        d = discover()[name].defaults()
        assert d["window"] == strategy_spec("rae").defaults()["window"]
        assert d["forgetting"] == strategy_spec("sage-husa").defaults()["forgetting"]
        assert d["rho"] == strategy_spec("vb").defaults()["rho"]
    gps = discover()["gps-circle"].defaults()
    assert gps["somd_every"] == strategy_spec("somd").defaults()["every"]
    assert gps["somd_window"] == strategy_spec("somd").defaults()["window"]


BAD = [
    ("latency", {"runs": 0}, "--runs must be at least 1"),
    ("latency", {"runs": 1.5}, "runs must be an integer"),
    ("latency", {"durration": 10.0}, "does not take parameter(s) durration"),
    ("latency", {"delay": 0.05}, "smaller than its measurable part"),
    ("latency", {"rate": "fast"}, "rate must be a number"),
    ("monte-carlo", {"n": 50}, "--n must be at least 100 samples"),
    ("monte-carlo", {"signal": "nope"}, "signal must be a string: one of"),
    ("noise-step", {"jobs": 0}, "--jobs must be at least 1"),
    ("noise-step", {"methods": ("oracle", "kalman")}, "methods must be strings"),
    ("noise-step", {"forgetting": 1.5}, "forgetting=1.5 is out of range"),
    ("noise-step", {"runs": 1, "steps": 1000, "settle": 5000}, "settle"),
    ("gps-circle", {"window": 0}, "window=0 is out of range"),
    ("outliers", {"kappa_sweep": "1.345,-2"}, "kappa_sweep=-2 is out of range"),
    ("carrier", {"sweep": "25,x"}, "sweep must be a number"),
    ("carrier", {"data_bits": "yes"}, "data_bits must be true or false"),
    ("fusion", {"failure": "melted"}, "failure must be a string: one of bias, frozen"),
]


@pytest.mark.parametrize(("name", "kwargs", "phrase"), BAD)
def test_bad_values_raise_noisevar_error(name: str, kwargs: dict[str, Any], phrase: str) -> None:
    with pytest.raises(NoisevarError) as info:
        discover()[name].run(**kwargs)
    assert phrase in str(info.value)


@pytest.mark.parametrize(
    ("argv", "phrase"),
    [
        (["outliers", "--kappa-sweep", "1,-2"], "kappa_sweep=-2 is out of range"),
        (["carrier", "--sweep", "25,x"], "sweep must be a number"),
        (["noise-step", "--jobs", "0"], "--jobs must be at least 1"),
        (["noise-step", "--methods", "kalman"], "invalid choice: 'kalman'"),
        (["latency", "--runs", "0"], "--runs must be at least 1"),
    ],
)
def test_bad_flags_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str], phrase: str) -> None:
    code, out, err = _cli(capsys, "experiment", *argv)
    assert code == 2 and out == ""
    assert err.startswith("noisevar: error: ") and phrase in err and err.count("\n") == 1


def test_list_parameters_accept_text_or_sequences() -> None:
    exp = discover()["carrier"]
    assert exp.validate(sweep="25, 30,,35")["sweep"] == (25.0, 30.0, 35.0)
    assert exp.validate(sweep=[25, 30])["sweep"] == (25.0, 30.0)
    assert exp.validate(sweep="")["sweep"] == ()
    mc = discover()["monte-carlo"]
    assert mc.validate(methods="auto, rice")["methods"] == ("auto", "rice")
    assert mc.validate(methods="")["methods"] == ()


TRIVIAL = """
from dataclasses import dataclass

from noisevar.experiments import Experiment, ExperimentResult
from noisevar.params import ParamSpec


@dataclass(frozen=True)
class TrivialResult(ExperimentResult):
    runs: int
    seed: int
    total: float


def run(*, runs: int, seed: int, scale: float) -> TrivialResult:
    return TrivialResult(runs=runs, seed=seed, total=scale * runs + seed)


EXPERIMENT = Experiment(
    name="trivial",
    help="a one-file experiment",
    compute=run,
    params=(ParamSpec("scale", "float", 2.0, "multiplier", lo=0),),
    default_runs=3,
)
"""


def test_one_new_module_is_one_new_experiment(
    tmp_path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "trivial_experiment.py").write_text(textwrap.dedent(TRIVIAL))
    monkeypatch.setattr(experiments, "__path__", [*experiments.__path__, str(tmp_path)])
    monkeypatch.delitem(sys.modules, "noisevar.experiments.trivial_experiment", raising=False)
    try:
        found = discover()
        assert "trivial" in found
        assert found["trivial"].run(seed=1).to_dict() == {"runs": 3, "seed": 1, "total": 7.0}
        code, out, err = _cli(capsys, "experiment", "trivial", "--scale", "0.5", "--format", "json")
        assert code == 0, err
        assert json.loads(out) == {"runs": 3, "seed": 0, "total": 1.5}
        code, out, err = _cli(capsys, "experiment", "trivial", "--scale", "-1")
        assert code == 2 and "scale=-1.0 is out of range" in err
    finally:
        sys.modules.pop("noisevar.experiments.trivial_experiment", None)
