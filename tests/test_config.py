"""noisevar.config: the tuned-parameter JSON the dashboard exports and the CLI reads."""

from __future__ import annotations

import json

import pytest

import noisevar
from noisevar.config import (
    config_to_json,
    load_config,
    params_to_config,
    parse_config,
    split_config,
    validate_config,
)
from noisevar.errors import NoisevarError


@pytest.fixture(scope="module")
def z():
    return noisevar.generate("fast-slow", n=4000, seed=3).measured


def test_round_trip_reproduces_the_estimate(z, tmp_path):
    est = noisevar.estimate(z, method="somd", h_smooth=[1.5e-5, 3e-5], window=50, gamma_amp=0.6)
    cfg = params_to_config(est.params["method"], est.params)
    assert cfg["method"] == "somd"
    assert list(cfg)[0] == "method"
    path = tmp_path / "tuned.json"
    path.write_text(config_to_json(cfg))
    loaded = load_config(path)
    assert loaded == cfg
    again = noisevar.estimate(z, **loaded)
    assert again.variance == est.variance
    method, params = split_config(loaded)
    assert method == "somd" and "method" not in params


def test_every_method_params_round_trip(z):
    for m in noisevar.methods():
        if m == "somd-redundant":
            continue
        est = noisevar.estimate(z, method=m)
        cfg = params_to_config(m, est.params)
        assert json.loads(config_to_json(cfg)) == cfg


def test_none_values_mean_default():
    assert validate_config({"method": "somd", "h_track": None}) == {"method": "somd"}


@pytest.mark.parametrize(
    ("cfg", "fragment"),
    [
        ([1, 2], "JSON object"),
        ({"window": 40}, "no 'method'"),
        ({"method": "magic"}, "unknown method"),
        ({"method": "somd", "windw": 40}, "unknown config key 'windw'"),
        ({"method": "somd", "window": 4}, "'window': window must be an integer of at least 8"),
        ({"method": "somd", "window": 40.5}, "integer"),
        ({"method": "somd", "window": True}, "must be a number"),
        ({"method": "somd", "h_smooth": 0.9}, "stable range"),
        ({"method": "somd", "h_smooth": []}, "empty"),
        ({"method": "somd", "gamma_amp": 0}, "out of range"),
        ({"method": "somd", "gamma_ang": 95}, "out of range"),
        ({"method": "somd", "angle": "degrees"}, "angle"),
        ({"method": "somd", "select": "yes"}, "true or false"),
        ({"method": "auto", "span": 20}, "odd"),
        ({"method": "auto", "order": 9}, "out of range: it must be in [1, 6]"),
        ({"method": "auto", "trim": 0.5}, "out of range"),
        ({"method": "somd", "window": "40"}, "must be a number"),
        ({"method": "rice", "window": 40}, "not a parameter of method 'rice'"),
        ({"method": "somd-redundant", "reference": [1, 2, 3]}, "data, not a parameter"),
    ],
)
def test_invalid_configs_are_refused_naming_the_key(cfg, fragment):
    with pytest.raises(NoisevarError) as info:
        validate_config(cfg)
    assert fragment in str(info.value)


def test_bad_json_and_missing_file(tmp_path):
    with pytest.raises(NoisevarError, match="not valid JSON"):
        parse_config("{method: somd}")
    with pytest.raises(NoisevarError, match="no such config file"):
        load_config(tmp_path / "nope.json")
