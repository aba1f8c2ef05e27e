"""The Noise model page's consumer files: each filter's config from one IMU model (§E7).

Best fit or conservative, the gyroscope's and accelerometer's units (default: the unit
declared on the Signal page), a download per consumer, a zip of all of them and the HTML
report (verdict, units, conversions: docs/algorithms.md §E7.5).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import streamlit as st

from dashboard import cache
from dashboard.sections.noise_model import composite_cached, imu_column, imu_stretch, imu_times
from dashboard.state import LoadedSignal, initial, signal_units
from dashboard.widgets import guarded
from noisevar import units
from noisevar.errors import NoisevarError
from noisevar.estimators import estimate
from noisevar.estimators.answer import RecordAnswer, record_answer
from noisevar.estimators.regimes import StillStretch
from noisevar.noise_model import InertialNoise, exports, inertial_noise
from noisevar.noise_model.exports.report import REPORT_FILENAME, Axis, imu_report

_LABELS = {"best": "Best fit (default)", "conservative": "Conservative (overbound)"}


@st.cache_data(max_entries=32, show_spinner="Fitting the noise terms...")
def _fit(
    digest: str,
    rate: float,
    unit: str,
    regimes: str,
    stretch: StillStretch | None,
    _z: np.ndarray,
    _t: np.ndarray | None,
) -> InertialNoise:
    fit = inertial_noise(_z, rate, unit=unit, regimes=regimes, t=_t, stretch=stretch)
    assert isinstance(fit, InertialNoise)
    return fit


def _default(declared: str, target: str) -> str:
    """The Signal page's unit when it has the dimension of ``target``, else ``target``."""
    try:
        units.factor(declared, target)
    except NoisevarError:
        return target
    return declared or target


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
        stretch = imu_stretch(sig, gyro + accel, rate, regimes)
        fits = {
            (c, u): _fit(key, r, u, regimes, stretch, z, imu_times(sig, c, rate, z.size))
            for cols, u in ((gyro, g_unit), (accel, a_unit))
            for c in dict.fromkeys(cols)
            for key, r, z in [imu_column(sig, c, rate)]
        }
        axes = [("gyroscope", c, fits[c, g_unit]) for c in gyro]
        axes += [("accelerometer", c, fits[c, a_unit]) for c in accel]
        bias = {  # the composite fits of the same regimes as the IEEE-952 fits
            key: [
                composite_cached(k, r, u, regimes, z, stretch)
                for c in cols
                for k, r, z in [imu_column(sig, c, rate)]
            ]
            for key, cols, u in (("gyro_bias", gyro, g_unit), ("accel_bias", accel, a_unit))
        }
        model = exports.imu_model(
            [fits[c, g_unit] for c in gyro],
            [fits[c, a_unit] for c in accel],
            variant=variant,
            gyro_unit=g_unit,
            accel_unit=a_unit,
            **bias,
        )
        said = {c: _said(sig, c, regimes) for _, c, _ in axes}
        model = replace(model, verdicts={c: a.verdict for c, a in said.items() if a.verdict})
        files = exports.export(model, "all", params=sig.log_params)  # as the CLI: the log's
        for name, s in (("Gyroscope", model.gyro), ("Accelerometer", model.accel)):
            f = ", ".join(f"{k} x{v:.3g}" for k, v in s.factors.items())
            st.caption(
                f"{name}: N {s.N:.4g} {units.term_unit(s.unit, 'N')}, "
                f"K {s.K:.4g} {units.term_unit(s.unit, 'K')}"
                + (f"; factors over the best fit: {f}" if f else "")
            )
        st.caption(f"K from {model.k_from}.")
        for note in model.notes:
            st.caption(note)
        _downloads(files, variant)
        _report_download(sig, model, files, axes)


def report_html(
    sig: LoadedSignal,
    model: exports.ImuModel,
    files: list[exports.ExportFile],
    axes: list[tuple[str, str, InertialNoise]],
) -> str:
    """The HTML report (:func:`~noisevar.noise_model.exports.report.imu_report`): each
    column's verdict (the record's answer, method auto, as the Estimator page), the units,
    the conversions, every consumer value and each column's Allan fit."""
    from noisevar.figures.noise_model import allan_figure

    report_axes = [Axis(c, sensor, fit, _said(sig, c, model.regimes)) for sensor, c, fit in axes]
    figures = [
        allan_figure(a.fit.allan, fit=a.fit, title=f"Allan deviation of {a.column}", unit=u)
        for a in report_axes
        for u in [a.fit.unit]
    ]
    return imu_report(model, files, report_axes, source=sig.label, figures=figures)


def _said(sig: LoadedSignal, column: str, regimes: str) -> RecordAnswer:
    """A column's record answer (its samples: the signal's table or the log's topics); a
    table's column as every page reads it (:func:`dashboard.cache.column_estimate`: split at
    its time column's gaps), so the report quotes the page's R."""
    if sig.topics is None:
        return record_answer(cache.column_estimate(sig, column), regimes)
    key, _, z = imu_column(sig, column, 1.0)  # the answer is per sample: no rate
    return _answer(key, regimes, z)


@st.cache_data(max_entries=32, show_spinner="The record's answer...")
def _answer(digest: str, regimes: str, _z: np.ndarray) -> RecordAnswer:
    return record_answer(estimate(_z), regimes)


def _report_download(
    sig: LoadedSignal,
    model: exports.ImuModel,
    files: list[exports.ExportFile],
    axes: list[tuple[str, str, InertialNoise]],
) -> None:
    """The report's download button (built on click: its Allan figures take time)."""
    st.download_button(
        "Report (HTML): verdict, units, conversions",
        data=lambda: report_html(sig, model, files, axes),
        file_name=REPORT_FILENAME,
        mime="text/html",
        key="nm_dl_report",
        icon=":material/description:",
        on_click="ignore",
    )
