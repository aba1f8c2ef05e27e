"""fit_kalman's innovations are told light-tailed, not Gaussian, when their kurtosis is
below a Gaussian's sampling interval (a sine, quantised or uniform noise; docs/algorithms.md
§E6 *Tails*): one rule, diagnostics.tails.tails_shape, in Python, the CLI and the page."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.diagnostics.tails import tails_shape
from noisevar.noise_model import fit_kalman
from noisevar.noise_model.kalman_tails import innovation_kurtosis


def _track(seed: int, n: int = 2000) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(np.cumsum(rng.normal(0, 0.3, n))) * 0.1


def test_a_sine_in_the_innovations_is_not_gaussian(tmp_path, capsys) -> None:
    # kurtosis 1.51 was labelled "Gaussian": only kurtosis above 4 counted
    z = _track(3) + 1.4 * np.sin(2 * np.pi * np.arange(2000) / 7.3)
    t = fit_kalman(z)
    assert t.innovations_kurtosis < 2.0
    assert not t.innovations_gaussian and t.innovations_tails == "light"
    assert any(n.startswith("the innovations are light-tailed") for n in t.notes)
    assert t.to_dict()["innovations_tails"] == "light"
    path = tmp_path / "z.csv"
    np.savetxt(path, z, header="z", comments="")
    assert main(["fit", str(path), "--column", "z", "--rate", "1"]) == 0
    assert "NOT Gaussian (kurtosis 1.51; light tails" in capsys.readouterr().out


def test_uniform_noise_is_light_tailed() -> None:
    rng = np.random.default_rng(8)
    t = fit_kalman(np.full(3000, 5.0) + rng.uniform(-1, 1, 3000), "rw")
    assert t.innovations_tails == "light", t.innovations_kurtosis


@pytest.mark.parametrize("n", [20, 50, 200, 2000])
def test_gaussian_samples_are_not_called_light(n) -> None:
    # the bound is a Gaussian b2's sampling interval at n: 0 of 500 records called light
    light = sum(
        tails_shape(n, innovation_kurtosis(np.random.default_rng(s).normal(size=n))) == "light"
        for s in range(500)
    )
    assert light <= 5
