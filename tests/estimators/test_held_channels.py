"""Channels that hold one value: a trigger (refused, systole's Stim, audit6), rare flips."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import noisevar
from noisevar.errors import NoisevarError


def _trigger(n: int = 100_000, pulses: int = 10, seed: int = 0) -> np.ndarray:
    z = np.zeros(n)
    z[np.random.default_rng(seed).choice(n, pulses, replace=False)] = 5.0
    return z


def test_a_trigger_channel_is_refused_in_one_sentence() -> None:
    # was: R 0.0025 (ci95 0.00248-0.00252), the pulses' alone, and no verdict
    with pytest.raises(NoisevarError, match="holds one value but for 10 samples"):
        noisevar.estimate(_trigger())


def test_the_cli_refuses_it_with_exit_2(tmp_path) -> None:
    path = tmp_path / "stim.csv"
    np.savetxt(path, _trigger(20_000, 4, 1), header="stim", comments="")
    out = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(path)],
        capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "trigger or event channel" in out.stderr


def test_a_held_sensor_with_flips_keeps_its_estimate() -> None:
    rng = np.random.default_rng(2)
    z = 100 + (rng.random(20_000) < 0.02).astype(float)  # one-step flips: rounding, not pulses
    assert noisevar.estimate(z).variance > 0


def test_rare_one_step_flips_are_rounding_not_a_changing_level() -> None:
    rng = np.random.default_rng(0)
    z = 100 + (rng.random(20_000) < 0.003).astype(float)
    v = noisevar.estimate(z).verdict
    # was: "the noise level changes along the record: ... no stretch of it is measurably
    # quieter" (blocks with and without a flip)
    assert v.startswith("white noise under half a step on a grid of step 1"), v


def test_a_constant_channel_is_refused_saying_what_to_do():
    """real_audit8: a price file's `OpenInt` (always 0) was refused without a hint."""
    with pytest.raises(NoisevarError, match="give a channel that varies"):
        noisevar.estimate(np.zeros(500))
