"""A table with missing cells converts to Arrow (no server-side traceback, issue 28)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from dashboard.widgets import blank_missing  # noqa: E402


def test_a_column_of_numbers_and_gaps_converts_to_arrow():
    rows = [
        {"filter": "huber", "magvar": np.float64(-5.008), "n": 3},
        {"filter": "ekf", "magvar": -4.9},
        {"filter": "none", "magvar": None, "n": 4},
    ]
    shown = blank_missing(rows)
    assert [r["magvar"] for r in shown] == ["-5.008", "-4.9", "—"]
    assert [r["n"] for r in shown] == ["3", "—", "4"]
    pa.Table.from_pandas(pd.DataFrame(shown))  # raised ArrowTypeError on mixed columns


def test_a_column_without_gaps_keeps_its_numbers():
    shown = blank_missing([{"x": 1.5, "y": None}, {"x": 2.5, "y": "a"}])
    assert [r["x"] for r in shown] == [1.5, 2.5] and shown[0]["y"] == "—"
