"""Signal page: upload, generate or pick a sample signal; choose the column and sample period."""

from __future__ import annotations

import streamlit as st

import dashboard_common as dc
import noisevar
from noisevar.figures.estimator import signal_figure
from noisevar.io import signal_summary
from noisevar.signals import GPS_CHANNELS


def explain() -> None:
    """The page's how-it-works expander."""
    dc.how_it_works(
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


sig = dc.setup_page("Signal", ":material/show_chart:")
st.title("Signal")
st.caption(
    "The signal every page works on. Load a sample file, generate a scenario with a seed, or "
    "upload your own; then choose the column and the sample period."
)
errors = st.container()

tab_sample, tab_gen, tab_upload = st.tabs(
    ["Sample data", "Generate", "Upload"], key="sig_source", bind="query-params"
)

# ---------------------------------------------------------------- sample data
with tab_sample:
    files = dc.sample_files()
    desc = dc.sample_descriptions()
    if not files:
        st.info("The sample_data/ folder is empty: generate a signal instead.")
    for path in files:
        c1, c2 = st.columns([1, 4], vertical_alignment="center")
        if c1.button(
            path.name, key=f"sample_{path.name}", icon=":material/dataset:", width="stretch"
        ):
            with errors, dc.guarded(f"{path.name}: "):
                sig = dc.load_sample(path.name)
        c2.caption(desc.get(path.name, f"{path.stat().st_size / 1e3:.0f} kB"))

# ------------------------------------------------------------------ generate
with tab_gen:
    names = noisevar.signal_names()
    c1, c2, c3, c4 = st.columns(4)
    family = c1.selectbox(
        "Scenario",
        names,
        key="gen_name",
        bind="query-params",
        help="Signal families of noisevar.generate (see its docstring).",
    )
    n = c2.number_input(
        "Samples n",
        min_value=200,
        max_value=2_000_000,
        step=1000,
        key="gen_n",
        bind="query-params",
        **dc.initial("gen_n", 6000),
    )
    noise_std = c3.number_input(
        "Noise std (empty: scenario default)",
        min_value=1e-6,
        max_value=1e6,
        format="%g",
        key="gen_std",
        bind="query-params",
        placeholder="default",
        **dc.initial("gen_std", None),
    )
    seed = c4.number_input(
        "Seed",
        min_value=0,
        max_value=2**31 - 1,
        step=1,
        key="gen_seed",
        bind="query-params",
        **dc.initial("gen_seed", 0),
    )
    extras = {}
    specs = dc.GENERATOR_EXTRAS.get(family, [])
    if specs:
        ecols = st.columns(max(len(specs), 2))
        for (key, kind, default, lo, hi), col in zip(specs, ecols, strict=False):
            wkey = f"gen_{family}_{key}"
            if kind == "choice":
                extras[key] = col.selectbox(
                    key.replace("_", " "), list(GPS_CHANNELS), key=wkey, bind="query-params"
                )
            elif kind == "int":
                extras[key] = col.number_input(
                    key.replace("_", " "),
                    min_value=int(lo),
                    max_value=int(hi),
                    step=1,
                    key=wkey,
                    bind="query-params",
                    **dc.initial(wkey, int(default)),
                )
            else:
                extras[key] = col.number_input(
                    key.replace("_", " "),
                    min_value=float(lo),
                    max_value=float(hi),
                    format="%g",
                    key=wkey,
                    bind="query-params",
                    **dc.initial(wkey, float(default)),
                )
    if st.button("Generate", key="gen_go", type="primary", icon=":material/play_arrow:"):
        with errors, dc.guarded("Generate: "):
            sig = dc.load_generated(family, n=n, seed=seed, noise_std=noise_std, **extras)

# -------------------------------------------------------------------- upload
with tab_upload:
    limit_mb = dc.max_upload_bytes() / 1024 / 1024
    st.caption(
        f"CSV/TSV (header optional; a column named t/time gives the sample period), `.npy` "
        f"(numeric arrays only), or NMEA 0183 GGA/RMC (converted to local east/north metres, "
        f"speed and course). Up to {limit_mb:.0f} MB."
    )
    up = st.file_uploader(
        "Upload a file",
        type=["csv", "tsv", "txt", "dat", "npy", "nmea", "log"],
        key="upload",
    )
    if up is not None:
        failed = st.session_state.get("upload_failed")
        if st.session_state.get("upload_done") != up.file_id and (
            not failed or failed[0] != up.file_id
        ):
            try:
                with st.spinner(f"Reading {up.name}..."):
                    sig = dc.load_bytes(up.getvalue(), up.name)
                st.session_state["upload_done"] = up.file_id
                st.session_state.pop("upload_failed", None)
            except noisevar.NoisevarError as exc:
                st.session_state["upload_failed"] = (up.file_id, str(exc))
        failed = st.session_state.get("upload_failed")
        if failed and failed[0] == up.file_id:
            kept = f" (The previous signal, {sig.label}, is kept.)" if sig is not None else ""
            errors.error(failed[1] + kept)

# ------------------------------------------------------- column and period
sig = dc.current_signal()
if sig is None:
    st.info("No signal loaded yet: pick a sample file, generate one, or upload a file above.")
    explain()
    st.stop()

st.subheader(f"{sig.label}")
cols = sig.table.data_columns
c1, c2 = st.columns(2)
column = c1.selectbox(
    "Signal column",
    cols,
    index=cols.index(sig.column) if sig.column in cols else 0,
    key=f"sig_column_{sig.table_digest}",
    help="The column every page estimates; the Two sensors page can use several.",
)
period = c2.number_input(
    "Sample period T (s)",
    value=sig.sample_period,
    min_value=1e-9,
    max_value=1e6,
    format="%g",
    key=f"sig_period_{sig.table_digest}",
    placeholder="unknown: axes in samples",
    help=(
        "From the time column when there is one. Only the time axes use it: the estimators "
        "work per sample."
    ),
)
if column != sig.column or period != sig.sample_period:
    with errors, dc.guarded(f"Column {column!r}: "):
        sig = dc.reselect(sig, column, period)

summary = signal_summary(sig.z, sig.sample_period)
auto = None
with errors, dc.guarded("Quick estimate: "):
    auto = dc.estimate(sig, "auto", {})
m = st.columns(6)
m[0].metric("Samples", f"{summary['n']:,}")
m[1].metric(
    "Duration",
    f"{summary['duration_s']:.4g} s" if sig.sample_period else "n/a",
    help=None if sig.sample_period else "Set the sample period T to see the duration.",
)
m[2].metric("Mean", dc.fmt(summary["mean"]))
m[3].metric("Std (signal + noise)", dc.fmt(summary["std"]))
m[4].metric(
    "Min / max",
    f"{dc.fmt(summary['min'], 3)} / {dc.fmt(summary['max'], 3)}",
    help=f"{dc.fmt(summary['min'], 8)} to {dc.fmt(summary['max'], 8)}",
)
if auto is not None:
    truth = dc.truth_of(sig)
    m[5].metric(
        "Noise std (auto)",
        dc.fmt(auto.std),
        delta=f"true {dc.fmt(truth**0.5)}" if truth else None,
        delta_color="off",
        delta_arrow="off",
        help="Quick estimate with the default method; tune it on the Estimator page.",
    )
for note in sig.notes:
    st.caption(f"Note: {note}")

fig = signal_figure(
    sig.z,
    sig.sample_period,
    name=sig.column,
    clean=dc.clean_of(sig),
    title=f"{sig.label}",
)
dc.show_figure(fig, key="signal_preview")
c1, c2 = st.columns([1, 2])
with c1:
    st.download_button(
        "Signal as CSV",
        data=lambda: sig.table.to_csv(),
        file_name=f"{sig.table.name.split('.')[0].replace(' ', '_')}.csv",
        mime="text/csv",
        key="signal_csv",
        on_click="ignore",
        icon=":material/download:",
        width="stretch",
    )
with c2:
    dc.figure_downloads(fig, "signal", "signal_fig")
with st.expander("First rows of the table"):
    st.dataframe({k: v[:20] for k, v in sig.table.columns.items()}, hide_index=False)

explain()
