"""Session and URL state: the loaded signal, load errors, recipes, query-param-bound widgets.

The loaded signal lives in ``st.session_state`` (:class:`LoadedSignal`). A signal that
can be rebuilt without data (a generated scenario or a file of ``sample_data/``) is
named in the URL (``?sig=...``, its *recipe*); uploaded data never goes into the URL.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np
import streamlit as st

import noisevar
from dashboard.text import plain
from noisevar.errors import NoisevarError
from noisevar.io import LoadedTable, content_digest, pick_column, record_times
from noisevar.io.logs.record import TopicsRecord
from noisevar.units import unit_label

LOG = logging.getLogger("noisevar.dashboard")

#: Session-state keys of the loaded signal and of the last failed load.
SIGNAL_KEY = "nv_signal"
ERROR_KEY = "nv_load_error"
#: The URL parameter that names a rebuildable signal.
RECIPE_PARAM = "sig"
#: The URL parameter that names an uploaded file (its data never goes into the URL).
UPLOAD_PARAM = "upload"
#: Widget key (and URL parameter) of the signal's units.
UNITS_KEY = "units"
#: Session key of the sidebar's signal card (redrawn when the signal changes mid-run).
CARD_KEY = "_nv_sidebar_card"

T = TypeVar("T")


@dataclass
class LoadedSignal:
    """The signal every page works on.

    Attributes
    ----------
    table : LoadedTable
        All columns of the source (other pages may use more than one).
    column : str
        The chosen column.
    z : ndarray
        The chosen column's samples.
    sample_period : float or None
        Seconds per sample (None: axes in samples).
    digest : str
        Content hash of ``z``: the cache key of every computation.
    source : {"generated", "sample", "upload"}
        Where it came from.
    label : str
        Short description for titles.
    recipe : str or None
        How to rebuild it without data (the ``sig`` URL parameter).
    recipe_base : str or None
        The recipe without the column and period choices.
    table_digest : str
        Content hash of the whole table (keys the column/period widgets).
    clean : ndarray or None
        The noise-free signal (generated signals).
    true_variance : float or None
        The known noise variance (generated signals).
    notes : list of str
        Remarks from loading.
    topics : TopicsRecord or None
        For a log read with more topics than the signal's (the Noise model page's IMU
        columns): every chosen topic, each column on its own time base.
    log_params : dict of str to float
        The vehicle's configuration a flight log carries (ULog parameters, DataFlash
        ``PARM``: :func:`noisevar.io.logs.params.log_parameters`), for the filter files'
        EKF step as the command line takes it; empty for other files.
    topics_key : str
        Content key of ``topics`` (the cache key of its columns' fits).
    times : ndarray or None
        The table's own sample times (:func:`noisevar.io.record_times`) unless the user set
        another sample period: every estimate takes them (a record with gaps is split at
        them, as the command line does), and ``digest`` covers them.
    time_unit : str or None
        The unit the user stated for the file's times (the Signal page's control,
        ``--time-unit``); the exported configs carry it.
    series : str or None
        The series read of a file that stacks several (the Signal page's picker,
        ``--series``); the exported configs carry it.
    """

    table: LoadedTable
    column: str
    z: np.ndarray
    sample_period: float | None
    digest: str
    source: str
    label: str
    recipe: str | None = None
    recipe_base: str | None = None
    table_digest: str = ""
    clean: np.ndarray | None = None
    true_variance: float | None = None
    notes: list[str] = field(default_factory=list)
    topics: TopicsRecord | None = None
    topics_key: str = ""
    log_params: dict[str, float] = field(default_factory=dict)
    times: np.ndarray | None = None
    time_unit: str | None = None
    series: str | None = None

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.z.size)


# ------------------------------------------------------------------ the signal
def current_signal() -> LoadedSignal | None:
    """The loaded signal, or None (anything else in its session slot is ignored)."""
    sig = st.session_state.get(SIGNAL_KEY)
    return sig if isinstance(sig, LoadedSignal) else None


def set_signal(sig: LoadedSignal) -> None:
    """Make ``sig`` the signal of every page (and name it in the URL when it can be rebuilt)."""
    st.session_state[SIGNAL_KEY] = sig
    st.session_state.pop(ERROR_KEY, None)
    sync_url(sig)
    slot = st.session_state.get(CARD_KEY)
    if slot is not None:
        try:
            signal_card(slot, sig)
        except Exception:  # noqa: BLE001 - a slot from an earlier run: the next run redraws
            LOG.debug("could not redraw the sidebar card", exc_info=True)


def signal_card(slot: object, sig: LoadedSignal | None) -> None:
    """The sidebar's line naming the current signal, drawn into ``slot`` (an ``st.empty``)."""
    if sig is None:
        slot.caption("No signal loaded.")  # type: ignore[attr-defined]
        return
    period = f", T = {sig.sample_period:g} s" if sig.sample_period else ""
    origin = {"upload": "uploaded file", "sample": "sample file", "generated": "generated"}
    slot.caption(  # type: ignore[attr-defined]
        f"Signal: **{plain(sig.label)}** ({origin.get(sig.source, sig.source)}, column "
        f"{plain(sig.column)}) — {sig.n:,} samples{period}"
    )


def sync_url(sig: LoadedSignal | None) -> None:
    """Put the signal's recipe in the URL (or remove a stale one)."""
    try:
        if sig is not None and sig.recipe:
            if st.query_params.get(RECIPE_PARAM) != sig.recipe:
                st.query_params[RECIPE_PARAM] = sig.recipe
        elif RECIPE_PARAM in st.query_params:
            del st.query_params[RECIPE_PARAM]
        upload = sig.label if sig is not None and sig.source == "upload" else None
        if upload and st.query_params.get(UPLOAD_PARAM) != upload:
            st.query_params[UPLOAD_PARAM] = upload  # the name only: a reopened link says so
        elif not upload and sig is not None and UPLOAD_PARAM in st.query_params:
            del st.query_params[UPLOAD_PARAM]
    except Exception:  # noqa: BLE001 - the URL is a convenience; never break a page for it
        LOG.debug("could not update the sig query parameter", exc_info=True)


def url_recipe() -> str | None:
    """The recipe named in the URL, if any."""
    return st.query_params.get(RECIPE_PARAM) or None


def url_upload() -> str | None:
    """The uploaded file a link was made from (its name; the data is not in the link)."""
    return st.query_params.get(UPLOAD_PARAM) or None


def default_column(table: LoadedTable) -> str:
    """The column a table opens on: :attr:`~noisevar.io.LoadedTable.first_signal` (the
    first data column that is a signal: not a constant field, a counter or a second clock)."""
    col = table.first_signal
    if col is None:
        raise NoisevarError(f"{table.name} has no data column (only a time column)")
    return col


def make_signal(
    table: LoadedTable,
    column: str | None,
    sample_period: float | None,
    source: str,
    recipe_base: str | None,
    clean: np.ndarray | None = None,
    true_variance: float | None = None,
) -> LoadedSignal:
    """Build a :class:`LoadedSignal` from a table column (raises NoisevarError on bad data).

    Parameters
    ----------
    table : LoadedTable
        The loaded file or generated signal.
    column : str, optional
        Column (default :func:`default_column`).
    sample_period : float or None
        Seconds per sample.
    source : str
        ``"generated"``, ``"sample"`` or ``"upload"``.
    recipe_base : str or None
        The URL recipe without column/period.
    clean, true_variance
        Truth of a generated signal.

    Returns
    -------
    LoadedSignal
    """
    col = column or default_column(table)
    z = pick_column(table, col)
    noisevar.estimators.as_signal(z)  # same checks as the estimators: size, constant
    label = table.name if len(table.data_columns) == 1 else f"{table.name} · {col}"
    own = sample_period == table.period_of(col)  # the file's own (its run's clock)
    times = record_times(table, col) if own else None
    return LoadedSignal(
        table=table,
        column=col,
        z=z,
        sample_period=sample_period,
        digest=content_digest(z) + ("" if times is None else content_digest(times)),
        times=times,
        source=source,
        label=label,
        recipe=_recipe(table, col, sample_period, recipe_base),
        recipe_base=recipe_base,
        table_digest=table.digest(),
        clean=clean,
        true_variance=true_variance,
        notes=list(table.notes),
    )


def _recipe(
    table: LoadedTable, col: str, sample_period: float | None, recipe_base: str | None
) -> str | None:
    """The recipe: the base plus the column and period when they differ from the defaults."""
    if not recipe_base:
        return None
    recipe = recipe_base
    if col != default_column(table):
        recipe += f";col={col}"
    if sample_period != table.period_of(col) and sample_period:
        recipe += f";T={sample_period:g}"
    return recipe


def reselect(sig: LoadedSignal, column: str, sample_period: float | None) -> LoadedSignal:
    """The same source with another column or sample period (raises NoisevarError).

    The file's own period of the old column is the new column's own (a run's clock)."""
    if sample_period == sig.table.period_of(sig.column):
        sample_period = sig.table.period_of(column)
    new = make_signal(
        sig.table,
        column,
        sample_period,
        sig.source,
        sig.recipe_base,
        clean=sig.clean,
        true_variance=sig.true_variance,
    )
    new.topics, new.topics_key = sig.topics, sig.topics_key  # the log's other topics stay
    new.log_params, new.time_unit, new.series = sig.log_params, sig.time_unit, sig.series
    set_signal(new)
    return new


def truth_of(sig: LoadedSignal) -> float | None:
    """The true noise variance when known (a generated signal, unchanged column)."""
    return sig.true_variance if sig.source == "generated" and sig.column == "measured" else None


def declared_units(sig: LoadedSignal) -> str:
    """The unit the signal's file declares for its column (a log's field, a CSV header's
    ``[unit]``), as the command line labels it (:func:`noisevar.units.unit_label`); empty
    when it declares none."""
    return unit_label(sig.table.units.get(sig.column)) or ""


def signal_units() -> str:
    """The units the user gave the signal on the Signal page, else the unit its file declares
    for the column (:func:`declared_units`); empty: none. E.g. ``"m"``."""
    given = str(st.session_state.get(UNITS_KEY) or "").strip()[:20]
    sig = st.session_state.get(SIGNAL_KEY)
    if given or not isinstance(sig, LoadedSignal):
        return given
    return declared_units(sig)


def time_of(sig: LoadedSignal) -> np.ndarray | float | None:
    """The abscissa of the signal's figures: its own time column when it has one, else T.

    The time column wins (gaps are drawn as gaps) unless the user set another
    sample period, or the column is not finite and increasing.
    """
    return sig.sample_period if sig.times is None else sig.times


def times_of(sig: LoadedSignal) -> np.ndarray | None:
    """The signal's own sample times when :func:`time_of` uses them, else None."""
    t = time_of(sig)
    return t if isinstance(t, np.ndarray) else None


def clean_of(sig: LoadedSignal) -> np.ndarray | None:
    """The noise-free signal when known (a generated signal, unchanged column)."""
    return sig.clean if sig.source == "generated" and sig.column == "measured" else None


def sensor_matrix(sig: LoadedSignal, columns: list[str] | tuple[str, ...]) -> np.ndarray:
    """The chosen columns of the signal's table as an ``(n, k)`` array (raises on NaN)."""
    return np.column_stack([pick_column(sig.table, c) for c in columns])


def parse_recipe(recipe: str) -> tuple[str, str, dict[str, str]]:
    """Split ``kind:name;key=value;...`` into kind, name and options."""
    kind, _, rest = recipe.partition(":")
    parts = rest.split(";")
    opts = {}
    for p in parts[1:]:
        k, _, v = p.partition("=")
        if k:
            opts[k] = v
    return kind, parts[0], opts


# ----------------------------------------------------------------- load errors
def set_load_error(message: str, origin: str) -> None:
    """Remember a failed load (shown once on the Signal page; the previous signal stays)."""
    st.session_state[ERROR_KEY] = {"message": str(message), "origin": str(origin)}


def load_error() -> dict[str, str] | None:
    """The last failed load, if any (a malformed entry counts as none)."""
    err = st.session_state.get(ERROR_KEY)
    return err if isinstance(err, dict) and "message" in err else None


def clear_load_error() -> None:
    """Forget the last failed load."""
    st.session_state.pop(ERROR_KEY, None)


# ------------------------------------------------- query-param-bound widgets
def initial(key: str, default: object, arg: str = "value") -> dict[str, object]:
    """``{arg: default}``: the widget's default, always given (its state, when it has one,
    still wins).

    ``arg`` is the widget's default-value argument: ``value`` for most widgets,
    ``index`` for selectbox and radio, ``default`` for multiselect and
    segmented controls.

    Notes
    -----
    A widget bound to the URL that is drawn without its default takes Streamlit's own
    (a slider's minimum, a select box's first option) when Back or Forward restores a
    history entry that does not name it: before, Back to the Estimator showed method
    ``auto`` and every slider at its minimum. Streamlit's log warning about a default
    beside a state set in code is off (``.streamlit/config.toml``).
    """
    del key  # kept in the signature: the callers name the widget
    return {arg: default}


def keep_valid(key: str, valid: Callable[[T], bool], fallback: T) -> None:
    """Reset a widget's state to ``fallback`` when it is no longer valid (options changed)."""
    if key in st.session_state and not valid(st.session_state[key]):
        st.session_state[key] = fallback


def follow_table(marker: str, key: str, table_digest: str, default: list[str]) -> None:
    """Reset the column picker ``key`` to ``default`` when a new table is loaded.

    ``marker`` is the session key remembering which table the picker was set for.
    """
    if st.session_state.get(marker) != table_digest:
        st.session_state[marker] = table_digest
        if key in st.session_state:
            st.session_state[key] = default
