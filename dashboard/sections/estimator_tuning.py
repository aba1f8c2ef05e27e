"""The Estimator page's tuning panel: method, h_S (and more), h_T, window m, Γ, selection."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import streamlit as st

import noisevar
from dashboard.state import LoadedSignal, initial, keep_valid, reselect
from dashboard.text import plain
from dashboard.widgets import GLOSSARY, h_grid
from noisevar.config import parse_config, require_estimator_config
from noisevar.estimators import METHODS, PARAMS
from noisevar.estimators.params import SOMD_PARAMS
from noisevar.filters.abg import settling_samples

RATIOS = [2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100]
H_ALL = h_grid(1e-9, 3e-3)
HT_ALL = h_grid(1e-8, 0.3)
MIN_WINDOW = 8
#: Session key of the column named by a loaded config (applied by the page, then dropped).
CONFIG_COLUMN_KEY = "est_config_column"


def methods() -> list[str]:
    """The single-signal methods the page offers (none that needs a second sensor)."""
    return [name for name, spec in METHODS.items() if not spec.needs_reference]


def tuned_methods() -> list[str]:
    """The methods whose parameters the panel tunes: those taking SOMD's parameters.

    The first is the page's default method.
    """
    return [m for m in methods() if set(SOMD_PARAMS) <= set(METHODS[m].param_specs)]


def default(param: str) -> object:
    """A SOMD parameter's default (its spec's)."""
    return PARAMS[param].default


def max_window(n: int) -> int:
    """The longest window m the slider offers for ``n`` samples."""
    return int(max(min(400, n // 4), MIN_WINDOW + 1))


@dataclass
class Tuning:
    """What the panel chose.

    Attributes
    ----------
    method : str
        The estimator.
    params : dict
        Keyword arguments of :func:`noisevar.estimate` (empty unless a SOMD method).
    h_smooth : list of float
        The smoothing filters' h (the first one is h_S).
    window : int
        Window m (also the envelope window of the detail views).
    gamma_amp, gamma_ang : float
        The window tests' thresholds.
    """

    method: str
    params: dict[str, object] = field(default_factory=dict)
    h_smooth: list[float] = field(default_factory=list)
    window: int = PARAMS["window"].default
    gamma_amp: float = PARAMS["gamma_amp"].default
    gamma_ang: float = PARAMS["gamma_ang"].default

    @property
    def somd(self) -> bool:
        """Whether the method is one of the tuned SOMD methods."""
        return self.method in tuned_methods()


def _valid_h(options: list[str], window: int, n: int) -> list[str]:
    """h values whose filters settle with room for two windows (widgets never offer others)."""
    ok = [h for h in options if settling_samples(float(h)) + 2 * window < n]
    return ok or options[-1:]


def closest(options: list[str], target: float) -> str:
    return min(options, key=lambda h: abs(math.log(float(h) / target)))


def _parse_with_column(raw: bytes, name: str) -> tuple[dict[str, object], str | None]:
    """A config's parameters and its ``column`` (the channel is not an estimator parameter)."""
    try:
        data = json.loads(raw)
    except (ValueError, UnicodeDecodeError, RecursionError):  # RecursionError: nested deeply
        return parse_config(raw, name), None  # parse_config words the JSON error
    column = data.pop("column", None) if isinstance(data, dict) else None
    if column is not None and not isinstance(column, str):
        raise noisevar.NoisevarError(f"{name}: 'column' must be a column name, got {column!r}")
    cfg = parse_config(json.dumps(data), name)
    require_estimator_config(cfg, name)  # a tuned filter's config belongs to the Noise model page
    return cfg, column


def follow_config_column(sig: LoadedSignal) -> LoadedSignal:
    """Switch to the column a just-loaded config names (once; a warning if the table lacks it)."""
    column = st.session_state.pop(CONFIG_COLUMN_KEY, None)
    if column is None or column == sig.column:
        return sig
    columns = sig.table.data_columns
    if column not in columns:
        st.warning(
            f"The loaded config was tuned on column {plain(repr(column))}, which this table does "
            f"not have (columns: {plain(', '.join(columns))}); the parameters apply to column "
            f"{plain(repr(sig.column))}."
        )
        return sig
    try:
        new = reselect(sig, column, sig.sample_period)
    except noisevar.NoisevarError as exc:
        st.error(f"Column {plain(repr(column))} of the loaded config: {plain(exc)}")
        return sig
    st.info(f"Switched to column {plain(repr(column))}, named by the loaded config.")
    return new


def _apply_config(largest_window: int) -> None:
    """Load an exported config JSON into the widgets (runs before the page script)."""
    up = st.session_state.get("est_config_upload")
    if up is None:
        return
    try:
        cfg, column = _parse_with_column(up.getvalue(), up.name)
    except noisevar.NoisevarError as exc:
        st.session_state["est_config_error"] = str(exc)
        return
    st.session_state.pop("est_config_error", None)
    state = st.session_state
    state[CONFIG_COLUMN_KEY] = column
    if cfg.get("method") in methods():
        state["est_method"] = cfg["method"]
    hs = cfg.get("h_smooth")
    if hs is not None:
        hs = hs if isinstance(hs, list) else [hs]
        # h_S is the smallest (noisevar sets h_T from it); the others are the extra filters
        state["h_s"] = closest(H_ALL, min(hs))
        state["h_more"] = sorted({closest(H_ALL, h) for h in hs} - {state["h_s"]}, key=float)
    if "h_track" in cfg:
        state["ht_mode"] = "value"
        state["h_t"] = closest(HT_ALL, cfg["h_track"])
    elif "track_ratio" in cfg:
        state["ht_mode"] = "multiple of h_S"
        state["ht_ratio"] = min(RATIOS, key=lambda r: abs(r - cfg["track_ratio"]))
    if "window" in cfg:
        state["win"] = int(min(max(cfg["window"], MIN_WINDOW), largest_window))
    if "gamma_amp" in cfg:
        state["g_amp"] = float(min(max(round(cfg["gamma_amp"] * 20) / 20, 0.05), 1.0))
    if "gamma_ang" in cfg:
        state["g_ang"] = float(min(max(round(cfg["gamma_ang"] * 2) / 2, 0.5), 90.0))
    if "angle" in cfg:
        state["angle"] = cfg["angle"]
    if "select" in cfg:
        state["select"] = bool(cfg["select"])


def tuning_panel(n: int) -> Tuning:
    """The panel's widgets for a record of ``n`` samples; the chosen method and parameters.

    The chosen SOMD parameters are also kept in ``st.session_state["nv_tuned"]``: the
    Compare page runs the SOMD methods with them.
    """
    st.markdown("#### Parameters")
    method = _method_select()
    somd = method in tuned_methods()
    h_s, h_more = _smoothing_filters(n, somd)
    track = _tracking_filter(h_s, n, somd)
    largest = max_window(n)
    paper_window = min(int(default("window")), largest)
    keep_valid("win", lambda v: MIN_WINDOW <= v <= largest, paper_window)
    window = st.slider(
        "Window m (samples)",
        MIN_WINDOW,
        largest,
        key="win",
        bind="query-params",
        help="Windows for the selection tests and the envelope amplitude (paper: "
        f"{default('window')}).",
        **initial("win", paper_window),
    )
    g_amp, g_ang, angle, select = _window_tests(somd)
    _config_upload(largest)
    hs_list = [float(h_s)] + [float(h) for h in h_more if h != h_s]
    tuning = Tuning(method, {}, hs_list, int(window), float(g_amp), float(g_ang))
    if somd:
        tuning.params = {
            "h_smooth": hs_list if len(hs_list) > 1 else hs_list[0],
            "window": int(window),
            "gamma_amp": float(g_amp),
            "gamma_ang": float(g_ang),
            "angle": angle,
            "select": bool(select),
            **track,
        }
        st.session_state["nv_tuned"] = dict(tuning.params)
    return tuning


def _method_select() -> str:
    names = methods()
    desc = noisevar.describe_methods()
    first = tuned_methods()[0]
    keep_valid("est_method", lambda v: v in names, first)
    # the options are the names (as in the CLI and the share link); the description follows
    method = st.selectbox(
        "Method",
        names,
        key="est_method",
        bind="query-params",
        help="The estimator; `noisevar methods` lists the same names.",
        **initial("est_method", names.index(first), "index"),
    )
    st.caption(desc[method])
    return method


def _smoothing_filters(n: int, somd: bool) -> tuple[str, list[str]]:
    hs_opts = _valid_h(H_ALL, MIN_WINDOW, n)
    paper_h = float(default("h_smooth"))
    keep_valid("h_s", lambda v: v in hs_opts, closest(hs_opts, paper_h))
    h_s = st.select_slider(
        "Smoothing filter h_S (log scale)",
        hs_opts,
        key="h_s",
        bind="query-params",
        disabled=not somd,
        help=GLOSSARY["h"] + f" Paper: {paper_h:g}.",
        **initial("h_s", closest(hs_opts, paper_h)),
    )
    # only filters above h_S: the smallest h sets h_T (noisevar.estimators.somd), so a
    # smaller one would silently replace the h_S the slider shows ("Select all" did)
    more_opts = [h for h in hs_opts if float(h) > float(h_s)]
    kept = [h for h in st.session_state.get("h_more", []) if h in more_opts]
    keep_valid("h_more", lambda v: all(h in more_opts for h in v), kept)
    h_more = st.multiselect(
        "More smoothing filters (larger h than h_S)",
        more_opts,
        key="h_more",
        bind="query-params",
        disabled=not somd,
        help="Section 2.4: a window counts when any smoothing filter passes; more windows. "
        "h_S stays the smallest: h_T is a multiple of it.",
    )
    return h_s, h_more


def _tracking_filter(h_s: str, n: int, somd: bool) -> dict[str, float]:
    """The tracking filter as ``{"h_track": ...}`` or ``{"track_ratio": ...}``.

    Both sliders are always drawn (the unused one disabled): a widget that exists
    follows a loaded config into the URL, so a share link carries ``h_t``.
    """
    ht_mode = st.radio(
        "Tracking filter h_T",
        ["multiple of h_S", "value"],
        key="ht_mode",
        bind="query-params",
        horizontal=True,
        disabled=not somd,
    )
    by_ratio = ht_mode == "multiple of h_S"
    ratio_opts = [r for r in RATIOS if float(h_s) * r < 0.3]
    paper_ratio = int(default("track_ratio"))
    keep_valid("ht_ratio", lambda v: v in ratio_opts, ratio_opts[-1])
    ratio = st.select_slider(
        "h_T / h_S",
        ratio_opts,
        key="ht_ratio",
        bind="query-params",
        disabled=not somd or not by_ratio,
        help="The paper takes h_T 10 to 100 times h_S (docs/algorithms.md §A5).",
        **initial("ht_ratio", paper_ratio if paper_ratio in ratio_opts else ratio_opts[-1]),
    )
    ht_opts = _valid_h(HT_ALL, MIN_WINDOW, n)
    keep_valid("h_t", lambda v: v in ht_opts, closest(ht_opts, 5e-4))
    h_t = st.select_slider(
        "h_T (log scale)",
        ht_opts,
        key="h_t",
        bind="query-params",
        disabled=not somd or by_ratio,
        **initial("h_t", closest(ht_opts, 5e-4)),
    )
    return {"track_ratio": float(ratio)} if by_ratio else {"h_track": float(h_t)}


def _window_tests(somd: bool) -> tuple[float, float, str, bool]:
    """Γ_amp, Γ_ang, the slopes of the angle test and the selection toggle."""
    g_amp = st.slider(
        "Γ_amp (amplitude test)",
        0.05,
        1.0,
        step=0.05,
        key="g_amp",
        bind="query-params",
        disabled=not somd,
        help=(
            GLOSSARY["Γ_amp"] + " somd-paper (as printed): |A1/A2|, |A2/A3|, |A3/A4| within "
            "(1 − Γ, 1 + Γ). somd: the same chain closed by |A4/A1|, scored by tanh|ln r| ("
            + GLOSSARY["tanh|ln r|"]
            + "), so that −z keeps the same windows as z."
        ),
        **initial("g_amp", default("gamma_amp")),
    )
    g_ang = st.slider(
        "Γ_ang (angle test, degrees)",
        0.5,
        90.0,
        step=0.5,
        key="g_ang",
        bind="query-params",
        disabled=not somd,
        help=GLOSSARY["Γ_ang"],
        **initial("g_ang", default("gamma_ang")),
    )
    angle = st.radio(
        "Slopes of the angle test",
        ["scaled", "paper"],
        key="angle",
        bind="query-params",
        horizontal=True,
        disabled=not somd,
        help="scaled: slopes in noise units (unit-free); paper: raw units per sample.",
    )
    select = st.toggle(
        "Window selection",
        key="select",
        bind="query-params",
        disabled=not somd,
        help="Off for a signal known to be slowly varying (the paper's GPS experiment).",
        **initial("select", default("select")),
    )
    return g_amp, g_ang, angle, select


def _config_upload(largest_window: int) -> None:
    st.file_uploader(
        "Load tuned parameters (JSON)",
        type=["json"],
        key="est_config_upload",
        on_change=_apply_config,
        args=(largest_window,),
        help="A config exported here or written for `noisevar estimate --config`.",
    )
    if st.session_state.get("est_config_error"):
        st.error(plain(st.session_state["est_config_error"]))
