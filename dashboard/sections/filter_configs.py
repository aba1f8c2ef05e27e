"""The Noise model page's consumer files: each filter's config from one IMU model (§E7).

Best fit or conservative, the gyroscope's and accelerometer's units (default: the unit
declared on the Signal page), a download per consumer and a zip of all of them.
"""

from __future__ import annotations

import numpy as np
import streamlit as st

from dashboard.state import LoadedSignal, initial, signal_units
from dashboard.widgets import guarded
from noisevar import units
from noisevar.errors import NoisevarError
from noisevar.noise_model import InertialNoise, exports, inertial_noise

_LABELS = {"best": "Best fit (default)", "conservative": "Conservative (overbound)"}


@st.cache_data(max_entries=32, show_spinner="Fitting the noise terms...")
def _fit(digest: str, rate: float, unit: str, regimes: str, _z: np.ndarray) -> InertialNoise:
    fit = inertial_noise(_z, rate, unit=unit, regimes=regimes)
    assert isinstance(fit, InertialNoise)
    return fit


def _default(declared: str, target: str) -> str:
    """The Signal page's unit when it has the dimension of ``target``, else ``target``."""
    try:
        units.factor(declared, target)
    except NoisevarError:
        return target
    return declared or target


def _column(sig: LoadedSignal, name: str) -> np.ndarray:
    from noisevar.io import pick_column

    return np.asarray(pick_column(sig.table, name), dtype=float)


def _choices() -> tuple[str, str, str]:
    """Best fit or conservative, and the gyroscope's and accelerometer's units."""
    c1, c2, c3 = st.columns([2, 1, 1])
    variant = c1.radio(
        "Values",
        list(_LABELS),
        format_func=_LABELS.get,
        horizontal=True,
        key="nm_variant",
        **initial("nm_variant", 0, "index"),
    )
    declared = signal_units()
    g_unit = c2.text_input(
        "Gyroscope unit", key="nm_gyro_unit", **initial("nm_gyro_unit", _default(declared, "rad/s"))
    )
    a_unit = c3.text_input(
        "Accelerometer unit",
        key="nm_accel_unit",
        **initial("nm_accel_unit", _default(declared, "m/s^2")),
    )
    return str(variant), g_unit, a_unit


def _downloads(files: list[exports.ExportFile], variant: str) -> None:
    """A download button per consumer file, and one for a zip of all."""
    cols = st.columns(3)
    for i, f in enumerate(files):
        cols[i % 3].download_button(
            f.filename,
            f.text,
            file_name=f.filename,
            key=f"nm_dl_{f.consumer}",
            icon=":material/download:",
            on_click="ignore",
            help=exports.consumer(f.consumer).title,
        )
    st.download_button(
        "All files (zip)",
        exports.zip_exports(files),
        file_name=f"filter_configs_{variant}.zip",
        mime="application/zip",
        key="nm_dl_zip",
        icon=":material/folder_zip:",
        on_click="ignore",
    )


def consumer_files(sig: LoadedSignal, rate: float, regimes: str) -> None:
    """Every consumer's file from the gyroscope and accelerometer columns chosen above."""
    gyro = list(st.session_state.get("nm_gyro") or [])
    accel = list(st.session_state.get("nm_accel") or [])
    st.markdown(
        "**Every filter's config** (Kalibr, OpenVINS, VINS, ORB-SLAM3, "
        "robot_localization, PX4, ArduPilot, MATLAB, filterpy)"
    )
    variant, g_unit, a_unit = _choices()
    if not (gyro and accel):
        st.caption("Choose the gyroscope and accelerometer columns above.")
        return
    with guarded("Filter configs: "):
        fits = {
            c: _fit(f"{sig.table_digest}:{c}", rate, "", regimes, _column(sig, c))
            for c in dict.fromkeys(gyro + accel)
        }
        model = exports.imu_model(
            [fits[c] for c in gyro],
            [fits[c] for c in accel],
            variant=variant,
            gyro_unit=g_unit,
            accel_unit=a_unit,
        )
        files = exports.export(model, "all")
        for name, s in (("Gyroscope", model.gyro), ("Accelerometer", model.accel)):
            f = ", ".join(f"{k} x{v:.3g}" for k, v in s.factors.items())
            st.caption(
                f"{name}: N {s.N:.4g} {units.term_unit(s.unit, 'N')}, "
                f"K {s.K:.4g} {units.term_unit(s.unit, 'K')}"
                + (f"; factors over the best fit: {f}" if f else "")
            )
        for note in model.notes:
            st.caption(note)
        _downloads(files, variant)
