"""Figures of the temperature model, the datasheet overlay and a composite model (§E9)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from noisevar.figures.noise_model import (
    bias_temperature_figure,
    composite_figure,
    datasheet_figure,
    warmup_figure,
)
from noisevar.noise_model import inertial_noise, temperature_model
from noisevar.noise_model.datasheet import datasheet_terms
from noisevar.noise_model.simulate import simulate_inertial, simulate_thermal


def test_bias_and_warmup_figures_draw_the_model() -> None:
    rate = 10.0
    temp = np.linspace(15.0, 35.0, 20_000)
    y = simulate_thermal(
        temp, rate, polynomial=(0.0, 1e-3), warmup=(0.02, 60.0), random_walk=1e-3, seed=3
    )
    m = temperature_model(y, temp, rate, unit="deg/s", bootstrap=20)
    fig = bias_temperature_figure(m)
    assert [t.name for t in fig.data][-1] == f"bias(T), order {m.order}"
    assert fig.layout.yaxis.title.text == "bias (deg/s)"
    warm = warmup_figure(m)
    assert warm.data[-1].name.startswith("A exp(-t/τ)")


def test_datasheet_overlay_is_the_closed_form_deviation() -> None:
    y = simulate_inertial(20_000, 100.0, random_walk=0.005, seed=1)
    fit = inertial_noise(y, 100.0, unit="deg/s")
    sheet = datasheet_terms((0.3, "°/√h"), (5.0, "°/h"), "deg/s")
    fig = datasheet_figure(fit.allan, sheet, fit=fit, unit="deg/s")
    trace = fig.data[-1]
    assert trace.name.startswith("datasheet: ARW 0.3")
    want = np.sqrt((0.3 / 60.0) ** 2 / trace.x + 2 * np.log(2) / np.pi * (5.0 / 3600.0) ** 2)
    assert np.allclose(trace.y, want, rtol=1e-12)


@dataclass(frozen=True)
class _Composite:
    """What composite_figure reads of an ImuModel (noisevar.noise_model.gmwm)."""

    model: str = "WN+RW"
    ci: float = 0.683
    robust: bool = False
    scales: np.ndarray = field(default_factory=lambda: np.geomspace(0.01, 100.0, 10))

    @property
    def wv(self) -> np.ndarray:
        return self.model_wv(self.scales)

    @property
    def wv_interval(self) -> tuple[np.ndarray, np.ndarray]:
        return 0.8 * self.wv, 1.2 * self.wv

    def components(self, t: np.ndarray) -> dict[str, np.ndarray]:
        return {"WN": 1e-4 / t, "RW": 1e-6 * t}

    def model_wv(self, t: np.ndarray) -> np.ndarray:
        return sum(self.components(t).values())


def test_composite_figure_draws_each_component_and_the_sum() -> None:
    fig = composite_figure(_Composite(), unit="rad/s")
    names = [t.name for t in fig.data]
    assert names[1:] == ["Haar wavelet variance", "WN", "RW", "sum: WN+RW"]
    assert np.allclose(fig.data[-1].y, fig.data[2].y + fig.data[3].y)
