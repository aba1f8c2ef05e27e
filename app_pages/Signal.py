"""Upload CSV/TSV, .npy or NMEA; generate a scenario; or pick a sample file.

Signal page: upload, generate or pick a sample signal; choose the column and sample period.
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import channels, signal_loader, signal_overview
from dashboard.state import current_signal
from dashboard.widgets import how_it_works

HOW_IT_WORKS = (
    "**Measurement model.** Every sample is the true value plus white noise:",
    "$$z_k = s_k + v_k,\\qquad \\mathrm{E}[v_k]=0,\\; \\operatorname{var}(v_k)=\\sigma^2$$",
    "The estimators assume a uniform sample period $T$ and a slowly varying $s_k$ compared "
    "with the noise; everything is computed per sample, $T$ only labels the time axes.",
    "**Formats.** CSV/TSV/whitespace text with or without a header (the first row is a header "
    "when one of its fields is not a number; `#` starts a comment); `.npy` arrays read with "
    "`np.load(allow_pickle=False)`; NMEA 0183 GGA/RMC sentences with valid checksums. "
    "Positions become local east/north/up metres from the first fix through the WGS-84 "
    "ellipsoid (geodetic → Earth-centred → local tangent frame):",
    "$$\\begin{bmatrix}e\\\\n\\\\u\\end{bmatrix} = R(\\varphi_0,\\lambda_0)"
    "\\left(\\mathbf{x}_{\\mathrm{ECEF}}(\\varphi,\\lambda,h) - "
    "\\mathbf{x}_{\\mathrm{ECEF}}(\\varphi_0,\\lambda_0,h_0)\\right)$$",
    "RMC speed is converted from knots to m/s (1 kn = 1852/3600 m/s).",
    "**Long records** (up to millions of samples) are computed on every sample but drawn "
    "downsampled (MinMax-LTTB keeps peaks and the noise band), as each figure says.",
)

st.title("Signal")
st.caption(
    "The signal every page works on. Load a sample file, generate a scenario with a seed, or "
    "upload your own; then choose the column and the sample period."
)
errors = st.container()

tab_sample, tab_gen, tab_upload = st.tabs(
    ["Sample data", "Generate", "Upload"], key="sig_source", bind="query-params"
)
with tab_sample:
    signal_loader.sample_buttons(errors)
with tab_gen:
    signal_loader.generator_form(errors)
with tab_upload:
    signal_loader.uploader(errors)

sig = current_signal()
if sig is None:
    st.info("No signal loaded yet: pick a sample file, generate one, or upload a file above.")
    how_it_works(*HOW_IT_WORKS)
    st.stop()

sig = signal_overview.column_and_period(sig, errors)
signal_overview.summary_metrics(sig, errors)
signal_overview.preview(sig)
channels.side_by_side(sig)
how_it_works(*HOW_IT_WORKS)
