"""What a record is too short to check is neither held nor failed (issue 26: every estimate
says what it assumes and whether the record satisfies it). The Compare page's table read
"everything it assumes holds on this record" (45 samples) or "it states no assumption about
the noise" (45 samples split at a gap, pymavlink's test.BIN) beside a verdict saying the
record was too short to check whether the noise is white, its level or its tails."""

from __future__ import annotations

import numpy as np

import noisevar as nv
from noisevar.diagnostics.panel import assumption_rows


def test_a_short_record_says_what_it_could_not_check():
    z = np.random.default_rng(0).normal(size=45)
    rows = {r["method"]: r for r in assumption_rows(
        [nv.estimate(z, method=m) for m in ("auto", "mad-diff")])}  # fmt: skip
    for r in rows.values():
        assert r["meaning"].startswith("too few samples to check"), r
        assert "tails" in r["meaning"]
    assert "Gaussian tails" not in rows["mad-diff"]["holds"]  # untested, not held


def test_no_diagnostics_is_not_no_assumption():
    z = np.random.default_rng(1).normal(size=45)
    t = np.r_[np.arange(20), np.arange(25) + 30.0]  # a gap: segments too short to diagnose
    est = nv.estimate(z, t=t)
    assert est.diagnostics is None
    (row,) = assumption_rows([est])
    assert "states no assumption" not in row["meaning"]
    assert row["meaning"].startswith("too few samples to check whether the noise is white")


def test_a_long_record_is_checked_whole():
    z = np.random.default_rng(2).normal(size=3000)
    (row,) = assumption_rows([nv.estimate(z, method="mad-diff")])
    assert row["meaning"] == "everything it assumes holds on this record"
    assert "Gaussian tails" in row["holds"]
