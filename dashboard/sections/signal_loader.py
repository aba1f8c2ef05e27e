"""Loading the signal from a page: sample buttons, the generator form, the uploader, offers."""

from __future__ import annotations

from collections.abc import Sequence

import streamlit as st
from streamlit.delta_generator import DeltaGenerator

import noisevar
from dashboard import loading
from dashboard.pages import SIGNAL
from dashboard.state import LoadedSignal, current_signal
from dashboard.text import plain
from dashboard.url_params import RECIPE_PARAMS
from dashboard.widgets import guarded, how_it_works, param_input
from noisevar.io.logs import default_topic, readers
from noisevar.io.series_option import SERIES, SERIES_CONTROL
from noisevar.io.time_option import TIME_UNIT, TIME_UNIT_CONTROL, TIME_UNIT_EXAMPLES
from noisevar.signals import PAPER_SIGNAL, signal_spec


def require_signal(
    purpose: str = "This page works on the loaded signal.",
    preferred: Sequence[str] = ("fast_slow.csv",),
    explain: Sequence[str] | None = None,
) -> LoadedSignal:
    """The loaded signal; without one, say so, offer sample data and stop the page.

    Parameters
    ----------
    purpose : str
        What the page would do with a signal.
    preferred : sequence of str
        Sample files to offer first.
    explain : sequence of str, optional
        The page's how-it-works blocks, shown before the page stops.

    Returns
    -------
    LoadedSignal
    """
    sig = current_signal()
    if sig is not None:
        return sig
    st.info(
        f"No signal loaded yet. {purpose} Load a sample file with one click, generate the "
        "paper's signal, or upload your own on the Signal page."
    )
    names = [p.name for p in loading.sample_files()]
    order = [n for n in preferred if n in names] + [n for n in names if n not in preferred]
    desc = loading.sample_descriptions()
    cols = st.columns(3)
    for i, name in enumerate(order):
        with cols[i % 3]:
            if st.button(f"Load {name}", key=f"offer_{name}", help=desc.get(name)):
                with guarded():
                    loading.load_sample(name)
                    st.rerun()
    paper = loading.paper_signal_defaults()
    label = f"Generate the paper's {PAPER_SIGNAL} signal (n = {paper['n']}, seed {paper['seed']})"
    if st.button(label, key="offer_gen"):
        with guarded():
            loading.load_paper_signal()
            st.rerun()
    st.page_link(SIGNAL.path, label="Go to the Signal page", icon=":material/upload:")
    if explain:
        how_it_works(*explain)
    st.stop()
    raise AssertionError("unreachable")  # pragma: no cover


def quick_start() -> None:
    """The home page's two buttons: the sample fast_slow.csv or the generated paper signal."""
    st.info("Start by loading a signal: a sample file, a generated scenario, or your own file.")
    c1, c2 = st.columns(2)
    with c1:
        if st.button("Load the sample fast_slow.csv", key="home_sample", type="primary"):
            with guarded():
                loading.load_sample("fast_slow.csv")
                st.rerun()
    with c2:
        if st.button(f"Generate the paper's {PAPER_SIGNAL} signal", key="home_generate"):
            with guarded():
                loading.load_paper_signal()
                st.rerun()


def sample_buttons(errors: DeltaGenerator) -> None:
    """One button per file of ``sample_data/`` with its description."""
    files = loading.sample_files()
    desc = loading.sample_descriptions()
    if not files:
        st.info("The sample_data/ folder is empty: generate a signal instead.")
    for path in files:
        c1, c2 = st.columns([1, 4], vertical_alignment="center")
        if c1.button(
            path.name, key=f"sample_{path.name}", icon=":material/dataset:", width="stretch"
        ):
            with errors, guarded(f"{path.name}: "):
                loading.load_sample(path.name)
        c2.caption(desc.get(path.name, f"{path.stat().st_size / 1e3:.0f} kB"))


def generator_form(errors: DeltaGenerator) -> None:
    """The scenario generator: family, n, noise std, seed, the family's own parameters.

    Every widget comes from a parameter spec: ``n``, the noise std and the seed from the
    link's limits (:data:`~dashboard.url_params.RECIPE_PARAMS`), the rest from the
    family's spec (:func:`noisevar.signals.signal_spec`).
    """
    names = noisevar.signal_names()
    c1, c2, c3, c4 = st.columns(4)
    family = c1.selectbox(
        "Scenario",
        names,
        key="gen_name",
        bind="query-params",
        help="Signal families of noisevar.generate (see its docstring).",
    )
    n = param_input(RECIPE_PARAMS["n"], "gen_n", c2, "Samples n", step=1000)
    noise_std = param_input(
        RECIPE_PARAMS["noise_std"],
        "gen_std",
        c3,
        "Noise std (empty: scenario default)",
        placeholder="default",
    )
    seed = param_input(RECIPE_PARAMS["seed"], "gen_seed", c4, "Seed")
    extras = signal_spec(family).extras
    values = {}
    for spec, col in zip(extras, st.columns(max(len(extras), 2)) if extras else (), strict=False):
        values[spec.name] = param_input(spec, f"gen_{family}_{spec.name}", col)
    if st.button("Generate", key="gen_go", type="primary", icon=":material/play_arrow:"):
        with errors, guarded("Generate: "):
            loading.load_generated(family, n=n, seed=seed, noise_std=noise_std, **values)


def _log_topic(up, errors: DeltaGenerator) -> tuple[str, list[str]] | None | bool:
    """For an uploaded log, the signal's topic picked in a selectbox and the topics read
    beside it (a multiselect: the Noise model page's IMU columns); None: not a log; False:
    the log cannot be read, said in ``errors``."""
    try:
        topics = loading.log_topics(up.getvalue(), up.name)
    except noisevar.NoisevarError as exc:
        errors.error(str(exc))
        return False
    if topics is None:
        return None
    usable = [t for t in topics if t.fields and t.count > 0]
    if not usable:
        errors.error(f"{up.name} holds no topic with numbers")
        return False
    labels = {
        t.name: f"{t.name} ({t.message}, {t.count:,} records"
        + (f", {t.rate:.4g} Hz)" if t.rate else ")")
        for t in usable
    }
    first = default_topic(usable)  # an IMU's topic when the log has one
    topic = st.selectbox(
        "Topic",
        list(labels),
        index=list(labels).index(first.name) if first is not None else 0,
        format_func=labels.get,
        key=f"upload_topic_{up.file_id}",
    )
    others = [t for t in labels if t != topic]
    also = st.multiselect(
        "More topics of this log (IMU model)",
        others,
        format_func=labels.get,
        key=f"upload_topics_{up.file_id}",
        help="Read these topics too: the Noise model page's gyroscope and accelerometer "
        "columns then come from every chosen topic (e.g. PX4's sensor_gyro_fifo and "
        "sensor_accel_fifo), each at its own topic's rate; a field several topics share "
        "is named topic/field.",
    )
    return topic, [t for t in also if t in others]


def _time_unit(where: DeltaGenerator) -> str | None:
    """The unit of the file's times (:data:`noisevar.io.time_option.TIME_UNIT`): any unit of
    time typed in, or one of the examples; None: as the file states (else seconds)."""
    unit = where.selectbox(
        TIME_UNIT_CONTROL,
        [AS_THE_FILE, *TIME_UNIT_EXAMPLES],
        key="upload_time_unit",
        accept_new_options=True,
        help=f"{TIME_UNIT.help[:1].upper()}{TIME_UNIT.help[1:]} (CLI: {TIME_UNIT.flag}; the "
        "exported configs carry it).",
    )
    return None if unit in (None, AS_THE_FILE) or not str(unit).strip() else str(unit).strip()


#: The time-unit control's default: the unit the file states, else seconds (said in a note).
AS_THE_FILE = "as the file states"


def uploader(errors: DeltaGenerator) -> None:
    """The file uploader; a failed file is reported once per file (the old signal stays)."""
    limit_mb = loading.max_upload_bytes() / 1024 / 1024
    st.caption(
        f"CSV/TSV (header optional; a column named t/time gives the sample period; a decimal "
        f"comma with `;` separators, as European spreadsheets export, is read too), `.npy` "
        f"(numeric arrays only), or NMEA 0183 GGA/RMC (converted to local east/north metres, "
        f"speed and course); or a log or workbook, one topic (a sheet) for the signal (more "
        f"for the IMU model) with its own timestamps: {_log_kinds()}. A ROS bag cut short, or "
        f"a recorder's `.bag.active`, is read up to its cut. Any other file is read by what it "
        f"holds, as `noisevar estimate` reads it (RTKLIB `.pos` solutions, LAS well logs, "
        f"IAGA-2002 observatory files...), or refused saying what it is. Up to "
        f"{limit_mb:.0f} MB."
    )
    # any suffix: the loader reads a file by what it holds (an RTKLIB .pos, a LAS well
    # log), as `noisevar estimate` does, and refuses the rest in one line
    up = st.file_uploader("Upload a file", key="upload")
    c1, c2 = st.columns([3, 2], vertical_alignment="bottom")
    drop = c1.checkbox(
        "Drop rows with empty or NaN values",
        key="upload_drop",
        help="Otherwise a column with empty or NaN cells is refused (CLI: --drop-nonfinite).",
    )
    time_unit = _time_unit(c2)
    if up is None:
        return
    picked = _log_topic(up, errors)
    if picked is False:
        return
    topic, also = picked if picked else (None, [])
    series = _series(up.file_id, st.container())
    attempt = (up.file_id, bool(drop), topic, tuple(also), time_unit, series)
    failed = st.session_state.get("upload_failed")
    if st.session_state.get("upload_done") != attempt and (not failed or failed[0] != attempt):
        try:
            with st.spinner(f"Reading {up.name}..."):
                loading.load_bytes(
                    up.getvalue(),
                    up.name,
                    drop_nonfinite=bool(drop),
                    topic=topic,
                    also=also,
                    time_unit=time_unit,
                    series=series,
                )
            st.session_state["upload_done"] = attempt
            st.session_state.pop("upload_failed", None)
        except noisevar.EmptyCells as exc:  # the checkbox above is this page's way to drop them
            st.session_state["upload_failed"] = (attempt, f"{exc}. {DROP_HERE}")
        except noisevar.StackedSeries as exc:  # the picker is this page's way to read one
            st.session_state[STACKED] = (up.file_id, exc.column, exc.labels, exc.n_labels)
            st.session_state.pop("upload_series", None)  # another file's label
            st.session_state["upload_failed"] = (attempt, f"{exc}. {PICK_HERE}")
            st.rerun()  # the picker shows its labels
        except noisevar.NoisevarError as exc:
            st.session_state["upload_failed"] = (attempt, str(exc))
    failed = st.session_state.get("upload_failed")
    if failed and failed[0] == attempt:
        sig = current_signal()
        kept = f" (The previous signal, {plain(sig.label)}, is kept.)" if sig is not None else ""
        errors.error(plain(failed[1]) + kept)


#: Where this page drops empty cells, said beside a refusal of them.
DROP_HERE = "Here: tick 'Drop rows with empty or NaN values' in the Upload tab"
#: Where this page reads one series of a stacked file, said beside a refusal of it.
PICK_HERE = f"Here: pick one in '{SERIES_CONTROL}' in the Upload tab, under the uploader"
#: Session key of the last upload refused as stacked: (file id, column, labels, count).
STACKED = "upload_stacked"


def _series(file_id: str, where: DeltaGenerator) -> str | None:
    """The series picked of an upload refused as stacking several (its labels, from the
    :class:`~noisevar.errors.StackedSeries` it raised); None for another file, or until one
    is picked (the previous signal stays)."""
    stacked = st.session_state.get(STACKED)
    if not stacked or stacked[0] != file_id:
        return None
    _, column, labels, n_labels = stacked
    more = f" (the first {len(labels)} of {n_labels}: give another with the CLI)"
    label = where.selectbox(
        SERIES_CONTROL,
        list(labels),
        index=None,
        key="upload_series",
        placeholder=f"a value of column {column!r}",
        help=f"{SERIES.help[:1].upper()}{SERIES.help[1:]}: the rows whose {column!r} has the "
        f"value picked{more if n_labels > len(labels) else ''} (CLI: {SERIES.flag}; the "
        "exported configs carry it).",
    )
    return None if label is None else str(label)


def _log_kinds() -> str:
    """The log readers' formats and suffixes, from their registry (one line each)."""
    return "; ".join(f"{r.title} ({', '.join(f'`{x}`' for x in r.suffixes)})" for r in readers())
