"""AppTest: the Fusion, Robust filter, Carrier tracking and Latency pages (issue 6)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _shown(at: AppTest) -> tuple:
    return tuple((m.label, m.value) for m in at.metric) + tuple(
        str(d.value.to_dict()) for d in at.dataframe
    )


def _open(page: str, **query: str) -> AppTest:
    at = AppTest.from_file(APP, default_timeout=120)
    at.query_params.update(query)
    at.switch_page(page).run()
    _clean(at)
    assert not at.error, [e.value for e in at.error]
    assert at.get("plotly_chart")
    return at


PAGES = {
    "app_pages/Fusion.py": (
        "fu_view",
        ["Track", "Position error", "VB estimate of R", "Isolation test"],
        [
            ("selectbox", "fu_fault", "noise-step"),
            ("slider", "fu_runs", 3),
            ("number_input", "fu_seed", 2),
            ("select_slider", "fu_fa", 0.01),
        ],
    ),
    "app_pages/Robust_filter.py": (
        "ro_view",
        ["Track", "Position error", "Magnetic variation", "Bearing error"],
        [
            ("toggle", "ro_outliers", False),
            ("slider", "ro_magvar", 3.0),
            ("slider", "ro_kappa", 2.0),
            ("slider", "ro_runs", 3),
        ],
    ),
    "app_pages/Carrier_tracking.py": (
        "ca_view",
        ["Phase error", "Doppler", "Adaptation (R, Q)", "I/Q plane"],
        [
            ("slider", "ca_cn0", 40.0),
            ("select_slider", "ca_tint", 5),
            ("slider", "ca_runs", 3),
            ("slider", "ca_window", 100),
            ("slider", "ca_nominal", 35.0),
        ],
    ),
    "app_pages/Latency.py": (
        "la_view",
        ["Records", "Cost against shift", "Delay per segment"],
        [
            ("slider", "la_unknown", 0.5),
            ("slider", "la_noise", 0.5),
            ("number_input", "la_seed", 3),
            ("select_slider", "la_rate", 5),
        ],
    ),
}
SMALL = {
    "app_pages/Fusion.py": {"fu_runs": "4", "fu_steps": "300"},
    "app_pages/Robust_filter.py": {"ro_runs": "4"},
    "app_pages/Carrier_tracking.py": {"ca_runs": "4", "ca_dur": "5"},
    "app_pages/Latency.py": {},
}


@pytest.mark.parametrize("page", list(PAGES))
def test_page_defaults_views_and_widgets(page, how_it_works_opens):
    view_key, views, widgets = PAGES[page]
    at = _open(page, **SMALL[page])
    assert how_it_works_opens(at)
    for view in views:
        at.segmented_control(key=view_key).set_value(view).run()
        _clean(at)
        assert not at.error, (page, view, [e.value for e in at.error])
        assert at.get("plotly_chart"), (page, view)
    for kind, key, value in widgets:
        before = _shown(at)
        getattr(at, kind)(key=key).set_value(value).run()
        _clean(at)
        assert not at.error, (page, key, [e.value for e in at.error])
        assert _shown(at) != before, (page, key)


def test_fusion_equals_centralised():
    at = _open("app_pages/Fusion.py", fu_runs="2", fu_steps="200")
    diff = next(m.value for m in at.metric if "centralised" in m.label)
    assert float(diff) < 1e-8


def test_latency_estimate_is_close():
    at = _open("app_pages/Latency.py")
    true = float(next(m.value for m in at.metric if m.label == "True mean delay").split()[0])
    est = float(next(m.value for m in at.metric if m.label == "Estimated (filtered)").split()[0])
    assert abs(est - true) < 20.0  # ms


def test_carrier_sweep_on_demand():
    at = _open("app_pages/Carrier_tracking.py", ca_runs="2", ca_dur="4")
    at.number_input(key="ca_sweep_runs").set_value(2)
    at.button(key="ca_sweep_go").click().run()
    _clean(at)
    assert len(at.get("plotly_chart")) == 2
