"""The other still levels' table in a real browser, whole page (issue 26 item 5, pages26c).

A record resting at two levels (a short rest at the floor, a long one at 2.2x) is uploaded
on the Signal page; the Noise model page then shows its regime warning and, under it, the
other still level as a small table. The whole page is checked by the rules of
``test_browser_pages.py`` (nothing cut, no overlap, every axis titled) at 1400 and 390 px
and saved to ``test-artifacts/browser/pages/``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from test_app_still_levels import RATE, postures  # noqa: E402
from test_browser_pages import (  # noqa: E402
    KNOWN,
    VIEWPORTS,
    _settle,
    problems,
    upload_then_open,
    whole_page,
)

from noisevar.estimators.answer import STILL_LEVELS_NOTE  # noqa: E402


@pytest.fixture(scope="module")
def record_csv(tmp_path_factory) -> Path:
    z = postures(0)
    path = tmp_path_factory.mktemp("browser_levels") / "postures.csv"
    pd.DataFrame({"t": np.arange(z.size) / RATE, "gyro": z}).to_csv(path, index=False)
    return path


def test_noise_model_page_with_two_still_levels(server, browser, record_csv) -> None:
    ctx = browser.new_context(viewport=VIEWPORTS["desktop"])
    page = ctx.new_page()
    main = upload_then_open(page, server, record_csv, "Noise model", "Noise_model")
    main.get_by_text(STILL_LEVELS_NOTE[:60]).first.wait_for(timeout=60_000)
    note = main.locator('[data-testid="stCaptionContainer"]', has_text=STILL_LEVELS_NOTE[:60])
    table = note.first.locator("xpath=following::*[@data-testid='stDataFrame'][1]")
    assert table.count() == 1 and table.is_visible()
    found = []
    for size, viewport in VIEWPORTS.items():  # the same page, then at a phone's size
        page.set_viewport_size(viewport)
        _settle(page)
        shot = whole_page(page, f"{size}-Noise_model-still-levels")
        found += problems(shot, f"{size} Noise model")
    ctx.close()
    new = [f for f in found if not any(re.search(k, f) for k in KNOWN)]
    assert not new, f"{len(new)} problems:\n" + "\n".join(new)
