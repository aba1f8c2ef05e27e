"""Other still levels as data: the rows pages draw and the exports write (issue 26 item 5)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import noisevar
from noisevar import synth
from noisevar.config import config_to_json, params_to_config, record_value
from noisevar.estimators.answer import (
    STILL_LEVEL_COLUMNS,
    record_answer,
    row_still_levels,
    still_level_rows,
)


def _postures(seed: int, raised: float) -> np.ndarray:
    """Two still levels, motion between (:func:`noisevar.synth.postures`)."""
    return synth.postures(raised, rng=seed)


@pytest.fixture(scope="module")
def est():
    e = noisevar.estimate(_postures(0, 2.2))
    assert len(e.diagnostics.other_still) == 1 and e.still is not None
    return e


def test_rows_say_what_the_verdict_says(est) -> None:
    (x,) = est.diagnostics.other_still
    (row,) = record_answer(est).still_level_rows("m")
    assert list(row) == list(STILL_LEVEL_COLUMNS.values())
    c = STILL_LEVEL_COLUMNS
    said = f"{row[c['stretch']]} ({row[c['share']]} of the record) at {row[c['level']]} (ci95 "
    assert said + f"{row[c['ci95']]})" in est.diagnostics.verdict  # one wording
    assert row[c["stretch"]] == f"samples {x.start}-{x.stop}"
    assert row[c["level"]] == f"{x.ratio:.2f}x"
    assert row[c["ci95"]] == f"{x.lo:.2f}-{x.hi:.2f}x"
    assert row[c["variance"]] == noisevar.format.eng(x.ratio * est.still.variance, "m²")


def test_the_table_row_carries_them_and_reads_back(est) -> None:
    row = est.to_row()
    levels = row_still_levels(row["other_still_levels"])
    assert levels == est.diagnostics.other_still  # the same numbers, bit for bit
    z = _postures(0, 2.2)
    frame = noisevar.estimate(np.column_stack([z, z]), axis=0).to_frame()
    n, still = int(frame["n_total"].iloc[0]), float(frame["still_variance"].iloc[0])
    from_frame = row_still_levels(frame["other_still_levels"].iloc[0])
    assert still_level_rows(from_frame, n, still) == record_answer(est).still_level_rows()
    assert "other_still_levels" not in est.to_dict()  # JSON: under diagnostics, once
    assert est.to_dict()["diagnostics"]["other_still_levels"] == json.loads(
        row["other_still_levels"]
    )


BAD_CELLS = [None, float("nan"), "", "not json", "[{}]", "{}", "5", "[5]"]
ONE = {"start": 1, "stop": 9, "ratio": 2.0, "ci95_low": 1.5, "ci95_high": 2.5}
BAD_CELLS += [json.dumps([ONE | {k: v}]) for k, v in [("start", 1e400), ("ratio", "nan"),
              ("ci95_high", float("inf")), ("stop", 0), ("start", -3), ("ratio", [1])]]  # fmt: skip


@pytest.mark.parametrize("bad", BAD_CELLS)
def test_a_missing_or_bad_cell_reads_as_none(bad) -> None:
    assert row_still_levels(bad) == ()


def test_a_good_cell_reads() -> None:
    (x,) = row_still_levels(json.dumps([ONE]))
    assert (x.start, x.stop, x.ratio, x.lo, x.hi) == (1, 9, 2.0, 1.5, 2.5)


def test_one_level_has_no_rows_and_no_export_line() -> None:
    e = noisevar.estimate(_postures(0, 1.0))
    assert record_answer(e).still_level_rows() == []
    assert "other_still_levels" not in record_answer(e).summary()
    assert e.to_row()["other_still_levels"] is None
    assert still_level_rows(e.diagnostics.other_still, 10, None) == []


def test_the_exports_write_them(est) -> None:
    summary = record_answer(est, "still").summary("m")
    text = summary["other_still_levels"]
    (row,) = record_answer(est).still_level_rows("m")
    assert text.startswith(row["Stretch"]) and row["R there"] in text
    cfg = json.loads(config_to_json(params_to_config("auto", {}), record=summary))
    assert cfg["record"]["other_still_levels"] == text
    assert record_value(cfg["record"]) == summary  # a config that carries them reads back
