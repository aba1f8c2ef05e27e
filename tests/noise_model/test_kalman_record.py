"""The Kalman fit's r beside the record's answer (issue 26 item 5: one record, one answer)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import noisevar
from noisevar.noise_model import fit_kalman
from noisevar.noise_model.kalman_record import USE_STILL

N = 4000


def track(seed: int, kind: str = "white") -> np.ndarray:
    """A random walk (step std 0.1) seen in unit white noise, and one departure from it."""
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.normal(scale=0.1, size=N))
    e = rng.normal(size=N)
    if kind == "level":  # the noise 3x louder in the second half
        e[N // 2 :] *= 3.0
    if kind == "differenced":
        e = np.diff(rng.normal(size=N + 1)) / np.sqrt(2.0)
    if kind == "vibration":
        x = x + np.sin(2 * np.pi * 0.23 * np.arange(N))
    return x + e


def test_white_noise_on_a_random_walk_agrees_and_breaks_nothing() -> None:
    z = track(0)
    fit, est = fit_kalman(z, model="rw"), noisevar.estimate(z)
    c = fit.record
    assert c is not None and c.agrees and c.broken == () and c.advice == ()
    assert (c.variance, c.ci95) == (est.variance, est.ci95) and c.where == "the whole record"
    assert c.ratio == pytest.approx(fit.r / est.variance) and c.use == est.variance
    assert fit.notes[-1] == c.note and c.note.startswith("r agrees with the record's R")


def test_a_level_that_varies_names_the_still_r_to_use_and_what_to_do() -> None:
    z = track(1, "level")
    est = noisevar.estimate(z)
    whole = fit_kalman(z, model="rw").record
    assert whole.agrees and whole.broken[0].startswith("one noise level")
    assert whole.use == est.still.variance and whole.use < whole.variance / 3
    assert USE_STILL in whole.advice and "the R to use is its still regimes'" in whole.note
    still = fit_kalman(z, model="rw", regimes="still").record
    assert still.where == "its still regimes" and still.variance == est.still.variance
    assert still.agrees and still.broken == ()


def test_a_vibration_puts_r_outside_and_says_why() -> None:
    fit = fit_kalman(track(2, "vibration"), model="rw")
    c = fit.record
    assert not c.agrees and c.ratio > 1.2 and "outside its interval" in c.note
    assert "oscillation at 0.23" in c.broken[0] and "notch" in c.advice[0]


def test_differenced_noise_is_named() -> None:
    c = fit_kalman(track(3, "differenced"), model="rw").record
    assert c.agrees and "differenced" in c.broken[0] and "MA(1)" in c.advice[0]


def test_the_check_does_not_depend_on_the_unit() -> None:
    z = track(2, "vibration")
    a, b = fit_kalman(z, model="cv").record, fit_kalman(z * 1e7, model="cv").record
    assert b.variance == pytest.approx(1e14 * a.variance, rel=1e-9)
    assert (a.agrees, a.broken) == (b.agrees, b.broken)
    assert b.ratio == pytest.approx(a.ratio, rel=1e-6)


def test_to_dict_and_the_cli_carry_it(tmp_path) -> None:
    z = track(1, "level")
    fit = fit_kalman(z, model="rw")
    out = json.loads(json.dumps(fit.to_dict()))["record"]
    assert out["agrees"] is True and out["use"] == pytest.approx(fit.record.use)
    assert out["broken"] == list(fit.record.broken) and out["note"] == fit.record.note
    path = tmp_path / "z.csv"
    np.savetxt(path, z)

    def cli(*extra: str) -> str:
        cmd = [sys.executable, "-m", "noisevar", "fit", str(path), "--model", "rw"]
        return subprocess.run(
            [*cmd, "--rate", "10", *extra], capture_output=True, text=True, check=True
        ).stdout

    said = json.loads(cli("--format", "json"))["record"]
    assert said["use"] == pytest.approx(fit.record.use) and said["agrees"] is True
    table = cli("--unit", "m")
    assert "record R  " in table and "inside its interval" in table
    assert f"R to use  {noisevar.format.eng(fit.record.use)} m²" in table
    assert "not met   the fit's assumption of one noise level (it varies" in table


def test_a_given_q_and_r_are_checked_too() -> None:
    from noisevar.noise_model import evaluate_kalman

    z = track(1, "level")
    fit = fit_kalman(z, model="rw")
    given = evaluate_kalman(z, "rw", fit.q, fit.r)
    assert given.record == fit.record and given.notes[-1] == fit.record.note
    small = evaluate_kalman(z, "rw", fit.q, fit.record.use).record  # the still R, given
    assert not small.agrees and small.ratio == pytest.approx(fit.record.use / fit.record.variance)
