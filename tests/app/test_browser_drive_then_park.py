"""The Noise panel's level profile of a record that drives, then parks, in a real browser.

A 300-fix GNSS position drives over its first half and parks (``park_records``); the jump
detector leaves the drive out, so the level profile shades it as moving too fast to
measure (``LevelProfile.unmeasured``). The Estimator page's Noise panel is opened on its
"Level profile" tab, and the whole page is checked by the rules of ``test_browser_pages.py``
(nothing cut, no overlap, every axis titled) at 1400 and 390 px, saved to
``test-artifacts/browser/pages/``.
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

from test_browser_pages import (  # noqa: E402
    KNOWN,
    VIEWPORTS,
    _settle,
    problems,
    upload_then_open,
    whole_page,
)

from tests.diagnostics.park_records import drive_then_park  # noqa: E402

#: The shaded stretch's label on the level profile (noisevar.figures.noise).
SHADE = "moving too fast to measure"


@pytest.fixture(scope="module")
def record_csv(tmp_path_factory) -> Path:
    z = drive_then_park(3, 300, 5.0, True)
    path = tmp_path_factory.mktemp("browser_park") / "drive_park.csv"
    pd.DataFrame({"t": np.arange(z.size), "north_m": z}).to_csv(path, index=False)
    return path


def test_noise_panel_shades_the_drive(server, browser, record_csv) -> None:
    ctx = browser.new_context(viewport=VIEWPORTS["desktop"])
    page = ctx.new_page()
    main = upload_then_open(page, server, record_csv, "Estimator", "Estimator")
    # the page opens on the paper's somd, which needs 332 samples here: choose auto
    main.locator('[data-testid="stSelectbox"]', has_text="Method").first.click()
    page.get_by_role("option", name="auto", exact=True).click()
    _settle(page)
    main.get_by_text("Noise: distribution, autocorrelation, level along the record").click()
    _settle(page)
    main.get_by_role("tab", name="Level profile").click()
    _settle(page)
    main.get_by_text(SHADE).first.wait_for(timeout=60_000)  # the shaded stretch's label
    assert main.locator(".js-plotly-plot .shapelayer path").count() >= 1
    found = []
    for size, viewport in VIEWPORTS.items():  # the same page, then at a phone's size
        page.set_viewport_size(viewport)
        _settle(page)
        shot = whole_page(page, f"{size}-Estimator-drive-then-park")
        found += problems(shot, f"{size} Estimator")
    assert main.locator('[data-testid="stException"]').count() == 0
    ctx.close()
    new = [f for f in found if not any(re.search(k, f) for k in KNOWN)]
    assert not new, f"{len(new)} problems:\n" + "\n".join(new)
