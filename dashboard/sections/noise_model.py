"""The Noise model page's parts: Allan deviation, IEEE-952 terms, Kalibr, simulation (§E4)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import streamlit as st

from dashboard import cache
from dashboard.sections.regimes import regime_choice
from dashboard.state import LoadedSignal, initial, signal_units
from dashboard.widgets import figure_downloads, fmt, guarded, show_figure, show_table
from noisevar.errors import NoisevarError
from noisevar.estimators.answer import REGIME_WARNING, WHY_DIFFERENT, record_answer
from noisevar.estimators.regimes import DEFAULT_REGIMES, still_used, variance_for
from noisevar.figures.noise_model import allan_figure
from noisevar.format import squared
from noisevar.io import record_times
from noisevar.noise_model import AllanResult, InertialNoise, allan, exports, inertial_noise
from noisevar.noise_model.allan import DATA_KINDS, KINDS, default_data
from noisevar.noise_model.inertial_misfit import MISFIT
from noisevar.noise_model.kalibr import kalibr_imu
from noisevar.noise_model.simulate import simulate_inertial
from noisevar.units import sensor_columns

_KIND_LABELS = {"oadev": "Overlapping ADEV", "mdev": "Modified ADEV", "hdev": "Overlapping HDEV"}


@dataclass(frozen=True)
class NoiseModelSettings:
    """The page's choices (``regimes``: the whole record or its still regimes only)."""

    rate: float
    data: str
    kind: str
    unit: str
    regimes: str = DEFAULT_REGIMES


def record_summary(sig: LoadedSignal, regimes: str) -> dict[str, str] | None:
    """The record's answer (method auto, as the Estimator page) for the exported configs."""
    try:
        est = cache.estimate(sig, cache.DEFAULT_METHOD, {})
    except NoisevarError:  # said by the regime panel above
        return None
    return record_answer(est, regimes).summary(signal_units())


def regime_panel(sig: LoadedSignal) -> str:
    """The record's R (method auto, as the Estimator page), the regime warning and choice.

    Returns ``"still"`` when "use the still regimes only" is ticked (offered when the
    level varies), else ``"all"``.
    """
    est = None
    with guarded("Noise estimate: "):
        est = cache.estimate(sig, cache.DEFAULT_METHOD, {})
    regimes = regime_choice(
        [(None, est)],
        key="nm_regimes",
        help="R, the Allan deviation, the noise terms, Kalibr and the Kalman fits below then "
        "use the record's longest still stretch (each Kalibr column its own).",
    )
    if est is not None:
        value = variance_for(est, regimes)
        where = "its still regimes" if still_used(est, regimes) else "the whole record"
        st.metric(
            "Noise variance R",
            fmt(value, unit=squared(signal_units())),  # as the Estimator page writes it
            help=f"Method {est.method}, as on the Estimator page, over {where}.",
        )
        if still_used(est, regimes):
            st.caption(f"This page's R differs from the record's answer: {WHY_DIFFERENT['still']}.")
    return regimes


def settings_form(sig: LoadedSignal, regimes: str = DEFAULT_REGIMES) -> NoiseModelSettings:
    """Sample rate (default: the signal's), phase or rate data, deviation, unit."""
    default_rate = 1.0 / sig.sample_period if sig.sample_period else 1.0
    c1, c2, c3, c4 = st.columns(4)
    rate = c1.number_input(
        "Sample rate (Hz)",
        min_value=0.0,
        format="%.6g",
        key="nm_rate",
        **initial("nm_rate", float(default_rate)),
    )
    declared = signal_units() or "u"  # the unit declared on the Signal page
    data = c2.radio(
        "The samples are",
        DATA_KINDS,
        horizontal=True,
        key="nm_data",
        help="rate: gyro rate, specific force, fractional frequency; phase: angle, time error "
        "(default: phase for a unit of time, else rate, as `noisevar allan`)",
        **initial("nm_data", DATA_KINDS.index(default_data(declared)), "index"),
    )
    kind = c3.selectbox(
        "Deviation",
        list(KINDS),
        format_func=_KIND_LABELS.get,
        key="nm_kind",
        **initial("nm_kind", 0, "index"),
    )
    unit = c4.text_input("Unit of the rate", key="nm_unit", **initial("nm_unit", declared))
    return NoiseModelSettings(float(rate), str(data), str(kind), unit.strip() or "u", regimes)


@st.cache_data(max_entries=16, show_spinner="Allan deviation...")
def _allan_cached(
    digest: str,
    rate: float,
    data: str,
    kind: str,
    regimes: str,
    _z: np.ndarray,
    _t: np.ndarray | None = None,
) -> AllanResult:
    return allan(_z, rate=rate, data=data, kind=kind, regimes=regimes, t=_t)


@st.cache_data(max_entries=16, show_spinner="Fitting the noise terms...")
def _fit_cached(
    digest: str,
    rate: float,
    unit: str,
    regimes: str,
    _z: np.ndarray,
    _t: np.ndarray | None = None,
    stretch: Any = None,
) -> InertialNoise:
    fit = inertial_noise(_z, rate, unit=unit, regimes=regimes, t=_t, stretch=stretch)
    assert isinstance(fit, InertialNoise)
    return fit


@st.cache_data(max_entries=16, show_spinner="Finding where every IMU axis is still...")
def _imu_stretch_cached(digests: tuple[str, ...], _rows: np.ndarray) -> Any:
    from noisevar.noise_model.inertial_axes import imu_still_stretch

    return imu_still_stretch(_rows)


def imu_stretch(sig: LoadedSignal, cols: list[str], rate: float, regimes: str) -> Any:
    """With the still regimes: the IMU's stretch where every chosen axis is still, which all
    its fits take, as ``noisevar imu --regimes still --export`` (None for axes of different
    lengths, a log's two topics: each axis its own)."""
    if regimes != "still":
        return None
    got = [imu_column(sig, c, rate) for c in dict.fromkeys(cols)]
    if len({z.size for *_, z in got}) != 1:
        return None
    return _imu_stretch_cached(tuple(k for k, *_ in got), np.stack([z for *_, z in got]))


def terms_table(fit: InertialNoise) -> pd.DataFrame:
    """The fitted terms: value, interval, unit and the per-sample equivalent."""
    return pd.DataFrame(
        [
            {
                "term": t.name.replace("_", " "),
                "symbol": t.symbol,
                "value": t.value,
                "low": t.interval[0],
                "high": t.interval[1],
                "unit": t.unit,
                "per sample": t.discrete,
                "per-sample unit": t.discrete_unit,
                "slope": t.slope,
            }
            for t in fit.terms
        ]
    )


def results(sig: LoadedSignal, s: NoiseModelSettings) -> InertialNoise | None:
    """The Allan deviation, the fitted terms (rate data, OADEV) and the simulated overlay."""
    res: AllanResult | None = None
    fit: InertialNoise | None = None
    with guarded():
        t = imu_times(sig, None, s.rate, sig.z.size)  # a log that drops samples
        res = _allan_cached(sig.digest, s.rate, s.data, s.kind, s.regimes, sig.z, t)
        if s.data == "rate" and s.kind == "oadev":
            fit = _fit_cached(sig.digest, s.rate, s.unit, s.regimes, sig.z, t)
    if res is None:
        return None
    for note in res.notes:
        st.caption(note)
    if not (s.data == "rate" and s.kind == "oadev"):
        st.caption("The IEEE-952 terms are fitted to the overlapping ADEV of rate data.")
    elif fit is not None:
        show_table(terms_table(fit), hide_index=True)
        st.caption(
            f"{fit.ci:.1%} intervals. Continuous-time values; *per sample* is the discrete "
            f"equivalent at {s.rate:g} Hz (docs/algorithms.md §E4)."
        )
        for note in fit.notes:  # what the fit assumes and where the record breaks it
            if note in res.notes:  # the deviation's own note, shown above
                continue
            warns = REGIME_WARNING in note or note.startswith(MISFIT)  # its terms mislead
            (st.warning if warns else st.caption)(note)
    simulated = _simulation(sig, s, fit)
    fig = allan_figure(res, fit=fit, simulated=simulated, unit=s.unit)
    show_figure(fig, key="nm_fig")
    figure_downloads(fig, "allan_deviation", key="nm_fig_dl")
    return fit


def _simulation(sig: LoadedSignal, s: NoiseModelSettings, fit: InertialNoise | None):
    """The "simulate from the fitted model" button; the simulated ADEV (kept per fit)."""
    if fit is None:
        return None
    key = (sig.digest, s.rate, s.unit, s.regimes)
    c1, c2 = st.columns([1, 3])
    seed = c2.number_input(
        "Simulation seed", 0, 2**31 - 1, key="nm_sim_seed", **initial("nm_sim_seed", 0)
    )
    if c1.button("Simulate from the fitted model", key="nm_simulate", icon=":material/casino:"):
        bar = st.progress(0.0, text="Simulating each term...")
        values = {t.name: t.value for t in fit.terms}
        # the length of the fitted record (its still stretch with the still regimes only)
        y = simulate_inertial(fit.allan.n_samples, s.rate, seed=int(seed), **values)
        bar.progress(0.5, text="Allan deviation of the simulated record...")
        st.session_state["nm_sim"] = (key, allan(y, rate=s.rate, data="rate"))
        bar.progress(1.0, text="Done")
        bar.empty()
    stored = st.session_state.get("nm_sim")
    if stored and stored[0] == key:
        st.caption(
            "The simulated record (same length, drawn from the fitted terms) is "
            "overlaid: each term shows where its slope dominates."
        )
        return stored[1]
    return None


def imu_columns(sig: LoadedSignal) -> list[str]:
    """The gyroscope and accelerometer pickers' columns: the loaded file's, or every column
    of the log's chosen topics (field, or ``topic/field`` when topics share it)."""
    return sig.topics.columns if sig.topics is not None else list(sig.table.data_columns)


def imu_column(sig: LoadedSignal, name: str, rate: float) -> tuple[str, float, np.ndarray]:
    """One IMU column: its cache key, its rate (its topic's for a log's chosen topics, else
    the page's ``rate``) and its samples."""
    if sig.topics is None:
        return f"{sig.table_digest}:{name}", rate, _column(sig, name)
    col = sig.topics.column(name)
    if col.rate is None:
        raise NoisevarError(f"topic {col.topic} has no sample rate from its times")
    return f"{sig.topics_key}:{col.name}", col.rate, col.values


def imu_times(sig: LoadedSignal, name: str | None, rate: float, n: int) -> np.ndarray | None:
    """One IMU column's sample times (``name`` None: the signal's), as the command line
    passes them (a log that drops samples is placed on its sample grid:
    :mod:`noisevar.noise_model.allan_gaps`): its topic's, or the file's when the page's rate
    is the file's; None when the user set another rate (the samples are then uniform at
    it, as ``--rate`` does)."""
    if sig.topics is not None and name is not None:
        t = record_times(sig.topics.tables[sig.topics.column(name).topic])
    elif sig.times is not None and sig.sample_period and abs(rate * sig.sample_period - 1) < 1e-9:
        t = sig.times
    else:
        return None
    return t if t is not None and t.size == n else None


def _topic_rates(sig: LoadedSignal) -> None:
    """Say each chosen topic's rate (its columns are fitted at it, not at the page's)."""
    if sig.topics is None:
        return
    said = ", ".join(
        f"{t} {r:g} Hz" if r else f"{t} (no rate)" for t, r in sig.topics.rates.items()
    )
    st.caption(
        f"Columns of the log's topics {said}: each column is fitted at its own topic's "
        "rate (from the log's timestamps; never resampled), not at the sample rate above."
    )


@st.cache_data(max_entries=32, show_spinner="Fitting the composite model (K)...")
def composite_cached(
    digest: str, rate: float, unit: str, regimes: str, _z: np.ndarray, stretch: Any = None
):
    """A column's composite fit on ``regimes`` (and the IMU's still ``stretch``, when given),
    whose bias gives the files' K (``exports.imu_model``, ``kalibr_imu``)."""
    (fit,) = exports.composite_fits([_z], [rate], unit=unit, regimes=regimes, stretch=stretch)
    return fit


def _sensor_defaults(sig: LoadedSignal, cols: list[str]) -> None:
    """The gyroscope and accelerometer pickers start on the columns the file declares in an
    angular-rate and an acceleration unit, not their norm (as ``noisevar imu --export``
    takes them), and drop a choice the loaded file does not have."""
    if sig.topics is not None:
        picked = {c: sig.topics.column(c) for c in cols}
        units = {c: col.unit for c, col in picked.items()}
        data = {c: col.values for c, col in picked.items()}
    else:
        units = {c: sig.table.units.get(c) for c in cols}
        data = {c: sig.table.columns[c] for c in cols}
    for key, found in zip(("nm_gyro", "nm_accel"), sensor_columns(units, data), strict=True):
        held = st.session_state.get(key)
        if held is None or any(c not in cols for c in held):
            st.session_state[key] = found


def kalibr_export(sig: LoadedSignal, s: NoiseModelSettings) -> None:
    """Kalibr imu.yaml from the gyroscope and accelerometer columns of the loaded file."""
    cols = imu_columns(sig)
    _topic_rates(sig)
    if sig.topics is None:
        c1, c2, c3 = st.columns([2, 2, 1])
    else:  # topic/field names: a picker a row, or three chips overflow a half-width box
        c1, c2, c3 = st.container(), st.container(), st.columns([1, 3])[0]
    _sensor_defaults(sig, cols)
    gyro = c1.multiselect("Gyroscope columns (rad/s)", cols, key="nm_gyro")
    accel = c2.multiselect("Accelerometer columns (m/s²)", cols, key="nm_accel")
    inflation = c3.number_input(
        "Inflation",
        min_value=0.0,
        format="%.6g",
        key="nm_inflation",
        **initial("nm_inflation", 1.0),
    )
    if not (gyro and accel):
        st.caption("Choose the gyroscope and accelerometer columns of the loaded file.")
        return
    with guarded("Kalibr export: "):
        stretch = imu_stretch(sig, gyro + accel, s.rate, s.regimes)
        fits = {
            c: _fit_cached(key, rate, "", s.regimes, z, imu_times(sig, c, s.rate, z.size), stretch)
            for c in dict.fromkeys(gyro + accel)
            for key, rate, z in [imu_column(sig, c, s.rate)]
        }
        bias = {  # the composite fits of the same regimes as the IEEE-952 fits
            key: [
                composite_cached(k, r, "", s.regimes, z, stretch)
                for c in cols
                for k, r, z in [imu_column(sig, c, s.rate)]
            ]
            for key, cols in (("gyro_bias", gyro), ("accel_bias", accel))
        }
        imu = kalibr_imu(
            [fits[c] for c in gyro], [fits[c] for c in accel], inflation=float(inflation), **bias
        )
        st.code(imu.to_yaml(), language="yaml")
        st.download_button(
            "Kalibr imu.yaml",
            imu.to_yaml(),
            file_name="imu.yaml",
            mime="application/x-yaml",
            key="nm_kalibr_dl",
            icon=":material/download:",
            on_click="ignore",
        )


def _column(sig: LoadedSignal, name: str) -> np.ndarray:
    from noisevar.io import pick_column

    return np.asarray(pick_column(sig.table, name), dtype=float)
