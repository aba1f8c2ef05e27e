"""The Fleet page's parts: get a batch table, show the fleet's spread, open a sensor."""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

import pandas as pd
import streamlit as st

import noisevar
from dashboard.cache import DEFAULT_METHOD
from dashboard.loading import load_bytes
from dashboard.pages import ESTIMATOR
from dashboard.sections.regimes import still_choice
from dashboard.session_dirs import SessionFolder, session_folder
from dashboard.state import reselect
from dashboard.widgets import blank_frame, csv_download, fmt, guarded, show_figure, show_table
from noisevar.batch import read_table
from noisevar.batch.example import EXAMPLE_CHANNELS, write_example_fleet
from noisevar.batch.fleet import DEFAULT_THRESHOLD, FleetReport, SensorScore
from noisevar.errors import NoisevarError
from noisevar.estimators.answer import STILL_LEVELS_NOTE, row_still_levels, still_level_rows
from noisevar.estimators.results import FLAG_PREFIX
from noisevar.figures.fleet import flagged_sensors, fleet_distribution

#: Session keys: the batch table, where it came from, the folder of uploaded/example files.
TABLE_KEY = "nv_fleet_table"
LABEL_KEY = "nv_fleet_label"
FOLDER_KEY = "nv_fleet_folder"
SOURCES = ("Example fleet", "Batch table", "Run a batch")
#: At most this many verdicts in the regime warning.
MAX_VERDICTS = 5


def _folder(sub: str) -> Path:
    """A folder of this session for files the page writes (uploads, the example fleet)."""
    owner = st.session_state.get(FOLDER_KEY)
    if not isinstance(owner, SessionFolder) or not owner.path.is_dir():
        owner = session_folder()  # removed with the session (dashboard/session_dirs.py)
        st.session_state[FOLDER_KEY] = owner
    path = owner.path / sub
    path.mkdir(parents=True, exist_ok=True)
    return path


def _set_table(frame: pd.DataFrame, label: str) -> None:
    st.session_state[TABLE_KEY] = frame
    st.session_state[LABEL_KEY] = label


def current_table() -> tuple[pd.DataFrame | None, str]:
    """The fleet's batch table and its label (None before one is loaded)."""
    frame = st.session_state.get(TABLE_KEY)
    return (frame if isinstance(frame, pd.DataFrame) else None), st.session_state.get(LABEL_KEY, "")


def _run_batch(paths: list[Path], method: str, label: str) -> None:
    """Run :func:`noisevar.batch` with a progress bar; the table becomes the fleet's."""
    bar = st.progress(0.0, text="Estimating...")

    def progress(done: int, total: int) -> None:
        bar.progress(done / total if total else 1.0, text=f"{done} of {total} files")

    frame = noisevar.batch([str(p) for p in paths], method=method, progress=progress)
    bar.empty()
    _set_table(frame, label)


def source_panel() -> None:
    """Where the batch table comes from: the example fleet, an uploaded table, or a run."""
    source = st.segmented_control("Fleet from", SOURCES, key="fl_source", default=SOURCES[0])
    method = DEFAULT_METHOD
    if source == "Batch table":
        up = st.file_uploader(
            "A batch table (`noisevar batch ... --out noise.parquet`)",
            type=["parquet", "csv"],
            key="fl_table",
        )
        if up is not None and st.button("Load this table", key="fl_load", type="primary"):
            with guarded():
                _set_table(read_table(up.getvalue(), up.name), up.name)
        return
    if source == "Run a batch":
        ups = st.file_uploader(
            "Several logs (CSV/TSV, .npy, NMEA): each file is one sensor",
            accept_multiple_files=True,
            key="fl_files",
        )
        method = st.selectbox("Method", noisevar.methods(), key="fl_method")
        if ups and st.button(f"Estimate {len(ups)} files", key="fl_run", type="primary"):
            folder = _folder("uploads")
            paths = []
            for up in ups:
                path = folder / Path(up.name).name
                path.write_bytes(up.getvalue())
                paths.append(path)
            with guarded():
                _run_batch(paths, method, f"{len(paths)} uploaded files")
        return
    example = {k: p.default for k, p in inspect.signature(write_example_fleet).parameters.items()}
    st.caption(
        f"{example['n_sensors']} IMU logs ({', '.join(EXAMPLE_CHANNELS)}) of a production line; "
        f"{len(example['noisy'])} unit has {example['factor']:g} times the noise on one axis."
    )
    if st.button("Run the example fleet", key="fl_example", type="primary"):
        with guarded():
            paths = write_example_fleet(_folder("example"))
            _run_batch(paths, method, f"example fleet ({len(paths)} IMUs)")


def summary(report: FleetReport, frame: pd.DataFrame, label: str) -> None:
    """Headline numbers and one sentence per flagged sensor."""
    c = st.columns(4)
    c[0].metric("Sensors (files)", f"{frame['file'].nunique():,}")
    c[1].metric("Channels", f"{len(report.channels)}")
    c[2].metric("Flagged", f"{len(report.flagged)}")
    c[3].metric("Rows with an error", f"{report.n_errors}")
    st.caption(f"Table: {label}.")
    for note in report.notes:
        st.caption(note)
    for warning in report.warnings:  # identical files, differing sample rates
        st.warning(warning, icon=":material/warning:")
    if report.flagged:
        st.warning("\n".join(f"- {s.sentence}" for s in report.flagged))
    elif report.channels:
        st.success(
            "No sensor is outside the fleet's normal range "
            f"(robust z-score of log std within ±{report.threshold:g} on every channel)."
        )
    for spread in report.channels:
        st.caption(
            f"{spread.channel}: typical noise std {fmt(spread.median_std)}, normal range "
            f"{fmt(spread.low)} to {fmt(spread.high)} over {spread.n_sensors} sensors."
        )


def _label(s: SensorScore) -> str:
    return f"{Path(s.file).name} · {s.channel}" + ("  (flagged)" if s.flagged else "")


def _clicked(key: str) -> tuple[str, str] | None:
    """The ``[file, channel]`` of a point clicked on the distribution figure, if any."""
    event: Any = st.session_state.get(key)
    try:
        points = event["selection"]["points"]
    except (KeyError, TypeError):
        return None
    for p in points:
        data = p.get("customdata") if isinstance(p, dict) else None
        if data and len(data) == 2:
            return str(data[0]), str(data[1])
    return None


def figures(report: FleetReport) -> None:
    """The distribution per channel (click a point to pick it) and the most unusual sensors."""
    if not report.channels:
        st.info("No channel has enough sensors (3) to compare.")
        return
    show_figure(fleet_distribution(report), key="fl_dist", select="points")
    show_figure(flagged_sensors(report))


def open_sensor(report: FleetReport) -> None:
    """Pick a sensor (or click it above) and open it on the Estimator page."""
    sensors = list(report.sensors)
    if not sensors:
        return
    labels = [_label(s) for s in sensors]
    clicked = _clicked("fl_dist")
    if clicked is not None:
        for s, lab in zip(sensors, labels, strict=True):
            if (s.file, s.channel) == clicked:
                st.session_state["fl_sensor"] = lab
    if st.session_state.get("fl_sensor") not in labels:
        st.session_state["fl_sensor"] = labels[0]
    c1, c2 = st.columns([3, 1], vertical_alignment="bottom")
    chosen = c1.selectbox("Sensor", labels, key="fl_sensor")
    sensor = sensors[labels.index(chosen)]
    st.caption(sensor.sentence)
    if c2.button("Open on the Estimator page", key="fl_open", type="primary"):
        with guarded():
            _open(sensor)
            st.switch_page(ESTIMATOR.path)


def _open(sensor: SensorScore) -> None:
    """Make the sensor's channel the session's signal (raises NoisevarError)."""
    path = Path(sensor.file)
    if not path.is_file():
        raise NoisevarError(
            f"{sensor.file} is not on this server: open it on the Signal page instead"
        )
    sig = load_bytes(path.read_bytes(), path.name)
    if sig.column != sensor.channel:
        reselect(sig, sensor.channel, sig.sample_period)


def table(report: FleetReport, frame: pd.DataFrame) -> None:
    """The sensors' scores and the batch table, with a CSV download."""
    with st.expander("Every sensor and the batch table"):
        show_table(blank_frame(report.to_frame()), hide_index=True)
        show_table(blank_frame(frame), hide_index=True)
        csv_download(st, "Batch table as CSV", frame.to_csv(index=False), "fleet.csv", "fl_csv")


def threshold_input() -> float:
    """The ``|z|`` threshold of a flag."""
    return float(
        st.number_input(
            "Flag beyond robust |z| of",
            min_value=1.0,
            max_value=100.0,
            step=0.5,
            value=DEFAULT_THRESHOLD,
            key="fl_threshold",
        )
    )


def regime_choice(frame: pd.DataFrame) -> str:
    """The rows whose noise level varies, with their verdicts, and the still-regimes choice.

    Returns ``"still"`` when "use the still regimes only" is ticked (offered when a row's
    level varies): each sensor's R is then its still regimes' (``still_variance``).
    """
    flag = FLAG_PREFIX + "level_varies"
    moving = frame[frame[flag].fillna(False).astype(bool)] if flag in frame.columns else frame[:0]
    if len(moving):
        lines = [
            f"- {Path(str(r['file'])).name} · {r['channel']}: {r.get('verdict') or ''}"
            for _, r in moving.head(MAX_VERDICTS).iterrows()
        ]
        more = len(moving) - MAX_VERDICTS
        st.warning(
            f"The noise level varies along {len(moving)} of {len(frame)} records (motion among "
            "still stretches):\n"
            + "\n".join(lines)
            + (f"\n- and {more} more (the table below has every verdict)" if more > 0 else ""),
            icon=":material/warning:",
        )
    _still_levels(moving)
    return still_choice(
        "fl_regimes",
        bool(len(moving)),
        help="Each sensor's noise is then its still regimes' (the batch table's "
        "still_variance), where its level varies; its whole record's where it does not.",
    )


def _still_levels(moving: pd.DataFrame) -> None:
    """The moving rows' other still levels (the batch table's ``other_still_levels``) as
    one small table, a row per level, under what they mean (nothing when there is none)."""
    if "other_still_levels" not in moving.columns:
        return
    rows = []
    for _, r in moving.iterrows():
        n, still = r.get("n_total"), r.get("still_variance")
        if pd.isna(n) or pd.isna(still):
            continue
        levels = row_still_levels(r["other_still_levels"])
        sensor = {"Sensor": f"{Path(str(r['file'])).name} · {r['channel']}"}
        rows += [sensor | x for x in still_level_rows(levels, int(n), float(still))]
    if rows:
        st.caption(STILL_LEVELS_NOTE)
        show_table(pd.DataFrame(rows), hide_index=True, width="stretch")
