"""The Estimator page's tuning panel and the results it drives, as one fragment.

A control change reruns this fragment only: the page's title, the sidebar, the signal
loader and the how-it-works text are not rebuilt nor sent again.
"""

from __future__ import annotations

import streamlit as st

from dashboard import trace
from dashboard.sections import estimator_results as results
from dashboard.sections.estimator_tuning import CONFIG_COLUMN_KEY, tuning_panel
from dashboard.sections.noise_panel import render_noise_panel
from dashboard.state import LoadedSignal, times_of, truth_of
from dashboard.widgets import CONTROLS_KEY


@st.fragment
def tuned_view(sig: LoadedSignal) -> None:
    """Tuning controls (left) and the estimate, Noise panel, figures and exports (right).

    A loaded config that names a column switches the page's signal: the whole page then
    reruns (:func:`~dashboard.sections.estimator_tuning.follow_config_column` runs there).
    """
    with trace.script_run("Estimator (fragment)"):  # the load benchmark's trace
        _tuned_view(sig)


def _tuned_view(sig: LoadedSignal) -> None:
    left, right = st.columns([1, 3], gap="large")
    with left, st.container(key=CONTROLS_KEY):  # on a phone: below the answer
        tuning = tuning_panel(sig.n)
    if st.session_state.get(CONFIG_COLUMN_KEY) is not None:
        st.rerun(scope="app")  # the config's column: the signal, sidebar and link change
    with right:
        truth = truth_of(sig)
        est, shown = results.run_estimate(sig, tuning)
        if est is not None:
            results.headline(sig, est, truth, tuning)
            render_noise_panel(sig.z, est, times_of(sig), key="est_np", digest=sig.digest)
        fig = results.main_figure(sig, shown, tuning)
        results.step_views(sig, shown, tuning, truth)
        results.exports(sig, est, truth, fig)
