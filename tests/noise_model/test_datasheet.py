"""A datasheet's ARW, bias instability and VRW in the data's unit (§E9), in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model.datasheet import datasheet_terms

G = 9.80665


@pytest.mark.parametrize(
    ("density", "bias", "unit", "n", "b"),
    [
        ((0.3, "°/√h"), (5.0, "°/h"), "deg/s", 0.3 / 60.0, 5.0 / 3600.0),
        (
            (0.3, "°/√h"),
            (5.0, "°/h"),
            "rad/s",
            0.3 / 60.0 * math.pi / 180,
            5.0 / 3600.0 * math.pi / 180,
        ),
        ((0.01, "°/s/√Hz"), (1e-4, "rad/s"), "deg/s", 0.01, 1e-4 * 180 / math.pi),
        ((0.06, "m/s/√h"), (40.0, "µg"), "m/s^2", 0.001, 40e-6 * G),
        ((100.0, "µg/√Hz"), (0.04, "mg"), "g", 1e-4, 4e-5),
        ((0.06, "m/s/√h"), (1e-3, "m/s²"), "mg", 0.001 / (1e-3 * G), 1e-3 / (1e-3 * G)),
    ],
)
def test_conversions_in_closed_form(density, bias, unit, n, b) -> None:
    sheet = datasheet_terms(density, bias, unit)
    assert sheet.random_walk == pytest.approx(n, rel=1e-9)
    assert sheet.bias_instability == pytest.approx(b, rel=1e-9)


def test_floor_and_deviation() -> None:
    sheet = datasheet_terms((0.3, "°/√h"), (5.0, "°/h"), "deg/s", floor=True)
    flicker = 2 * math.log(2) / math.pi
    assert sheet.bias_instability == pytest.approx(5.0 / 3600.0 / math.sqrt(flicker), rel=1e-9)
    taus = np.array([1.0, 100.0])
    want = np.sqrt((0.3 / 60.0) ** 2 / taus + (5.0 / 3600.0) ** 2)
    assert sheet.deviation(taus) == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize(
    ("density", "bias", "unit", "match"),
    [
        ((0.3, "°/√h"), (5.0, "°/h"), "u", "data's unit"),
        ((0.06, "m/s/√h"), (5.0, "°/h"), "deg/s", "not a gyroscope's"),
        ((0.3, "furlong"), (5.0, "°/h"), "deg/s", "not known"),
        ((math.nan, "°/√h"), (5.0, "°/h"), "deg/s", "finite"),
    ],
)
def test_bad_datasheet_input(density, bias, unit, match) -> None:
    with pytest.raises(NoisevarError, match=match):
        datasheet_terms(density, bias, unit)
