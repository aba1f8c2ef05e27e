"""A record whose level varies and whose R is the R to use (its still stretches read R's
level) has R in its row's still cells, so a batch table's still comparison keeps it, as
``regimes="still"`` quotes R everywhere else (docs/algorithms.md §E1 *The still set*)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

import noisevar
from noisevar.estimators.regimes import choose_variances, variance_for
from noisevar.estimators.still_set import SAME, kept_still
from tests.estimators.rest_records import rest_in_motion


def _same_level_estimate():
    """A rest inside motion whose still R reads just over R with R inside its interval
    (gtsam's legged robot gyr_x with 2 samples dropped): R is the R to use."""
    est = noisevar.estimate(rest_in_motion(4, 564, 242, 101))
    r = est.variance
    just_over = replace(est.still, variance=1.02 * r, ci95=(0.6 * r, 2.0 * r))
    still, diag = kept_still(est.diagnostics, r, just_over)
    assert still is None and diag.quiet.source == SAME and diag.level_varies
    return replace(est, still=None, diagnostics=diag)


def test_a_row_at_rs_level_has_r_in_its_still_cells() -> None:
    est = _same_level_estimate()
    row = est.to_row()
    assert row["still_variance"] == est.variance
    assert (row["still_ci95_low"], row["still_ci95_high"]) == est.ci95
    assert row["still_note"].startswith("no separate still R")


def test_a_batch_table_compares_it_on_its_still_r() -> None:
    est = _same_level_estimate()
    frame = pd.DataFrame([est.to_row()])
    chosen = choose_variances(
        frame["variance"], frame["still_variance"], "still", frame["flag_level_varies"]
    )
    assert np.isfinite(chosen[0]) and chosen[0] == variance_for(est, "still")


def test_a_record_with_a_still_r_apart_keeps_it() -> None:
    est = noisevar.estimate(rest_in_motion(4, 564, 242, 101))
    assert est.still is not None
    assert est.to_row()["still_variance"] == est.still.variance
