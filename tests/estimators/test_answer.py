"""The record's one answer (noisevar.estimators.answer) and the same-quantity check (issue 28)."""

from __future__ import annotations

import numpy as np

import noisevar
from noisevar.estimators.answer import record_answer
from noisevar.estimators.redundant import same_quantity_notes


def test_a_still_start_then_motion_quotes_both_rs_and_warns() -> None:
    rng = np.random.default_rng(1)
    z = 0.15 * rng.standard_normal(6000)
    k = np.arange(2000, 6000)
    z[2000:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
    est = noisevar.estimate(z)
    ans = record_answer(est)
    assert ans.level_varies and ans.severity == "warning"
    assert ans.variance == est.variance and ans.where == "the whole record"
    assert "Its still regimes alone" in ans.sentence("m")
    still = record_answer(est, "still")
    assert still.variance == est.still.variance and still.where == "its still regimes"
    assert "m²" in still.sentence("m")


def test_white_noise_is_one_plain_answer() -> None:
    est = noisevar.estimate(np.random.default_rng(2).standard_normal(4000))
    ans = record_answer(est)
    assert not ans.level_varies and ans.severity == "ok" and ans.still_variance is None
    assert ans.sentence().startswith("R = ") and "still" not in ans.sentence()


def test_same_quantity_notes() -> None:
    rng = np.random.default_rng(0)
    n = 5000
    s = np.cumsum(rng.normal(size=n))
    same = np.column_stack([s + rng.normal(0, 1, n), s + rng.normal(0, 2, n)])
    assert same_quantity_notes(same, ["a", "b"], [1.0, 4.0], [1.1, 3.9]) == []
    k = np.arange(n)
    axes = np.column_stack([np.sin(k / 50), np.cos(k / 30), 9.8 + 0 * k]) + rng.normal(
        0, 0.1, (n, 3)
    )
    notes = same_quantity_notes(axes, ["X", "Y", "Z"], [0.01] * 3, [0.05, 0.1, 0.01])
    assert any("X - Y varies" in t for t in notes)
    assert any("X and Z differ in level" in t for t in notes)
    assert any("Y's redundant R is 10x" in t for t in notes)
