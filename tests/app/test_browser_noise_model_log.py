"""The Noise model page in a real browser with a log's two topics loaded (issues 27 and 30).

A PX4 ULog written by pyulog's writer (gyroscope FIFO at 800 Hz, accelerometer FIFO at
400 Hz) is uploaded on the Signal page, its gyroscope FIFO picked as the signal and its
accelerometer FIFO beside it; on the Noise model page both sensors' columns are chosen.
The whole page (Streamlit scrolls an inner container: screen by screen, stitched) is
checked by the rules of ``test_browser_pages.py`` (nothing cut, no overlap, every axis
titled, curves drawn in order) at 1400 and 390 px, and saved to
``test-artifacts/browser/pages/``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "logs"))

from logfiles import write_ulog_imu_fifos  # noqa: E402
from test_browser_pages import KNOWN, VIEWPORTS, _settle, problems, whole_page  # noqa: E402

PX4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"
GYRO, ACCEL = "sensor_gyro_fifo", "sensor_accel_fifo"


@pytest.fixture(scope="module")
def fifo_log(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("browser_log") / "flight.ulg"
    write_ulog_imu_fifos(path, PX4, seconds=20.0, rates=(800.0, 400.0), seed=3)
    return path


def _pick(page, testid: str, label: str, options: list[str]) -> None:
    """Type each option into a Streamlit selectbox or multiselect labelled ``label``."""
    box = page.locator(f'[data-testid="{testid}"]', has_text=label).first
    for option in options:
        box.locator("input").first.click()
        page.keyboard.type(option)  # the list is virtual: only matching options are drawn
        said = re.escape(option).replace("/", r"\/")  # playwright passes the regex as /.../
        page.get_by_role("option", name=re.compile(f"^{said}( |$)")).first.click()
        _settle(page)
    page.keyboard.press("Escape")


def _load_two_topics(page, server: str, path: Path) -> None:
    page.goto(f"{server}/Signal")
    _settle(page)
    page.locator('[data-testid="stFileUploader"] input[type=file]').first.set_input_files(str(path))
    page.wait_for_function("() => document.body.innerText.includes('flight.ulg')", timeout=120_000)
    _settle(page)
    page.get_by_role("tab", name="Upload").click()  # the topic pickers are on its tab
    page.get_by_text("More topics").first.wait_for(timeout=60_000)
    _settle(page)
    _pick(page, "stSelectbox", "Topic", [GYRO])
    _pick(page, "stMultiSelect", "More topics", [ACCEL])
    main = page.locator('[data-testid="stMain"]')
    assert main.locator('[data-testid="stException"]').count() == 0
    page.locator('[data-testid="stSidebarNav"]').get_by_text("Noise model", exact=True).click()
    page.wait_for_url("**/Noise_model**", timeout=30_000)
    _settle(page)
    main.get_by_text("Filter configs: Kalibr imu.yaml and every consumer").click()  # expander
    _settle(page)
    # the pickers start on the columns in a sensor's unit (units.sensor_columns): the FIFOs'
    for label, topic in (("Gyroscope columns", GYRO), ("Accelerometer columns", ACCEL)):
        box = main.locator('[data-testid="stMultiSelect"]', has_text=label).first
        chosen = box.inner_text()
        _pick(
            page,
            "stMultiSelect",
            label,
            [f"{topic}/{a}" for a in "xyz" if f"{topic}/{a}" not in chosen],
        )


def test_noise_model_page_with_a_logs_two_topics(server, browser, fifo_log):
    """Loaded once at the desktop size (the sidebar open), then drawn at each size."""
    ctx = browser.new_context(viewport=VIEWPORTS["desktop"])
    page = ctx.new_page()
    _load_two_topics(page, server, fifo_log)
    main = page.locator('[data-testid="stMain"]')
    text = main.inner_text()
    assert main.locator('[data-testid="stException"]').count() == 0
    errors = main.locator('[data-testid="stAlertContentError"]')
    assert errors.count() == 0, errors.first.inner_text()
    assert f"{GYRO} 800 Hz, {ACCEL} 400 Hz" in text  # each topic's own rate
    assert "K from the composite fit" in text  # which fit gives the files' K
    assert main.get_by_text("px4_ekf2.params").count() >= 1  # the downloads are drawn
    found = []
    for size, viewport in VIEWPORTS.items():
        page.set_viewport_size(viewport)  # the same session, drawn at this size
        _settle(page)
        shot = whole_page(page, f"{size}-noise-model-two-topics")
        found += problems(shot, f"{size} Noise model with two topics")
    ctx.close()
    print(f"\n{len(found)} findings:\n" + "\n".join(found))
    new = [f for f in found if not any(re.search(k, f) for k in KNOWN)]
    assert not new, f"{len(new)} problems:\n" + "\n".join(new)
