"""Real-browser test: ``streamlit run app.py`` driven by Debian's Chromium through Playwright.

The test starts the app headless on 127.0.0.1 and a free port, waits for
``/_stcore/health``, then visits every page through the sidebar navigation
and by opening each page's URL directly (a new session: the page must work
when it is the first one a browser opens), and fails on any Streamlit
exception box. Screenshots go to ``test-artifacts/browser/`` (printed).

Needs ``/usr/bin/chromium`` (``apt-get install -y chromium``) and the
``playwright`` Python package; browser downloads are not used
(``executable_path``). Skipped when either is missing.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from dashboard.pages import HOME  # noqa: E402
from dashboard.pages import PAGES as REGISTRY  # noqa: E402
from dashboard.widgets import RUNNING_ICON  # noqa: E402

SHOTS = ROOT / "test-artifacts" / "browser"
#: (sidebar label, URL path) of every page but Home (the registry's, as st.navigation gets it).
PAGES = [(p.title, p.url_path) for p in REGISTRY if p is not HOME]
SIG = "gen:fast-slow;n=6000;seed=0;noise_std=5.0"
#: Seconds without a running script before a page counts as drawn.
QUIET_S = 0.5

# the app's server and the browser are the session's (tests/app/conftest.py): one for every
# browser test module


def _settle(page, timeout: float = 120.0) -> None:
    """Wait until the app has rendered and no script run is in progress."""
    page.wait_for_selector('[data-testid="stAppViewContainer"]', timeout=timeout * 1000)
    page.wait_for_selector("h1", timeout=timeout * 1000)
    deadline = time.time() + timeout
    quiet_since = None
    while time.time() < deadline:
        running = page.locator('[data-testid="stStatusWidget"]').count() > 0
        skeleton = page.locator('[data-testid="stSkeleton"]').count() > 0
        if running or skeleton:
            quiet_since = None
        elif quiet_since is None:
            quiet_since = time.time()
        elif time.time() - quiet_since > QUIET_S:
            return
        time.sleep(0.2)
    raise AssertionError("the app kept running for too long")


def _check(page, name: str) -> None:
    print(f"  {name}: drawn at {time.strftime('%H:%M:%S')}")
    page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=True)
    exceptions = page.locator('[data-testid="stException"]')
    assert exceptions.count() == 0, f"{name}: exception box: {exceptions.first.inner_text()}"


def test_every_page_through_navigation(server, browser):
    ctx = browser.new_context(viewport={"width": 1400, "height": 1000})
    page = ctx.new_page()
    page.goto(server)
    _settle(page)
    _check(page, "00-home")
    page.get_by_role("button", name="Generate the paper's fast-slow signal").click()
    # the rerun may start later than the quiet interval on a loaded machine: wait for its result
    main = page.locator('[data-testid="stMain"]')
    main.get_by_text("Quick estimate").first.wait_for(timeout=120_000)
    _settle(page)
    assert "Quick estimate" in main.inner_text()
    _check(page, "01-home-with-signal")
    nav = page.locator('[data-testid="stSidebarNav"]')
    first = nav.locator('[data-testid="stSidebarNavLink"]').first.inner_text()
    assert first.strip().endswith("Home"), first  # not "app"
    for i, (label, path) in enumerate(PAGES, start=2):
        nav.get_by_text(label, exact=True).first.click()
        page.wait_for_url(f"**/{path}**", timeout=30_000)
        _settle(page)
        _check(page, f"{i:02d}-nav-{path}")
        errors = page.locator('[data-testid="stAlertContentError"]')
        assert errors.count() == 0, f"{label}: {errors.first.inner_text()}"
        _check_budget(page, label)
        _check_metrics_whole(page, label)
    ctx.close()


#: Points and shapes of every drawn Plotly figure (decoded typed arrays included).
FIGURES_JS = """() => Array.from(document.querySelectorAll('.js-plotly-plot')).map(el => ({
  points: (el._fullData || []).reduce((s, t) => s + (t._length || 0), 0),
  shapes: ((el.layout || {}).shapes || []).length,
}))"""
#: Every metric value: its text and whether the box cuts it (ellipsis or overflow).
METRICS_JS = """() => Array.from(document.querySelectorAll('[data-testid="stMetricValue"]'))
  .map(el => {
    const inner = el.querySelector('div') || el;
    const cut = [el, inner].some(e => e.scrollWidth > e.clientWidth + 1
      || getComputedStyle(e).textOverflow === 'ellipsis' && e.scrollWidth > e.clientWidth);
    return {text: el.innerText, full: el.textContent, cut: cut};
  })"""


def _check_budget(page, where: str) -> None:
    for fig in page.evaluate(FIGURES_JS):
        assert fig["points"] <= 10_000 and fig["shapes"] <= 2_000, (where, fig)


def _check_metrics_whole(page, where: str) -> list[dict]:
    metrics = page.evaluate(METRICS_JS)
    for m in metrics:
        assert not m["cut"] and "…" not in m["text"], (where, m)
        assert m["text"].strip() == m["full"].strip(), (where, m)
    return metrics


@pytest.mark.parametrize(("label", "path"), PAGES)
def test_every_page_opened_first_by_url(server, browser, label, path):
    ctx = browser.new_context(viewport={"width": 1400, "height": 1000})
    page = ctx.new_page()
    page.goto(f"{server}/{path}")
    _settle(page)
    assert label in page.inner_text("h1")
    _check(page, f"url-{path}")
    ctx.close()


def test_shared_link_reopens_the_view_and_box_select_picks_a_stretch(server, browser):
    ctx = browser.new_context(viewport={"width": 1400, "height": 1100})
    page = ctx.new_page()
    page.goto(f"{server}/Estimator?sig={SIG}&win=60&est_view=h+scan")
    _settle(page)
    main = page.inner_text('[data-testid="stMain"]')
    assert "Noise variance" in main and "No signal loaded" not in main
    assert "Window m (samples)" in main
    # the link's parameters reached the widgets
    window = page.locator('[data-testid="stSlider"]', has_text="Window m")
    assert window.locator("input").first.get_attribute("value") == "60"
    _check(page, "link-estimator")
    # drag horizontally across the main figure: the box selection estimates that stretch
    chart = page.locator('[data-testid="stPlotlyChart"]').first
    chart.scroll_into_view_if_needed()
    drag = chart.locator(".nsewdrag").first
    box = drag.bounding_box()
    assert box is not None
    y = box["y"] + box["height"] * 0.5
    page.mouse.move(box["x"] + box["width"] * 0.30, y)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] * 0.45, y, steps=8)
    page.mouse.move(box["x"] + box["width"] * 0.60, y, steps=8)
    page.mouse.up()
    page.wait_for_function(
        "() => document.body.innerText.includes('Stretch variance')", timeout=60_000
    )
    _settle(page)
    _check(page, "link-estimator-stretch")
    ctx.close()


def test_monte_carlo_progress_and_cancel(server, browser):
    ctx = browser.new_context(viewport={"width": 1400, "height": 1000})
    page = ctx.new_page()
    page.goto(f"{server}/Compare?sig={SIG}&cmp_tab=Monte+Carlo&mc_runs=3000&mc_n=3000")
    _settle(page)
    page.get_by_role("tab", name="Monte Carlo").click()
    page.get_by_role("button", name="Run Monte Carlo").click()
    page.wait_for_selector('[data-testid="stProgress"]', timeout=60_000)
    page.wait_for_function(
        "() => /Run [0-9]+ of 3000/.test(document.body.innerText)", timeout=60_000
    )
    page.get_by_role("button", name="Cancel").click()
    page.wait_for_function(
        "() => document.body.innerText.includes('Monte Carlo cancelled after')", timeout=60_000
    )
    _settle(page)
    text = page.inner_text('[data-testid="stMain"]')
    assert "of 3000 runs" in text and "done: 3000" not in text
    _check(page, "compare-montecarlo-cancelled")
    ctx.close()


def _upload(page, server: str, path: Path) -> None:
    page.goto(f"{server}/Signal")
    _settle(page)
    page.locator('[data-testid="stFileUploader"] input[type=file]').first.set_input_files(str(path))
    page.wait_for_function(
        f"() => document.body.innerText.includes({path.name!r} )", timeout=120_000
    )
    _settle(page)


def test_small_values_show_whole_in_the_metrics(server, browser, tmp_path):
    """A GPS-clock-like record (phase in seconds, noise 3.6e-9 s): no metric is cut."""
    import numpy as np

    import noisevar
    from dashboard.widgets import fmt

    rng = np.random.default_rng(16)
    n = 6_000
    z = np.cumsum(rng.normal(0.0, 2e-11, n)) + 1.7e-3 + rng.normal(0.0, 3.6e-9, n)
    path = tmp_path / "pps_phase.csv"
    path.write_text("phase\n" + "\n".join(f"{v:.15e}" for v in z))
    ctx = browser.new_context(viewport={"width": 1400, "height": 900})
    page = ctx.new_page()
    _upload(page, server, path)
    assert "pps_phase.csv" in page.inner_text('[data-testid="stSidebar"]')
    _check_metrics_whole(page, "Signal")
    page.locator('[data-testid="stSidebar"]').get_by_text("Estimator", exact=True).click()
    page.wait_for_url("**/Estimator**", timeout=30_000)
    _settle(page)
    _check(page, "small-values-estimator")
    metrics = {m["text"] for m in _check_metrics_whole(page, "Estimator")}
    est = noisevar.estimate(z, "somd", h_smooth=1.5e-5, window=40, track_ratio=30.0)
    assert fmt(est.std) in metrics  # the whole value, e.g. "3.628×10⁻⁹"
    ctx.close()


def test_two_sensor_headlines_are_per_sensor(server, browser):
    ctx = browser.new_context(viewport={"width": 1400, "height": 900})
    page = ctx.new_page()
    page.goto(f"{server}/Two_sensors?sig=sample:two_sensors.csv")
    _settle(page)
    _check(page, "two-sensors")
    values = {}
    for box in page.locator('[data-testid="stMetric"]').all():
        label = box.locator('[data-testid="stMetricLabel"]').inner_text()
        if "noise variance" in label:
            values[label.split(":")[0]] = float(
                box.locator('[data-testid="stMetricValue"]').inner_text()
            )
    assert set(values) == {"sensor_a", "sensor_b"}
    assert 0.75 < values["sensor_a"] < 1.25 and 12 < values["sensor_b"] < 20  # not 17 twice
    ctx.close()


def test_share_link_after_loading_a_config_restores_the_variance(server, browser, tmp_path):
    import json

    cfg = {"method": "somd", "h_smooth": 3e-05, "h_track": 0.0007, "window": 48}
    path = tmp_path / "tuned.json"
    path.write_text(json.dumps(cfg))
    ctx = browser.new_context(viewport={"width": 1400, "height": 1000})
    page = ctx.new_page()
    page.goto(f"{server}/Estimator?sig={SIG}")
    _settle(page)
    before = page.locator('[data-testid="stMetricValue"]').first.inner_text()
    uploader = page.locator('[data-testid="stFileUploader"]', has_text="Load tuned")
    uploader.locator("input[type=file]").set_input_files(str(path))
    page.wait_for_function("() => location.search.includes('h_t=0.0007')", timeout=60_000)
    _settle(page)
    loaded = page.locator('[data-testid="stMetricValue"]').first.inner_text()
    assert loaded != before
    link = page.url
    # somd is the page's default method: Streamlit writes no default into the link
    assert "est_method=somd&" in link + "&" or "est_method=" not in link
    assert "h_t=0.0007" in link and "win=48" in link
    again = ctx.new_page()
    again.goto(link)
    _settle(again)
    assert again.locator('[data-testid="stMetricValue"]').first.inner_text() == loaded
    _check(again, "config-link-reopened")
    ctx.close()


def test_link_from_an_upload_says_so(server, browser, tmp_path):
    path = tmp_path / "mine.csv"
    path.write_text("z\n" + "\n".join(str(0.1 * (i % 7)) for i in range(500)))
    ctx = browser.new_context(viewport={"width": 1400, "height": 900})
    page = ctx.new_page()
    _upload(page, server, path)
    link = page.url
    assert "upload=mine.csv" in link
    fresh = browser.new_context(viewport={"width": 1400, "height": 900}).new_page()
    fresh.goto(link)
    _settle(fresh)
    assert "made from an uploaded file" in fresh.inner_text('[data-testid="stMain"]')
    fresh.context.close()
    ctx.close()


def test_plotly_is_fetched_once_and_the_page_head_takes_no_room(server, browser):
    ctx = browser.new_context(viewport={"width": 1400, "height": 1000}, color_scheme="dark")
    page = ctx.new_page()
    page.goto(f"{server}/Estimator?sig={SIG}")
    _settle(page)
    page.wait_for_selector(".js-plotly-plot", timeout=120_000)
    fetched = page.evaluate(
        "() => performance.getEntriesByType('resource')"
        ".filter(e => e.name.includes('/PlotlyChart.')).map(e => e.name)"
    )
    assert len(fetched) == 1, fetched  # the preload and Streamlit share one module
    head = page.locator("[data-testid='stElementContainer']:has(.nv-head)")
    assert head.count() == 1 and head.bounding_box() is None  # display: none
    # figures sit on the page's own (dark) background: transparent, not plotly's white
    bg = page.evaluate(
        "() => getComputedStyle(document.querySelector('.js-plotly-plot .main-svg'))"
        ".backgroundColor"
    )
    assert bg in ("rgba(0, 0, 0, 0)", "transparent"), bg
    # a still running indicator (issue 29): Streamlit's cycling icon hidden, a word shown
    shown = page.evaluate(
        """(id) => { const d = document.createElement('div');
        d.setAttribute('data-testid', id);
        d.appendChild(document.createElementNS('http://www.w3.org/2000/svg', 'svg'));
        document.body.appendChild(d);
        const r = [getComputedStyle(d.firstChild).display,
                   getComputedStyle(d, '::after').content];
        d.remove(); return r; }""",
        RUNNING_ICON,
    )
    assert shown == ["none", '"Running…"'], shown
    ctx.close()
