"""The home page: what noisevar does, a quick start, a card per page, how SOMD works."""

from __future__ import annotations

import streamlit as st

from dashboard import cache
from dashboard.cache import DEFAULT_METHOD
from dashboard.pages import page_links
from dashboard.sections.regimes import record_answer_box
from dashboard.sections.signal_loader import quick_start
from dashboard.state import current_signal
from dashboard.widgets import fmt, guarded, how_it_works

HOW_IT_WORKS = (
    "A sensor reading is the true value plus noise: $z_k = s_k + v_k$ with "
    "$\\operatorname{var}(v_k)=\\sigma^2$. If a second sensor saw the same $s$, the noise would "
    "show in the difference of the two. SOMD builds that second sensor from the signal itself: "
    "an alpha-beta-gamma filter smooths $z$ into $\\hat z$, and the mutual differences of "
    "successive changes carry the noise:",
    "$$\\hat\\sigma^2 = \\frac{1}{c}\\,\\mathrm{E}\\big[(\\Delta\\hat z_k - \\Delta z_k)^2\\big],"
    "\\qquad \\Delta z_k = z_{k+1}-z_k$$",
    "The paper takes $c = 2$; the exact factor $c(h)$ of the filter removes its bias. "
    "Windows where the smooth filter bends or lags are left out (Estimator page). The best "
    "possible relative precision from $n$ samples is the Cramér-Rao floor:",
    "$$\\frac{\\operatorname{sd}(\\hat\\sigma^2)}{\\sigma^2} \\ge \\sqrt{2/n}$$",
)

sig = current_signal()
st.title("noisevar — how noisy is this signal?")
st.markdown(
    "Estimate the **measurement-noise variance** of a recorded signal, see every step of the "
    "estimator, compare it with its peers, and use it in **adaptive Kalman filters**. "
    "The core estimator is the second-order mutual difference (SOMD) with an "
    "alpha-beta-gamma *virtual redundant sensor* (Zhang, Zhang and Wu, 2016)."
)

if sig is None:
    quick_start()
else:
    est = None
    with guarded():
        est = cache.estimate(sig, DEFAULT_METHOD, {})
    if est is not None:
        st.success(
            f"Loaded **{sig.label}** ({sig.n:,} samples). Quick estimate (method "
            f"`{DEFAULT_METHOD}`): noise standard deviation **{fmt(est.std)}**, variance "
            f"{fmt(est.variance)} (95 % interval {fmt(est.ci95[0])} to {fmt(est.ci95[1])})."
        )
        record_answer_box(est)  # the record's verdict and regime warning, with its R

st.subheader("Pages")
page_links()

st.caption(
    "Parameters live in the page URL, so a link reopens the same view (generated and sample "
    "signals are reopened too; uploaded data never goes into the URL). Every page exports its "
    "results (CSV), its figure (HTML/PNG) and, on the Estimator page, the tuned parameters as "
    "the JSON that `noisevar estimate --config` reads."
)

how_it_works(*HOW_IT_WORKS)
