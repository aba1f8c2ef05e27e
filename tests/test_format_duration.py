"""Spans of time written in the unit people read them in."""

from __future__ import annotations

import math

import pytest

from noisevar.format import duration


@pytest.mark.parametrize(
    ("seconds", "text"),
    [
        (31_536_000.0, "365 d"),  # a year of hourly soil moisture read "31.54 Ms"
        (99.57e6, "1,152 d"),
        (19_999.0, "5.555 h"),
        (7_199.0, "120 min"),
        (150.0, "2.5 min"),
        (119.0, "119 s"),
        (0.5, "500 ms"),
        (None, "n/a"),
        (math.nan, "n/a"),
    ],
)
def test_a_span_in_days_hours_minutes_or_seconds(seconds, text):
    assert duration(seconds) == text
