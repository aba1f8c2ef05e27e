"""A held staircase (audit 11: GENEActiv's temperature, 0.1 °C values held for hundreds of
samples) is refused saying so, with the R its grid gives, not "try another method"."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.cli import main


def _staircase(seed: int) -> np.ndarray:
    """A warming temperature read every 300 samples to 0.1 °C and held in between, 8400
    samples at 50 Hz (the sensor's noise far under the step)."""
    rng = np.random.default_rng(seed)
    reads = 28.5 + 3.0 * np.linspace(0.0, 1.0, 28) + 0.01 * rng.normal(size=28)
    return np.repeat(np.round(reads, 1), 300)


@pytest.mark.parametrize("seed", [0, 1])
def test_python_names_the_grid_and_the_r_to_use(seed) -> None:
    with pytest.raises(noisevar.NoisevarError) as err:
        noisevar.estimate(_staircase(seed))
    said = str(err.value)
    # was: "... (not positive: the noise is below the method's resolution ...): try another
    # method such as 'rice'" (whose R would be the steps')
    assert "held on a grid of step 0.1" in said and "lsb²/12 = 0.0008333" in said
    assert "rice" not in said and "\n" not in said


def test_the_cli_refuses_with_the_same_one_line(tmp_path, capsys) -> None:
    z = _staircase(2)
    path = tmp_path / "temp.csv"
    np.savetxt(path, z, header="temperature", comments="", fmt="%.1f")
    with pytest.raises(noisevar.NoisevarError) as err:
        noisevar.estimate(z)
    for fmt in ("json", "csv"):
        assert main(["estimate", str(path), "--format", fmt]) == 2
        out = capsys.readouterr()
        assert out.err.strip() == f"noisevar: error: {err.value}"
        assert "held on a grid of step 0.1" in out.err  # was: "try another method"
        assert not out.out
