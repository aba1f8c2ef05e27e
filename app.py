"""noisevar dashboard: home page and frame.

Run with ``streamlit run app.py`` (settings in ``.streamlit/config.toml``:
headless, bound to 127.0.0.1). The pages live in ``pages/`` (Streamlit's
classic discovery); each calls :func:`dashboard_common.setup_page` first so it
also works when its URL is the first one opened.
"""

from __future__ import annotations

import streamlit as st

import dashboard_common as dc

sig = dc.setup_page("Home", ":material/home:")

st.title("noisevar — how noisy is this signal?")
st.markdown(
    "Estimate the **measurement-noise variance** of a recorded signal, see every step of the "
    "estimator, compare it with its peers, and use it in **adaptive Kalman filters**. "
    "The core estimator is the second-order mutual difference (SOMD) with an "
    "alpha-beta-gamma *virtual redundant sensor* (Zhang, Zhang and Wu, 2016)."
)

if sig is None:
    st.info("Start by loading a signal: a sample file, a generated scenario, or your own file.")
    c1, c2 = st.columns(2)
    with c1:
        if st.button("Load the sample fast_slow.csv", key="home_sample", type="primary"):
            with dc.guarded():
                dc.load_sample("fast_slow.csv")
                st.rerun()
    with c2:
        if st.button("Generate the paper's fast-slow signal", key="home_generate"):
            with dc.guarded():
                dc.load_generated("fast-slow", n=6000, seed=0, noise_std=5.0)
                st.rerun()
else:
    est = None
    with dc.guarded():
        est = dc.estimate(sig, "auto", {})
    if est is not None:
        st.success(
            f"Loaded **{sig.label}** ({sig.n:,} samples). Quick estimate (method `auto`): "
            f"noise standard deviation **{dc.fmt(est.std)}**, variance {dc.fmt(est.variance)} "
            f"(95 % interval {dc.fmt(est.ci95[0])} to {dc.fmt(est.ci95[1])})."
        )

st.subheader("Pages")
cols = st.columns(3)
for i, page in enumerate(p for p in dc.PAGES if (dc.ROOT / p.path).is_file()):
    with cols[i % 3], st.container(border=True):
        st.page_link(page.path, label=page.label, icon=page.icon)
        st.caption(page.blurb)

st.caption(
    "Parameters live in the page URL, so a link reopens the same view (generated and sample "
    "signals are reopened too; uploaded data never goes into the URL). Every page exports its "
    "results (CSV), its figure (HTML/PNG) and, on the Estimator page, the tuned parameters as "
    "the JSON that `noisevar estimate --config` reads."
)

dc.how_it_works(
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
