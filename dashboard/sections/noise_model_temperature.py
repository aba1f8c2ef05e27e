"""The Noise model page's temperature model, datasheet comparison and composite models.

docs/algorithms.md §E9. Each part is one function the page calls in its own expander.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import streamlit as st

from dashboard.sections.noise_model import NoiseModelSettings
from dashboard.state import LoadedSignal, initial
from dashboard.widgets import figure_downloads, fmt, guarded, show_figure, show_table
from noisevar.figures.noise_model import (
    bias_temperature_figure,
    composite_figure,
    datasheet_figure,
    warmup_figure,
)
from noisevar.noise_model import InertialNoise
from noisevar.noise_model.datasheet import BIAS_UNITS, DATA_UNITS, DENSITY_UNITS, datasheet_terms
from noisevar.noise_model.temperature import (
    TemperatureModel,
    matlab_temperature_params,
    temperature_model,
)


@st.cache_data(max_entries=8, show_spinner="Fitting bias(T) and the warm-up...")
def _temperature_cached(
    digest: str, rate: float, unit: str, _z: np.ndarray, _temp: np.ndarray
) -> TemperatureModel:
    model = temperature_model(_z, _temp, rate, unit=unit)
    assert isinstance(model, TemperatureModel)
    return model


def _column(sig: LoadedSignal, name: str) -> np.ndarray:
    from noisevar.io import pick_column

    return np.asarray(pick_column(sig.table, name), dtype=float)


def temperature_panel(sig: LoadedSignal, s: NoiseModelSettings) -> TemperatureModel | None:
    """Pick the temperature column; bias(T), the warm-up, noise(T), the process noise."""
    cols = [c for c in sig.table.data_columns if c != sig.column]
    col = st.selectbox(
        "Temperature column (°C)",
        [None, *cols],
        format_func=lambda c: "none" if c is None else c,
        key="nm_temp_col",
        help="The sensor's temperature, one value per sample of the analysed column.",
        **initial("nm_temp_col", 0, "index"),
    )
    if col is None:
        st.caption("Pick the record's temperature column to fit bias(T), the warm-up and noise(T).")
        return None
    model = None
    with guarded("Temperature model: "):
        temp = _column(sig, col)
        key = f"{sig.table_digest}:{sig.column}:{col}"
        model = _temperature_cached(key, s.rate, s.unit, sig.z, temp)
    if model is not None:
        _show_model(model)
    return model


def _coefficient_table(model: TemperatureModel) -> pd.DataFrame:
    rows = [
        {
            "term": c.name,
            "value": c.value,
            "low": c.interval[0],
            "high": c.interval[1],
            "unit": c.unit,
        }
        for c in model.coefficients
    ]
    w = model.warmup
    if w is not None:
        rows.append(
            {
                "term": "warm-up A",
                "value": w.amplitude,
                "low": w.amplitude_interval[0],
                "high": w.amplitude_interval[1],
                "unit": w.unit,
            }
        )
        rows.append(
            {
                "term": "warm-up τ",
                "value": w.time_constant,
                "low": w.time_constant_interval[0],
                "high": w.time_constant_interval[1],
                "unit": "s",
            }
        )
    return pd.DataFrame(rows)


def _show_model(model: TemperatureModel) -> None:
    show_table(_coefficient_table(model), hide_index=True)
    st.caption(
        f"bias(T) = a + b (T - {model.reference_temperature:g} °C) + ... of order {model.order} "
        f"(chosen by BIC among {len(model.candidates)} models) "
        + ("+ A exp(-t/τ) from power-on" if model.warmup else "; no warm-up found")
        + f"; {model.ci:.1%} intervals (moving-block bootstrap)."
    )
    p = model.process_noise
    c1, c2 = st.columns(2)
    c1.metric("Bias process noise", fmt(p.density, unit=p.unit), help=p.assumption)
    if model.warmup is not None:
        c2.metric("Warm-up within 1 % after", fmt(model.warmup.settled_after, unit="s"))
    st.caption(f"The process noise {p.assumption}; add it to K in quadrature.")
    fig = bias_temperature_figure(model)
    show_figure(fig, key="nm_temp_fig")
    figure_downloads(fig, "bias_temperature", key="nm_temp_fig_dl")
    show_figure(warmup_figure(model), key="nm_warm_fig")
    n = model.noise
    show_table(
        pd.DataFrame(
            {
                "T (°C)": n.centres,
                "white level": n.level,
                "low": n.interval[0],
                "high": n.interval[1],
                "differences": n.count.astype(int),
            }
        ),
        hide_index=True,
    )
    st.caption(f"White level σ(τ0)√τ0 ({n.unit}) in equal-count temperature bins.")
    st.code(str(matlab_temperature_params(model).to_dict()), language="python")
    st.caption("MATLAB gyroparams/accelparams temperature terms, in the data's unit.")


def datasheet_panel(fit: InertialNoise | None, s: NoiseModelSettings) -> None:
    """The datasheet's ARW/VRW and bias instability, with units, over the data's ADEV."""
    if fit is None:
        st.caption("The comparison needs the IEEE-952 fit (rate data, overlapping ADEV).")
        return
    units = list(DATA_UNITS)
    c0, c1, c2, c3, c4 = st.columns([1.2, 1, 1, 1, 1])
    data_unit = c0.selectbox(
        "Data's unit",
        units,
        key="nm_ds_unit",
        **initial("nm_ds_unit", units.index(s.unit) if s.unit in units else 0, "index"),
    )
    dim = DATA_UNITS[data_unit][0]
    dens = [u for u, (d, _) in DENSITY_UNITS.items() if d == dim]
    bias = [u for u, (d, _) in BIAS_UNITS.items() if d == dim]
    n_value = c1.number_input(
        "ARW" if dim == "angular" else "VRW",
        min_value=0.0,
        format="%.6g",
        key="nm_ds_n",
        **initial("nm_ds_n", 0.0),
    )
    n_unit = c2.selectbox("unit", dens, key=f"nm_ds_nu_{dim}")
    b_value = c3.number_input(
        "Bias instability", min_value=0.0, format="%.6g", key="nm_ds_b", **initial("nm_ds_b", 0.0)
    )
    b_unit = c4.selectbox("unit ", bias, key=f"nm_ds_bu_{dim}")
    floor = st.checkbox("The datasheet quotes the Allan floor (0.664 B), not B", key="nm_ds_floor")
    if n_value == 0 and b_value == 0:
        st.caption("Type the datasheet's values to overlay its Allan deviation.")
        return
    with guarded("Datasheet: "):
        sheet = datasheet_terms((n_value, n_unit), (b_value, b_unit), data_unit, floor=floor)
        fig = datasheet_figure(fit.allan, sheet, fit=fit, unit=data_unit)
        show_figure(fig, key="nm_ds_fig")
        show_table(
            pd.DataFrame(
                {
                    "term": ["N", "B"],
                    "datasheet": [sheet.random_walk, sheet.bias_instability],
                    "data": [fit.random_walk, fit.bias_instability],
                    "unit": [f"{data_unit}/√Hz", data_unit],
                }
            ),
            hide_index=True,
        )


def _gmwm():
    """``fit_imu_model`` of :mod:`noisevar.noise_model.gmwm`, or None before it is merged."""
    try:
        from noisevar.noise_model.gmwm import fit_imu_model
    except ImportError:
        return None
    return fit_imu_model


@st.cache_data(max_entries=8, show_spinner="Fitting composite models (GMWM)...")
def _composite_cached(digest: str, rate: float, unit: str, robust: bool, _z: np.ndarray):
    return _gmwm()(_z, rate, unit=unit, robust=robust)


def composite_panel(sig: LoadedSignal, s: NoiseModelSettings) -> None:
    """The composite (GMWM) model: components over the wavelet variance, table, intervals."""
    if _gmwm() is None:
        st.caption("Composite noise models (noisevar.noise_model.gmwm) are not installed.")
        return
    robust = st.toggle("Robust fit (records with outliers)", key="nm_gmwm_robust")
    with guarded("Composite model: "):
        model = _composite_cached(sig.digest, s.rate, s.unit, bool(robust), sig.z)
        fig = composite_figure(model, unit=s.unit)
        show_figure(fig, key="nm_gmwm_fig")
        figure_downloads(fig, "composite_model", key="nm_gmwm_fig_dl")
        show_table(pd.DataFrame([r.to_dict() for r in model.table]), hide_index=True)
        st.caption(f"Models compared; the chosen one ({model.model}) has the lowest criterion.")
        for note in model.notes:
            st.caption(note)
        rows = [
            {
                "parameter": p.name,
                "process": p.process,
                "value": p.value,
                "low": p.interval[0],
                "high": p.interval[1],
                "unit": p.unit,
            }
            for p in model.parameters
        ]
        show_table(pd.DataFrame(rows), hide_index=True)
        fb = model.filter_bias
        st.caption(
            f"{model.ci:.1%} intervals. The bias as one random walk over {fb.horizon:g} s (the K "
            f"the exports take from the composite fit, per axis): K_eq = {fb.random_walk:.4g} "
            f"[{fb.interval[0]:.3g}, {fb.interval[1]:.3g}] {model.unit}/s/√Hz. {fb.note}"
        )
