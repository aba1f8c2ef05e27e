"""The fleet report's regime choice: each row's whole-record R or its still regimes' R."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from noisevar.batch.fleet import fleet_report
from noisevar.errors import NoisevarError


def _table(still_dtype: str | None = None) -> pd.DataFrame:
    """20 units of std 1; unit03 moved (std 5 over its record, 1 in its still stretch)."""
    std = np.full(20, 1.0) + np.linspace(-0.05, 0.05, 20)
    still = [None] * 20
    std[3], still[3] = 5.0, 1.0
    frame = pd.DataFrame(
        {
            "file": [f"/fleet/unit{i:02d}.csv" for i in range(20)],
            "channel": "ax",
            "std": std,
            "variance": std**2,
            "still_variance": still,
        }
    )
    if still_dtype:
        frame["still_variance"] = frame["still_variance"].astype(still_dtype)
    return frame


@pytest.mark.parametrize("dtype", [None, "Float64"])
def test_the_still_regimes_unflag_a_sensor_that_moved(dtype) -> None:
    frame = _table(dtype)
    whole = fleet_report(frame)
    assert whole.regimes == "all" and [s.file[-10:] for s in whole.flagged] == ["unit03.csv"]
    still = fleet_report(frame, regimes="still")
    assert still.regimes == "still" and not still.flagged
    by_file = {s.file[-10:]: s.std for s in still.sensors}
    assert by_file["unit03.csv"] == 1.0 and by_file["unit05.csv"] == pytest.approx(std5(frame))
    assert still.to_dict()["regimes"] == "still"


def std5(frame: pd.DataFrame) -> float:
    return float(frame["std"].iloc[5])


def test_a_table_without_still_columns_and_a_bad_choice() -> None:
    frame = _table().drop(columns=["still_variance"])
    assert fleet_report(frame, regimes="still").sensors == fleet_report(frame).sensors
    with pytest.raises(NoisevarError, match="regimes must be one of"):
        fleet_report(frame, regimes="moving")


def test_a_row_with_no_still_r_is_left_out_not_given_its_whole_r() -> None:
    """A row whose level varies with no still variance (its still stretches too short):
    the still comparison never puts its whole record's R in place of a still one (issue 26)."""
    frame = _table()
    frame["flag_level_varies"] = False
    frame.loc[3, "flag_level_varies"] = True
    frame.loc[7, ["std", "flag_level_varies"]] = [6.0, True]  # moved, no still R
    still = fleet_report(frame, regimes="still")
    assert "unit07.csv" not in {s.file[-10:] for s in still.sensors}
    assert still.n_errors == 0 and any("1 rows have no still R" in n for n in still.notes)
    assert "unit07.csv" in {s.file[-10:] for s in fleet_report(frame).flagged}
