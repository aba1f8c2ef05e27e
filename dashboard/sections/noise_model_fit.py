"""The Noise model page's Kalman part: kinematic models compared, Q and R, the tuned filter.

``render_fit(z, rate)`` fits the random-walk, constant-velocity and
constant-acceleration models (docs/algorithms.md §E6), shows their comparison,
the chosen model's ``Q`` and ``R`` with exports (config JSON, filterpy snippet),
and that filter run on the record with its NIS band and innovation whiteness; an
expander fits the coloured-noise models (§E5) to the record.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable

import numpy as np
import streamlit as st

from dashboard import workers
from dashboard.budget import cached
from dashboard.state import current_signal
from dashboard.widgets import fmt, guarded, lazy_expander, show_figure, show_table
from noisevar.config import filter_config_json
from noisevar.estimators.regimes import DEFAULT_REGIMES
from noisevar.figures.kalman_tuning import (
    coloured_rows,
    innovation_acf_figure,
    model_comparison_figure,
    nis_figure,
    tuned_run_figure,
    tuning_rows,
)
from noisevar.format import pvalue, squared
from noisevar.noise_model import KalmanTuning, fit_coloured_noise, fit_models, run_tuned
from noisevar.noise_model.export import APPLY_COMMAND, filterpy_snippet, gain_text
from noisevar.noise_model.kalman_fit import METHODS, MODELS
from noisevar.units import in_data_unit

KEY = "nmf"
#: Session-state key of the (lazy) filterpy snippet expander.
SNIPPET_KEY = f"{KEY}_snippet_open"
#: The tuned filter's run (three figures), drawn while this expander is open.
RUN_LABEL = "The tuned filter on the record: estimate, NIS band, innovation whiteness"
#: Session-state key of the (lazy) run expander.
RUN_KEY = f"{KEY}_run_open"
#: Records longer than this (samples) take about a second or more to fit: show a progress bar.
PROGRESS_ABOVE = 20_000


def _digest(z: np.ndarray, *extra: object) -> str:
    return hashlib.sha1(z.tobytes() + repr(extra).encode()).hexdigest()


def _with_progress(label: str, n: int, work: Callable[[Callable[[float], None] | None], object]):
    """Run ``work(progress)`` with a progress bar when the record is long."""
    if n <= PROGRESS_ABOVE:
        return work(None)
    bar = st.progress(0.0, text=label)
    try:
        return work(lambda f: bar.progress(min(max(f, 0.0), 1.0), text=label))
    finally:
        bar.empty()


@cached
def _fits_on_pool(
    digest: str, rate: float, method: str, regimes: str, _z: np.ndarray, _t: np.ndarray | None
) -> dict[str, KalmanTuning]:
    return workers.call(fit_models, _z, rate=rate, method=method, regimes=regimes, t=_t)


def _fit_models(
    z: np.ndarray, rate: float, method: str, regimes: str, t: np.ndarray | None = None
) -> dict[str, KalmanTuning]:
    """Every kinematic model's fit for this record, rate, method and regimes; the record's
    answer on its times ``t`` (split at their gaps), as the Estimator page makes it.

    A record of at most :data:`PROGRESS_ABOVE` samples is fitted on the worker pool, once
    for every session (the server's cache): on the script thread it held the GIL, a quarter
    of the server's GIL time with 8 sessions (py-spy, ``benchmarks/load.py``). A longer one
    is fitted here with a progress bar and kept in the session.
    """
    times = None if t is None else hashlib.sha1(t.tobytes()).hexdigest()
    if z.size <= PROGRESS_ABOVE:
        return _fits_on_pool(_digest(z, times), float(rate), method, regimes, z, t)
    key = f"{KEY}_fits_{_digest(z, rate, method, regimes, times)}"
    if key not in st.session_state:

        def work(progress: Callable[[float], None] | None) -> dict[str, KalmanTuning]:
            return fit_models(z, rate, method, regimes, progress=progress, t=t)

        st.session_state[key] = _with_progress("Fitting q and r...", z.size, work)
    return st.session_state[key]


def _verdict(t: KalmanTuning) -> None:
    lo, hi = t.nis_band
    text = (
        f"NIS mean {fmt(t.nis_mean)} (95 % band {fmt(lo)} .. {fmt(hi)}); innovations "
        f"{'white' if t.innovations_white else 'NOT white'} "
        f"(Ljung-Box {pvalue(t.ljung_box_p)}), "
        f"{t.tails_text(fmt(t.innovations_kurtosis))}."
    )
    if t.innovations_white and t.nis_consistent and t.innovations_gaussian:
        st.success(f"The {t.model!r} filter fits this record. {text}")
    else:
        st.warning(f"The {t.model!r} filter does not fit this record. {text}")
    for note in t.notes:
        if t.record is None or note != t.record.note:  # that one is said by _record
            st.caption(note)


def _record(t: KalmanTuning, unit: str) -> None:
    """r beside the record's answer (``KalmanTuning.record``): agree, or why not and what to do."""
    c = t.record
    if c is None:
        return
    text = f"**r and the record's R (method auto).** {c.note}."
    if c.agrees and not c.broken:
        st.info(text)
        return
    st.warning(text)
    use = "none (no still stretch measures it)" if c.use is None else fmt(c.use, unit=squared(unit))
    st.markdown(f"R to use: **{use}**; this fit's r: {fmt(t.r, unit=squared(unit))}.")


def _how_read() -> tuple[str | None, str | None]:
    """The unit the Signal page read the file's times in and the series it read (the
    config carries them)."""
    sig = current_signal()
    return (None, None) if sig is None else (sig.time_unit, sig.series)


def _exports(t: KalmanTuning, column: str | None, unit: str, record: dict[str, str] | None) -> None:
    named = f" on column {column!r} (another column is refused)" if column else ""
    st.caption(f"Apply the config with `{APPLY_COMMAND}`: it replays this q and r{named}.")
    c1, c2 = st.columns(2)
    c1.download_button(
        "Config with Q and R (JSON)",
        data=filter_config_json(t, column, unit, record, *_how_read()),
        file_name=f"tuned_{t.model}.json",
        mime="application/json",
        key=f"{KEY}_cfg",
        on_click="ignore",
    )
    snippet = filterpy_snippet(t)
    c2.download_button(
        "filterpy snippet (.py)",
        data=snippet,
        file_name=f"kalman_{t.model}.py",
        mime="text/x-python",
        key=f"{KEY}_py",
        on_click="ignore",
    )
    # Lazy: a code block, even in a closed expander, loads and runs the browser's syntax
    # highlighter (about a second of the page's CPU in Chromium's profile, issue 29).
    with lazy_expander("The tuned filter in filterpy", SNIPPET_KEY) as is_open:
        if is_open:
            st.code(snippet, language="python")


def _run_figures(t: KalmanTuning, z: np.ndarray, named: str) -> None:
    """The tuned filter run on the record: estimate, NIS band, innovation whiteness.

    Lazy: run and drawn only while its expander is open. Three Plotly figures cost the
    browser about a quarter of a CPU-s each when the page opens (issue 29).
    """
    with lazy_expander(RUN_LABEL, RUN_KEY, icon=":material/show_chart:") as is_open:
        if is_open:
            run = run_tuned(t, z)
            show_figure(tuned_run_figure(run, z, dt=t.dt, y_title=named), key=f"{KEY}_run")
            show_figure(nis_figure(run, dt=t.dt), key=f"{KEY}_nis")
            show_figure(innovation_acf_figure(run), key=f"{KEY}_acf")


def _coloured(z: np.ndarray, rate: float, regimes: str) -> None:
    with st.expander("Coloured-noise models (for a static sensor's noise log)"):
        st.caption(
            "White, white + AR(1) and white + random walk, fitted by exact maximum likelihood "
            "to the detrended record and ranked by BIC."
        )
        key = f"{KEY}_col_{_digest(z, rate, regimes)}"
        if st.button("Fit the coloured-noise models", key=f"{KEY}_col_btn"):
            st.session_state[key] = _with_progress(
                "Fitting noise models...",
                0 if z.size < 5000 else PROGRESS_ABOVE + 1,
                lambda p: fit_coloured_noise(z, rate=rate, progress=p, regimes=regimes),
            )
        fit = st.session_state.get(key)
        if fit is not None:
            st.markdown(f"Chosen by {fit.criterion.upper()}: **{fit.model}**")
            for note in fit.notes:
                st.caption(note)
            show_table(coloured_rows(fit), hide_index=True)
            show_figure(model_comparison_figure(fit), key=f"{KEY}_colfig")


def render_fit(
    z: np.ndarray,
    rate: float,
    regimes: str = DEFAULT_REGIMES,
    column: str | None = None,
    unit: str = "",
    record: dict[str, str] | None = None,
    times: np.ndarray | None = None,
) -> None:
    """Kinematic models compared, the chosen one's Q and R, and its filter run on the record.

    Parameters
    ----------
    z : ndarray, shape (n,)
        The record.
    rate : float
        Samples per second.
    regimes : {"all", "still"}
        Fit the whole record, or its longest still stretch only.
    column, unit : str
        The record's column and declared unit, carried by the exported config.
    record : dict, optional
        The record's answer (:meth:`~noisevar.estimators.answer.RecordAnswer.summary`),
        carried by the exported config.
    times : ndarray, shape (n,), optional
        The samples' times: the fit's record check reads the record's answer on them.
    """
    with guarded("Kalman fit: "):
        z = np.asarray(z, dtype=float)
        c1, c2 = st.columns(2)
        method = c1.selectbox("Method", METHODS, key=f"{KEY}_method")
        tunings = _fit_models(z, rate, method, regimes, times)
        best = min(tunings.values(), key=lambda t: t.bic).model
        model = c2.selectbox(
            "Model for the filter",
            list(MODELS),
            index=list(MODELS).index(best),
            key=f"{KEY}_model",
            help="rw: random walk, cv: constant velocity, ca: constant "
            "acceleration. The best by BIC is preselected.",
        )
        show_table(tuning_rows(tunings, unit), hide_index=True)
        t = tunings[model]
        _verdict(t)
        st.markdown(
            f"Suggested **q = {fmt(t.q)}** {in_data_unit(t.units['q'], unit)} and "
            f"**r = {fmt(t.r)}** {in_data_unit(t.units['r'], unit)} "
            f"(h = qT^k/r = {fmt(t.h)}); steady-state gain: {gain_text(t)}."
        )
        _record(t, unit)
        _exports(t, column, unit, record)
        if t.regimes != DEFAULT_REGIMES:
            st.caption("Fitted on the still stretch; below, the filter runs on the whole record.")
        named = f"{column or 'record'} ({unit or 'u'})"  # a bare field ("x") names no quantity
        _run_figures(t, z, named)
    with guarded("Coloured-noise fit: "):
        _coloured(np.asarray(z, dtype=float), rate, regimes)
