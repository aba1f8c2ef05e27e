"""Empty cells are refused with one error type a caller can name its own way to drop them by."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.errors import EmptyCells, NoisevarError
from noisevar.io import load_table, pick_column


def test_empty_cells_are_refused_as_empty_cells(tmp_path):
    path = tmp_path / "gaps.csv"
    rows = [f"{i},{np.sin(i / 7):.4f}" for i in range(300)]
    rows[4] = "4,"
    path.write_text("t,x\n" + "\n".join(rows) + "\n")
    table = load_table(path)
    with pytest.raises(EmptyCells, match="drop-nonfinite"):
        pick_column(table, "x")
    assert pick_column(table, "x", drop_nonfinite=True).size == 299


def test_an_analysis_that_needs_every_sample_is_not_told_to_drop():
    """Where the fix is not to drop (an Allan deviation needs every sample in its place), the
    refusal is a plain NoisevarError, so no surface offers a checkbox that would be wrong."""
    from noisevar.io import table_from_arrays

    table = table_from_arrays("t", {"x": np.r_[np.ones(50), np.nan, np.ones(50)]})
    with pytest.raises(NoisevarError) as err:
        pick_column(table, "x", fix="keep every sample")
    assert not isinstance(err.value, EmptyCells)


def test_estimate_refuses_nan_as_empty_cells():
    z = np.r_[np.random.default_rng(0).normal(size=500), np.nan]
    with pytest.raises(noisevar.EmptyCells):
        noisevar.estimate(z)
