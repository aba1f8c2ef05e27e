"""AppTest: every page under a hostile shared link (issue 15): no exception, one warning."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

from dashboard.pages import PAGES  # noqa: E402
from dashboard.url_params import check_recipe, value_problem  # noqa: E402
from noisevar.signals import SIGNALS  # noqa: E402

HOSTILE = ["1e999", "-1e999", "9" * 400, "nan", "-inf", "1e300", "x" * 500, "a\x1b[31m"]
GOOD_SIG = "gen:fast-slow;n=3000;seed=1;noise_std=5.0"
BAD_SIGS = [
    "gen:fast-slow;n=1e999",
    "gen:fast-slow;n=30000000",
    "gen:fast-slow;n=6000;T=1e999",
    "gen:fast-slow;n=6000;T=-1",
    "gen:gps-circle;n=6000;sample_period=0",
    "gen:fast-slow;n=" + "9" * 400,
    "sample:fast_slow.csv;T=0",
]


def url_bound_keys() -> list[str]:
    """Every widget key bound to the URL, read from the dashboard's source."""
    keys: set[str] = set()
    files = [*ROOT.glob("dashboard/**/*.py"), *ROOT.glob("app_pages/*.py"), ROOT / "app.py"]
    for path in files:
        text = path.read_text()
        for m in re.finditer(r'bind="query-params"', text):
            start = max(0, m.start() - 600)
            around, at = text[start : m.end() + 300], m.start() - start
            found = re.findall(r'key="(\w+)"', around)
            if found:
                # the key nearest to the bind argument belongs to the same call
                keys.add(min(found, key=lambda k: abs(around.find(f'key="{k}"') - at)))
        # keys passed to a helper that binds them: _slider("label", lo, hi, step, "la_dur", ...)
        keys.update(re.findall(r'_slider\(.*?"(la_\w+)"', text))
        # widgets built from a parameter spec: param_input(spec, "key", ...)
        keys.update(re.findall(r'param_input\(\s*[^,]+,\s*"(\w+)"', text))
    for family, spec in SIGNALS.items():
        keys.update(f"gen_{family}_{p.name}" for p in spec.extras)
    return sorted(keys)


def _hostile_query() -> dict[str, str]:
    keys = url_bound_keys()
    return {k: HOSTILE[i % len(HOSTILE)] for i, k in enumerate(keys)}


def test_the_key_scan_finds_the_url_bound_widgets():
    keys = url_bound_keys()
    assert {"gen_n", "gen_seed", "s0", "s1", "ca_seed", "cmp_tab"} <= set(keys)
    assert len(keys) >= 40


def test_value_rules():
    for v in HOSTILE:
        assert value_problem(v), v
    for v in ("6000", "0.5", "somd", "1e-9", "fast-slow", "2147483647"):
        assert value_problem(v) is None, v
    for recipe in BAD_SIGS:
        with pytest.raises(ValueError):
            check_recipe(recipe)
    assert check_recipe(GOOD_SIG)["n"] == 3000


@pytest.mark.parametrize("page", [p.path for p in PAGES])
def test_every_page_survives_a_hostile_link(page):
    at = AppTest.from_file(APP, default_timeout=180)
    at.query_params.update({"sig": GOOD_SIG, **_hostile_query()})
    at.switch_page(page).run()
    assert not at.exception, [e.value for e in at.exception]
    warnings = [w.value for w in at.warning if "Ignored values of the link" in w.value]
    assert len(warnings) == 1, [w.value for w in at.warning]
    assert "\x1b" not in warnings[0]
    # the signal named by the link is still reopened
    assert at.session_state["nv_signal"].n == 3000


@pytest.mark.parametrize("recipe", BAD_SIGS)
def test_a_hostile_signal_recipe_is_dropped_with_a_warning(recipe):
    at = AppTest.from_file(APP, default_timeout=120)
    at.query_params["sig"] = recipe
    at.switch_page("app_pages/Signal.py").run()
    assert not at.exception, [e.value for e in at.exception]
    assert any("sig" in w.value for w in at.warning), [w.value for w in at.warning]
    assert "nv_signal" not in at.session_state


def _signal_page() -> AppTest:
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    assert not at.exception
    return at


def _upload(at: AppTest, name: str, body: str) -> None:
    at.file_uploader(key="upload").set_value((name, body.encode(), "text/csv")).run()
    assert not at.exception, [e.value for e in at.exception]


# (a step of 3.6e6 from 1.7e12 is milliseconds since 1970, hourly: tests/test_io_imu_formats.py)
@pytest.mark.parametrize(("step", "start"), [(3_600_000, 0), (1e-12, 0.0)])
def test_a_time_step_outside_the_period_range_never_crashes_a_visit(step, start):
    at = _signal_page()
    rows = "\n".join(f"{start + step * i!r},{(i * 7919) % 101 / 10}" for i in range(400))
    _upload(at, "stamps.csv", "time,x\n" + rows)
    sig = at.session_state["nv_signal"]
    assert sig.sample_period is None
    for page in ("app_pages/Estimator.py", "app_pages/Signal.py", "app_pages/Home.py"):
        at.switch_page(page).run()
        assert not at.exception, (page, [e.value for e in at.exception])


def test_decimal_comma_upload_is_accepted():
    at = _signal_page()
    rows = "\n".join(
        f"{i};{(i * 7919) % 101 / 10 + 0.25:.2f}".replace(".", ",") for i in range(400)
    )
    _upload(at, "europe.csv", "t;x\n" + rows)
    assert not at.error, [e.value for e in at.error]
    sig = at.session_state["nv_signal"]
    assert sig.n == 400 and sig.z[0] == 0.25


def test_drop_nonfinite_option_on_upload():
    at = _signal_page()
    rows = [f"{i},{(i * 7919) % 101 / 10}" for i in range(400)]
    rows[5] = "5,"
    rows[9] = "9,nan"
    _upload(at, "gaps.csv", "t,x\n" + "\n".join(rows))
    assert at.error and "empty or NaN" in at.error[0].value
    assert "tick 'Drop rows with empty or NaN values'" in at.error[0].value  # this page's way
    assert "nv_signal" not in at.session_state
    at.checkbox(key="upload_drop").check().run()
    assert not at.exception and not at.error
    assert at.session_state["nv_signal"].n == 398


def test_quantised_record_on_compare_gives_per_method_errors_not_a_crash():
    at = _signal_page()
    _upload(at, "quantised.csv", "x\n" + "0\n" * 1999 + "1\n")
    assert at.session_state["nv_signal"].n == 2000
    at.switch_page("app_pages/Compare.py").run()
    assert not at.exception, [e.value for e in at.exception]
