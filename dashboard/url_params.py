"""Shared links are untrusted input: every query-parameter value is checked first.

:func:`clean_query_params` runs at the top of every page, before any widget reads its
value from the URL. A value that no widget could hold (a non-finite or huge number, a
400-digit number, control characters, a very long string) is dropped from the URL and
from Streamlit's initial-value table, with one ``st.warning`` naming what was dropped.
Values inside that envelope but outside one widget's own range are reset to the
widget's default by Streamlit itself. The signal recipe (``?sig=gen:...``) is checked
against the dashboard's limits and the family's parameter specs (:func:`check_recipe`).
"""

from __future__ import annotations

import logging
import math
import re
from collections.abc import Iterable

import streamlit as st

import noisevar
from dashboard.state import parse_recipe
from dashboard.text import plain
from noisevar.errors import NoisevarError
from noisevar.io.table import SAMPLE_PERIOD_RANGE, echo
from noisevar.params import ParamSpec, by_name
from noisevar.signals import signal_spec

LOG = logging.getLogger("noisevar.dashboard")

#: Longest value kept from the URL (characters).
MAX_VALUE_CHARS = 200
#: Longest parameter name kept.
MAX_KEY_CHARS = 64
#: Largest magnitude of a number any widget takes (seeds are below 2**32).
MAX_NUMBER = 1e15
#: Most repeated values of one parameter (multiselects).
MAX_REPEATS = 50
_NUMBERISH = re.compile(r"^\s*[+-]?(\d|\.\d|inf|nan)", re.IGNORECASE)
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
#: The recipe's own numbers, with the dashboard's limits (the generator form uses them too);
#: a family's parameters are checked by their specs (:func:`noisevar.signals.signal_spec`).
RECIPE_PARAMS: dict[str, ParamSpec] = by_name(
    [
        ParamSpec("n", "int", 6000, "samples", lo=100, hi=2_000_000, lo_closed=True),
        ParamSpec("seed", "int", 0, "seed of the noise", lo=0, hi=2**31 - 1, lo_closed=True),
        ParamSpec(
            "noise_std", "float", help="noise standard deviation", lo=1e-6, hi=1e6, lo_closed=True
        ),
        ParamSpec(
            "T",
            "float",
            help="sample period (s)",
            lo=SAMPLE_PERIOD_RANGE[0],
            hi=SAMPLE_PERIOD_RANGE[1],
            lo_closed=True,
        ),
    ]
)


#: Browser history as a user expects it, installed once per tab by every page
#: (:func:`dashboard.widgets.page_head`). Streamlit pushes a history entry whenever the
#: server changes the query string. On a page change the server first strips the old
#: page's widget parameters and the frame names the signal again, both while the browser
#: still shows the old page (each an entry of the old page, without its settings), then
#: the new page is pushed. Back then landed on the old page with every setting gone, or
#: on a copy of the new page. Here, between a click on a link to another page and that
#: page's entry, a change of the query string leaves the old page's entry as it was; any
#: other change of the query string on the same page replaces the current entry instead
#: of adding one. One entry per page visited, each with its own settings.
HISTORY_JS = """<script>(() => {
  if (window.__nvHistory) return;
  window.__nvHistory = true;
  let leaving = 0;
  document.addEventListener('click', e => {
    const a = e.target.closest && e.target.closest('a[href]');
    if (a && new URL(a.href, location.href).pathname !== location.pathname) leaving = Date.now();
  }, true);
  const push = history.pushState.bind(history), replace = history.replaceState.bind(history);
  history.pushState = (state, title, url) => {
    const next = new URL(url, location.href);
    if (next.pathname !== location.pathname) { leaving = 0; return push(state, title, url); }
    if (Date.now() - leaving < 10000) return undefined;
    return replace(state, title, url);
  };
})();</script>"""


def value_problem(value: str) -> str | None:
    """Why a URL value cannot be given to any widget, or None when it can."""
    if len(value) > MAX_VALUE_CHARS:
        return f"{len(value):,} characters"
    if _CONTROL.search(value):
        return "control characters"
    if _NUMBERISH.match(value):
        try:
            number = float(value)
        except (ValueError, OverflowError):
            return None  # text such as a date or a label: the widget decides
        if not math.isfinite(number):
            return "not a finite number"
        if abs(number) > MAX_NUMBER or len(re.sub(r"\D", "", value)) > 30:
            return "number out of range"
    return None


def _problems(params: dict[str, list[str]]) -> dict[str, str]:
    """Parameter name to the reason it is dropped."""
    bad: dict[str, str] = {}
    for key, values in params.items():
        if len(key) > MAX_KEY_CHARS or _CONTROL.search(key):
            bad[key] = "bad name"
        elif len(values) > MAX_REPEATS:
            bad[key] = f"{len(values)} values"
        elif key == "sig":
            try:
                check_recipe(values[-1] if values else "")
            except NoisevarError as exc:
                bad[key] = str(exc)
        else:
            reason = next((r for r in map(value_problem, values) if r), None)
            if reason:
                bad[key] = reason
    return bad


def _drop(keys: Iterable[str]) -> None:
    """Remove parameters from the URL and from Streamlit's initial-value table."""
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    ctx = get_script_run_ctx()
    if ctx is None:
        return
    with ctx.session_state.query_params() as qp:
        initial = getattr(qp, "_initial_query_params", None)
        for key in keys:
            if isinstance(initial, dict):
                initial.pop(key, None)
            qp.remove_param(key)


def _current() -> dict[str, list[str]]:
    """Every query parameter of this run: the URL's and the initial ones seeding widgets."""
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    params: dict[str, list[str]] = {k: st.query_params.get_all(k) for k in st.query_params}
    ctx = get_script_run_ctx()
    if ctx is not None:
        with ctx.session_state.query_params() as qp:
            initial = getattr(qp, "_initial_query_params", None) or {}
            for key, values in initial.items():
                params.setdefault(key, list(values))
    return params


def clean_query_params() -> dict[str, str]:
    """Drop every query-parameter value no widget can hold; one warning if any was dropped.

    Call it before any widget (``dashboard.pages.frame`` does).

    Returns
    -------
    dict
        Dropped parameter name to the reason.
    """
    try:
        bad = _problems(_current())
        if bad:
            _drop(bad)
    except Exception:  # noqa: BLE001 - Streamlit internals changed: fall back to the URL only
        LOG.debug("could not clean the initial query parameters", exc_info=True)
        bad = _problems({k: st.query_params.get_all(k) for k in st.query_params})
        for key in bad:
            st.query_params.pop(key, None)
    if bad:
        listed = "; ".join(f"{plain(k, 40)} ({plain(r, 120)})" for k, r in bad.items())
        st.warning(f"Ignored values of the link that no control can take: {listed}.")
    return bad


def check_recipe(recipe: str) -> dict[str, float | int | str]:
    """Check a signal recipe's values against the dashboard's limits and the family's specs.

    Parameters
    ----------
    recipe : str
        ``gen:<family>;n=...;seed=...`` or ``sample:<file>`` (with ``col=``, ``T=``).

    Returns
    -------
    dict
        The checked options, converted to their kinds (unknown ones as text).

    Raises
    ------
    NoisevarError
        One sentence naming the bad value and its range.
    """
    if value_problem(recipe) == "control characters" or len(recipe) > 4 * MAX_VALUE_CHARS:
        raise NoisevarError("the signal recipe is malformed")
    kind, name, opts = parse_recipe(recipe)
    if kind not in ("gen", "sample"):
        raise NoisevarError(f"unknown signal source {echo(kind, 20)!r}")
    specs = dict(RECIPE_PARAMS)
    if kind == "gen" and name in noisevar.signal_names():
        specs.update({p.name: p for p in signal_spec(name).extras})
    out: dict[str, float | int | str] = {}
    for key, text in opts.items():
        problem = value_problem(text)
        if problem:
            raise NoisevarError(f"{echo(key, 20)}={echo(text, 40)}: {problem}")
        out[key] = specs[key].validate(text) if key in specs else text
    return out


def reset_page_controls() -> list[str]:
    """Put every control of the page now shown back to its default (the "Reset to
    defaults" button's callback); the signal stays.

    The page's controls are its widgets bound to the URL (Streamlit's binding registry
    knows each one's page); each is set to its own default, as drawn (widgets always get
    their default: :func:`dashboard.state.initial`), and Streamlit then removes its
    parameter from the URL.

    Returns
    -------
    list of str
        The keys reset.
    """
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    ctx = get_script_run_ctx()
    if ctx is None:
        return []
    done = []
    try:
        state = ctx.session_state._state  # noqa: SLF001 - Streamlit's widget metadata
        metadata = state._new_widget_state.widget_metadata  # noqa: SLF001
        with ctx.session_state.query_params() as qp:
            bindings = list(getattr(qp, "_bindings_by_param", {}).values())
        for b in bindings:
            meta = metadata.get(b.widget_id)
            if b.script_hash != ctx.page_script_hash or meta is None:
                continue
            st.session_state[b.param_key] = meta.deserializer(None)
            done.append(b.param_key)
    except Exception:  # noqa: BLE001 - Streamlit internals changed: nothing is reset
        LOG.warning("could not reset the page's controls", exc_info=True)
    return done
