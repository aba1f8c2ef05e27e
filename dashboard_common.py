"""Shared set-up and helpers of the noisevar dashboard pages (the Streamlit side).

Every page script starts with :func:`setup_page`, so that any page works when
it is the first one a browser opens (Streamlit's classic ``pages/`` folder
runs a page file on its own when its URL is opened directly):

* page config, the sidebar card of the loaded signal;
* the loaded signal lives in ``st.session_state`` (:class:`LoadedSignal`) and
  every page reads it with :func:`current_signal` / :func:`require_signal`;
  a page without one says so and offers the sample data;
* a signal that can be rebuilt without data (a generated scenario or a file
  of ``sample_data/``) is named in the URL (``?sig=...``), so a shared link
  reopens it; uploaded data never goes into the URL;
* computations are cached by a **content hash** of the signal (computed once
  at load), never by hashing the array on every rerun (Streamlit samples large
  arrays when it hashes them); cached results are shared read-only objects.

No numbers are computed here: everything comes from :mod:`noisevar`.
"""

from __future__ import annotations

import json
import logging
import math
import re
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import streamlit as st

import noisevar
from noisevar.errors import NoisevarError
from noisevar.estimators.compare import Comparison, compare_methods
from noisevar.estimators.results import VarianceEstimate
from noisevar.figures._common import to_html, to_png
from noisevar.filters.envelope import (
    HScan,
    WindowAmplitude,
    detrend_windows,
    noise_amplitude,
    scan_h,
)
from noisevar.io import LoadedTable, content_digest, load_table, pick_column, table_from_arrays
from noisevar.signals import GPS_CHANNELS

ROOT = Path(__file__).resolve().parent
SAMPLE_DIR = ROOT / "sample_data"
SAMPLE_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".npy", ".nmea")
LOG = logging.getLogger("noisevar.dashboard")

_SIGNAL = "nv_signal"
_ERROR = "nv_load_error"


@dataclass(frozen=True)
class PageInfo:
    """A page of the dashboard (for links and the home page)."""

    path: str
    label: str
    icon: str
    blurb: str


PAGES = (
    PageInfo(
        "pages/1_Signal.py",
        "Signal",
        ":material/show_chart:",
        "Upload CSV/TSV, .npy or NMEA; generate a scenario; or pick a sample file.",
    ),
    PageInfo(
        "pages/2_Estimator.py",
        "Estimator",
        ":material/tune:",
        "Tune SOMD (h_S, h_T, m, Γ) and see every step: filters, windows, envelopes, h scan.",
    ),
    PageInfo(
        "pages/3_Compare.py",
        "Compare",
        ":material/leaderboard:",
        "Every method on the signal; Monte Carlo relative errors against the Cramér-Rao floor.",
    ),
    PageInfo(
        "pages/4_Adaptive_filter.py",
        "Adaptive filter",
        ":material/route:",
        "Kalman filters that estimate R on line: tracks, R over time, NIS, RMSE, Table 1.",
    ),
    PageInfo(
        "pages/5_Two_sensors.py",
        "Two sensors",
        ":material/compare_arrows:",
        "Redundant SOMD with two or three real sensors (three-cornered hat).",
    ),
    PageInfo(
        "pages/6_Fusion.py",
        "Fusion",
        ":material/hub:",
        "Distributed VB fusion with chi-square fault isolation.",
    ),
    PageInfo(
        "pages/7_Robust_filter.py",
        "Robust filter",
        ":material/shield:",
        "Huber M-estimation EKF with a bearing-bias state against outliers.",
    ),
    PageInfo(
        "pages/8_Carrier_tracking.py",
        "Carrier tracking",
        ":material/satellite_alt:",
        "Adaptive EKF carrier tracking of a weak GNSS signal.",
    ),
    PageInfo(
        "pages/9_Latency.py",
        "Latency",
        ":material/timer:",
        "GPS delay estimation by least squares over shifts and a random-constant filter.",
    ),
)


# ------------------------------------------------------------------ the signal
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

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.z.size)


def current_signal() -> LoadedSignal | None:
    """The loaded signal, or None."""
    sig = st.session_state.get(_SIGNAL)
    return sig if isinstance(sig, LoadedSignal) else None


def set_signal(sig: LoadedSignal) -> None:
    """Make ``sig`` the signal of every page (and name it in the URL when it can be rebuilt)."""
    _set_signal(sig)


def _set_signal(sig: LoadedSignal) -> None:
    st.session_state[_SIGNAL] = sig
    st.session_state.pop(_ERROR, None)
    _sync_url(sig)


def _sync_url(sig: LoadedSignal | None) -> None:
    try:
        if sig is not None and sig.recipe:
            if st.query_params.get("sig") != sig.recipe:
                st.query_params["sig"] = sig.recipe
        elif "sig" in st.query_params:
            del st.query_params["sig"]
    except Exception:  # noqa: BLE001 - the URL is a convenience; never break a page for it
        LOG.debug("could not update the sig query parameter", exc_info=True)


def default_column(table: LoadedTable) -> str:
    """The first data column without empty/NaN cells (else the first data column)."""
    cols = table.data_columns
    for c in cols:
        if np.all(np.isfinite(table.columns[c])):
            return c
    if not cols:
        raise NoisevarError(f"{table.name} has no data column (only a time column)")
    return cols[0]


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
    recipe = None
    if recipe_base:
        recipe = recipe_base
        if col != default_column(table):
            recipe += f";col={col}"
        if sample_period != table.sample_period and sample_period:
            recipe += f";T={sample_period:g}"
    label = table.name if len(table.data_columns) == 1 else f"{table.name} · {col}"
    return LoadedSignal(
        table=table,
        column=col,
        z=z,
        sample_period=sample_period,
        digest=content_digest(z),
        source=source,
        label=label,
        recipe=recipe,
        recipe_base=recipe_base,
        table_digest=table.digest(),
        clean=clean,
        true_variance=true_variance,
        notes=list(table.notes),
    )


def set_load_error(message: str, origin: str) -> None:
    """Remember a failed load (shown once on the Signal page; the previous signal stays)."""
    st.session_state[_ERROR] = {"message": message, "origin": origin}


def load_error() -> dict[str, str] | None:
    """The last failed load, if any."""
    return st.session_state.get(_ERROR)


def clear_load_error() -> None:
    """Forget the last failed load."""
    st.session_state.pop(_ERROR, None)


# --------------------------------------------------------------- loaders
def sample_files() -> list[Path]:
    """The files of ``sample_data/`` the dashboard can load (listed at run time)."""
    if not SAMPLE_DIR.is_dir():
        return []
    return sorted(
        p for p in SAMPLE_DIR.iterdir() if p.is_file() and p.suffix.lower() in SAMPLE_EXTENSIONS
    )


@st.cache_data(show_spinner=False)
def sample_descriptions() -> dict[str, str]:
    """One-line descriptions of the sample files, from ``sample_data/make_samples.py``."""
    script = SAMPLE_DIR / "make_samples.py"
    out: dict[str, str] = {}
    if not script.is_file():
        return out
    text = script.read_text(encoding="utf-8", errors="replace")
    doc = text.split('"""')[1] if text.count('"""') >= 2 else ""
    current = None
    for line in doc.splitlines():
        m = re.match(r"^``([^`]+)``\s+(.*)$", line.strip())
        if m:
            current = m.group(1)
            out[current] = m.group(2).strip()
        elif current and line.startswith(" ") and line.strip():
            out[current] += " " + line.strip()
        else:
            current = None
    return out


@st.cache_resource(max_entries=16, show_spinner=False)
def _load_bytes_cached(digest: str, name: str, _raw: bytes) -> LoadedTable:
    return load_table(_raw, name)


def max_upload_bytes() -> int:
    """The upload limit of the server config (``server.maxUploadSize``, MB), in bytes."""
    try:
        mb = float(st.get_option("server.maxUploadSize"))
    except Exception:  # noqa: BLE001
        mb = 200.0
    return int(mb * 1024 * 1024)


def load_bytes(raw: bytes, name: str, source: str = "upload") -> LoadedSignal:
    """Load file bytes as the new signal (raises NoisevarError; the old signal stays then).

    Parameters
    ----------
    raw : bytes
        File content.
    name : str
        File name (its extension picks the format).
    source : str
        ``"upload"`` or ``"sample"``.

    Returns
    -------
    LoadedSignal
    """
    limit = max_upload_bytes()
    if len(raw) > limit:
        raise NoisevarError(
            f"{name} is {len(raw) / 1e6:.1f} MB, over the {limit / 1024 / 1024:.0f} MB upload "
            "limit: give a shorter record (or raise server.maxUploadSize)"
        )
    table = _load_bytes_cached(content_digest(raw), name, raw)
    recipe = f"sample:{name}" if source == "sample" else None
    sig = make_signal(table, None, table.sample_period, source, recipe)
    _set_signal(sig)
    return sig


def load_sample(name: str, column: str | None = None, period: float | None = None) -> LoadedSignal:
    """Load a file of ``sample_data/`` as the new signal.

    Parameters
    ----------
    name : str
        File name inside ``sample_data/``.
    column : str, optional
        Column (default the first usable one).
    period : float, optional
        Override of the sample period.

    Returns
    -------
    LoadedSignal
    """
    path = SAMPLE_DIR / Path(name).name
    if not path.is_file() or path.suffix.lower() not in SAMPLE_EXTENSIONS:
        raise NoisevarError(f"no sample file {name!r} in sample_data/")
    raw = path.read_bytes()
    table = _load_bytes_cached(content_digest(raw), path.name, raw)
    sig = make_signal(
        table,
        column,
        period if period else table.sample_period,
        "sample",
        f"sample:{path.name}",
    )
    _set_signal(sig)
    return sig


#: Extra generator parameters the Signal page offers, per family: (name, kind, default, lo, hi).
GENERATOR_EXTRAS: dict[str, list[tuple[str, str, Any, float, float]]] = {
    "fast-slow": [],
    "gps-circle": [
        ("channel", "choice", "east", 0, 0),
        ("sample_period", "float", 0.5, 0.01, 10.0),
    ],
    "random-jerk": [("jerk_std", "float", 5e-6, 1e-9, 1e-2)],
    "steps-ramps": [("n_steps", "int", 8, 0, 100)],
    "noise-step": [("factor", "float", 3.0, 1.0, 20.0)],
    "noise-ramp": [("factor", "float", 3.0, 1.0, 20.0)],
}


@st.cache_resource(max_entries=16, show_spinner=False)
def _generate_cached(name: str, kwargs_json: str) -> noisevar.GeneratedSignal:
    return noisevar.generate(name, **json.loads(kwargs_json))


def generated_kwargs(name: str, n: int, seed: int, noise_std: float | None, **extra: Any) -> dict:
    """Normalised keyword arguments of :func:`noisevar.generate` (for caching and the URL)."""
    kw: dict[str, Any] = {"n": int(n), "seed": int(seed)}
    if noise_std is not None:
        kw["noise_std"] = float(noise_std)
    for key, kind, _default, _lo, _hi in GENERATOR_EXTRAS.get(name, []):
        if key in extra and extra[key] is not None:
            kw[key] = (
                int(extra[key])
                if kind == "int"
                else (str(extra[key]) if kind == "choice" else float(extra[key]))
            )
    return kw


def load_generated(name: str, **kwargs: Any) -> LoadedSignal:
    """Generate a scenario of :func:`noisevar.generate` as the new signal.

    Parameters
    ----------
    name : str
        Family (:func:`noisevar.signal_names`).
    **kwargs
        ``n``, ``seed``, ``noise_std`` and family extras (see :data:`GENERATOR_EXTRAS`).

    Returns
    -------
    LoadedSignal
    """
    if name not in noisevar.signal_names():
        raise NoisevarError(f"unknown signal {name!r}; choose one of {noisevar.signal_names()}")
    kw = generated_kwargs(name, **kwargs)
    g = _generate_cached(name, json.dumps(kw, sort_keys=True))
    index_axis = np.array_equal(g.t, np.arange(g.t.size))
    period = None if index_axis else g.sample_period
    cols: dict[str, Any] = {} if index_axis else {"time": g.t}
    cols["measured"] = g.measured
    parts = [f"seed {kw['seed']}"] + [f"{k}={v}" for k, v in kw.items() if k not in ("n", "seed")]
    table = table_from_arrays(f"{name} ({', '.join(parts)})", cols, period, "generated")
    if not index_axis:
        table.time_column = "time"
    recipe = f"gen:{name};" + ";".join(f"{k}={v}" for k, v in kw.items())
    sig = make_signal(
        table, "measured", period, "generated", recipe, clean=g.clean, true_variance=g.true_variance
    )
    _set_signal(sig)
    return sig


def _parse_recipe(recipe: str) -> tuple[str, str, dict[str, str]]:
    kind, _, rest = recipe.partition(":")
    parts = rest.split(";")
    name = parts[0]
    opts = {}
    for p in parts[1:]:
        k, _, v = p.partition("=")
        if k:
            opts[k] = v
    return kind, name, opts


def restore_from_recipe(recipe: str) -> LoadedSignal:
    """Rebuild a signal from its URL recipe (``gen:...`` or ``sample:...``)."""
    kind, name, opts = _parse_recipe(recipe)
    col = opts.pop("col", None)
    period = float(opts.pop("T")) if "T" in opts else None
    if kind == "gen":
        kw: dict[str, Any] = {}
        for k, v in opts.items():
            if k in ("n", "seed", "n_steps"):
                kw[k] = int(float(v))
            elif k == "channel":
                if v not in GPS_CHANNELS:
                    raise NoisevarError(f"unknown gps-circle channel {v!r}")
                kw[k] = v
            else:
                kw[k] = float(v)
        kw.setdefault("n", 6000)
        kw.setdefault("seed", 0)
        kw.setdefault("noise_std", None)
        return load_generated(name, **kw)
    if kind == "sample":
        return load_sample(name, col, period)
    raise NoisevarError(f"cannot rebuild the signal {recipe!r} from the link")


# ---------------------------------------------------------------- page frame
def setup_page(title: str, icon: str = ":material/show_chart:") -> LoadedSignal | None:
    """Set up a page: config, the signal (restored from the link if needed), the sidebar card.

    Call it first in every page script.

    Parameters
    ----------
    title : str
        Page title (browser tab).
    icon : str
        Page icon.

    Returns
    -------
    LoadedSignal or None
        The loaded signal.
    """
    st.set_page_config(
        page_title=f"{title} · noisevar",
        page_icon=icon,
        layout="wide",
        initial_sidebar_state="expanded",
    )
    sig = current_signal()
    if sig is None:
        recipe = st.query_params.get("sig")
        if recipe:
            try:
                sig = restore_from_recipe(recipe)
            except (NoisevarError, ValueError) as exc:
                st.warning(f"Could not reopen the signal named in the link ({recipe}): {exc}")
    else:
        _sync_url(sig)
    _sidebar_card(sig)
    return sig


def _sidebar_card(sig: LoadedSignal | None) -> None:
    with st.sidebar:
        st.markdown("**noisevar** · measurement-noise variance")
        if sig is None:
            st.caption("No signal loaded.")
        else:
            period = f", T = {sig.sample_period:g} s" if sig.sample_period else ""
            st.caption(f"Signal: **{sig.label}** — {sig.n:,} samples{period}")
        st.page_link(
            "pages/1_Signal.py", label="Load or change the signal", icon=":material/upload:"
        )


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
    files = sample_files()
    names = [p.name for p in files]
    order = [n for n in preferred if n in names] + [n for n in names if n not in preferred]
    desc = sample_descriptions()
    cols = st.columns(3)
    for i, name in enumerate(order):
        with cols[i % 3]:
            if st.button(f"Load {name}", key=f"offer_{name}", help=desc.get(name)):
                with guarded():
                    load_sample(name)
                    st.rerun()
    if st.button("Generate the paper's fast-slow signal (n = 6000, seed 0)", key="offer_gen"):
        with guarded():
            load_generated("fast-slow", n=6000, seed=0, noise_std=5.0)
            st.rerun()
    st.page_link("pages/1_Signal.py", label="Go to the Signal page", icon=":material/upload:")
    if explain:
        how_it_works(*explain)
    st.stop()
    raise AssertionError("unreachable")  # pragma: no cover


@contextmanager
def guarded(context: str = "") -> Iterator[None]:
    """Show a noisevar error as one ``st.error`` (and anything unexpected without a traceback).

    Streamlit's own control flow (``st.rerun``, ``st.stop``) passes through.
    """
    try:
        yield
    except NoisevarError as exc:
        st.error(f"{context}{exc}")
    except Exception as exc:  # noqa: BLE001 - no traceback ever reaches the page
        LOG.exception("unexpected error in the dashboard")
        st.error(
            f"{context}Unexpected error ({type(exc).__name__}: {exc}). This is a bug in noisevar; "
            "the details are in the server log."
        )


def how_it_works(*blocks: str, expanded: bool = False) -> None:
    """The page's "How it works" expander: Markdown blocks, and ``$$...$$`` blocks as LaTeX."""
    with st.expander("How it works", expanded=expanded, icon=":material/school:"):
        for b in blocks:
            s = b.strip()
            if s.startswith("$$") and s.endswith("$$"):
                st.latex(s[2:-2].strip())
            else:
                st.markdown(s)


def show_figure(fig: Any, key: str | None = None, select: bool = False) -> Any:
    """Draw a Plotly figure (box-select events when ``select``); returns the chart state."""
    config = {"displaylogo": False, "scrollZoom": False}
    if select:
        return st.plotly_chart(
            fig,
            width="stretch",
            key=key,
            on_select="rerun",
            selection_mode="box",
            config=config,
        )
    return st.plotly_chart(fig, width="stretch", key=key, config=config)


def figure_downloads(fig: Any, basename: str, key: str) -> None:
    """Download buttons for a figure as interactive HTML and as PNG (built on click)."""
    c1, c2 = st.columns(2)
    c1.download_button(
        "Figure as HTML",
        data=lambda: to_html(fig),
        file_name=f"{basename}.html",
        mime="text/html",
        key=f"{key}_html",
        on_click="ignore",
        icon=":material/download:",
        width="stretch",
    )
    c2.download_button(
        "Figure as PNG",
        data=lambda: _png_or_note(fig),
        file_name=f"{basename}.png",
        mime="image/png",
        key=f"{key}_png",
        on_click="ignore",
        icon=":material/image:",
        help="Rendered by kaleido with a headless Chromium (a few seconds).",
        width="stretch",
    )


def _png_or_note(fig: Any) -> bytes:
    try:
        return to_png(fig)
    except NoisevarError:
        LOG.exception("PNG export failed")
        raise


def fmt(v: float | None, digits: int = 4) -> str:
    """A number for display (``n/a`` for None/NaN)."""
    if v is None or not isinstance(v, (int, float, np.floating, np.integer)):
        return "n/a"
    if isinstance(v, float | np.floating) and not math.isfinite(float(v)):
        return "n/a"
    return f"{float(v):.{digits}g}"


# --------------------------------------------------------------- cached calls
def _key(params: dict[str, Any]) -> str:
    return json.dumps(params, sort_keys=True, default=str)


@st.cache_resource(max_entries=24, show_spinner=False)
def _estimate_cached(
    digest: str, method: str, params_json: str, start: int, stop: int, _z: np.ndarray
) -> VarianceEstimate:
    z = _z if (start, stop) == (0, _z.size) else _z[start:stop]
    return noisevar.estimate(z, method=method, **json.loads(params_json))


def estimate(
    sig: LoadedSignal, method: str, params: dict[str, Any], stretch: slice | None = None
) -> VarianceEstimate:
    """:func:`noisevar.estimate` on the signal (or a stretch of it), cached by content hash."""
    start, stop = (0, sig.n) if stretch is None else (stretch.start, stretch.stop)
    return _estimate_cached(sig.digest, method, _key(params), int(start), int(stop), sig.z)


@st.cache_resource(max_entries=8, show_spinner=False)
def _scan_cached(digest: str, window: int, _z: np.ndarray) -> HScan:
    return scan_h(_z, window)


def h_scan(sig: LoadedSignal, window: int) -> HScan:
    """:func:`noisevar.filters.envelope.scan_h` on the signal, cached."""
    return _scan_cached(sig.digest, int(window), sig.z)


@st.cache_resource(max_entries=12, show_spinner=False)
def _amplitude_cached(
    digest: str, window: int, which: str, _x: np.ndarray
) -> tuple[WindowAmplitude, np.ndarray]:
    return noise_amplitude(_x, window), detrend_windows(_x, window).ravel()


def amplitude(
    sig: LoadedSignal, window: int, x: np.ndarray | None = None, which: str = "raw"
) -> tuple[WindowAmplitude, np.ndarray]:
    """Envelope amplitude (eq. 13) and the window-detrended record, cached.

    ``x`` defaults to the raw signal; pass a filter output with a ``which``
    label that identifies it (e.g. the estimate's parameters).
    """
    return _amplitude_cached(sig.digest, int(window), which, sig.z if x is None else x)


@st.cache_resource(max_entries=8, show_spinner=False)
def _compare_cached(
    digest: str,
    methods: tuple[str, ...],
    params_json: str,
    true_variance: float | None,
    _z: np.ndarray,
) -> Comparison:
    return compare_methods(_z, list(methods), json.loads(params_json), true_variance)


def compare(sig: LoadedSignal, methods: Sequence[str], params: dict[str, dict]) -> Comparison:
    """:func:`noisevar.estimators.compare.compare_methods` on the signal, cached."""
    return _compare_cached(sig.digest, tuple(methods), _key(params), truth_of(sig), sig.z)


def truth_of(sig: LoadedSignal) -> float | None:
    """The true noise variance when known (a generated signal, unchanged column)."""
    return sig.true_variance if sig.source == "generated" and sig.column == "measured" else None


def clean_of(sig: LoadedSignal) -> np.ndarray | None:
    """The noise-free signal when known (a generated signal, unchanged column)."""
    return sig.clean if sig.source == "generated" and sig.column == "measured" else None


def reselect(sig: LoadedSignal, column: str, sample_period: float | None) -> LoadedSignal:
    """The same source with another column or sample period (raises NoisevarError)."""
    new = make_signal(
        sig.table,
        column,
        sample_period,
        sig.source,
        sig.recipe_base,
        clean=sig.clean,
        true_variance=sig.true_variance,
    )
    _set_signal(new)
    return new


# ------------------------------------------------------------ widget helpers
#: The log grid of ``h`` values offered by the sliders (1, 1.5, 2, 3, 5, 7 per decade).
H_MANTISSAS = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0)


def h_grid(lo: float = 1e-9, hi: float = 0.3) -> list[str]:
    """``h`` values from ``lo`` to ``hi`` as strings (stable in URLs: ``1.5e-05``)."""
    out = []
    for e in range(-12, 1):
        for m in H_MANTISSAS:
            v = float(f"{m}e{e}")
            if lo * (1 - 1e-9) <= v <= hi * (1 + 1e-9):
                out.append(f"{v:g}")
    return out


def initial(key: str, default: Any, arg: str = "value") -> dict[str, Any]:
    """``{arg: default}`` unless the widget already has a state (avoids Streamlit's warning).

    ``arg`` is the widget's default-value argument: ``value`` for most widgets,
    ``index`` for selectbox and radio, ``default`` for multiselect and
    segmented controls.
    """
    return {} if key in st.session_state else {arg: default}


def keep_valid(key: str, valid: Callable[[Any], bool], fallback: Any) -> None:
    """Reset a widget's state to ``fallback`` when it is no longer valid (options changed)."""
    if key in st.session_state and not valid(st.session_state[key]):
        st.session_state[key] = fallback


# ------------------------------------------------------------- several sensors
def sensor_matrix(sig: LoadedSignal, columns: Sequence[str]) -> np.ndarray:
    """The chosen columns of the signal's table as an ``(n, k)`` array (raises on NaN)."""
    return np.column_stack([pick_column(sig.table, c) for c in columns])


def delay_is_significant(delay: Any, sample_period: float) -> bool:
    """A delay worth removing: over half a sample and over twice its standard deviation."""
    return abs(delay.delay_s) > 0.5 * sample_period and abs(delay.delay_s) > 2.0 * delay.std_s


@st.cache_resource(max_entries=8, show_spinner=False)
def _redundant_cached(
    table_digest: str, columns: tuple[str, ...], align: bool, period: float, _sig: LoadedSignal
) -> tuple[noisevar.RedundantEstimate, np.ndarray, Any, float]:
    from noisevar.systems.latency import align_signals, estimate_delay

    data = sensor_matrix(_sig, columns)
    delay = None
    removed = 0.0
    if align:
        delay = estimate_delay(data[:, 0], data[:, 1], period)
        if delay_is_significant(delay, period):
            # whole samples only: interpolating between samples would average (and so
            # shrink) the noise whose variance is being measured
            removed = round(delay.delay_s / period) * period
            a, b = align_signals(data[:, 0], data[:, 1], removed, period)
            data = np.column_stack([a, b])
    return noisevar.estimate_redundant(data), data, delay, removed


def redundant(
    sig: LoadedSignal, columns: Sequence[str], align: bool = False
) -> tuple[noisevar.RedundantEstimate, np.ndarray, Any, float]:
    """Redundant SOMD on several columns (optionally delay-aligned first, two sensors), cached.

    With ``align`` the delay of the second sensor behind the first is
    estimated (:func:`noisevar.systems.latency.estimate_delay`) and, when significant
    (:func:`delay_is_significant`), removed by a whole-sample shift.

    Returns
    -------
    (RedundantEstimate, ndarray, DelayEstimate or None, float)
        The estimate, the (aligned) sensor matrix it used, the delay estimate,
        and the shift removed (s; 0 when none).
    """
    period = float(sig.sample_period or 1.0)
    return _redundant_cached(sig.table_digest, tuple(columns), bool(align), period, sig)


@st.cache_resource(max_entries=16, show_spinner=False)
def _delay_cached(table_digest: str, ref: str, other: str, period: float, _sig: LoadedSignal):
    from noisevar.systems.latency import estimate_delay

    return estimate_delay(pick_column(_sig.table, ref), pick_column(_sig.table, other), period)


def delay_between(sig: LoadedSignal, ref: str, other: str) -> Any:
    """:func:`~noisevar.systems.latency.estimate_delay` of ``other`` behind ``ref``, cached."""
    return _delay_cached(sig.table_digest, ref, other, float(sig.sample_period or 1.0), sig)


@st.cache_resource(max_entries=16, show_spinner=False)
def _column_estimate_cached(
    table_digest: str, column: str, method: str, _sig: LoadedSignal
) -> VarianceEstimate:
    return noisevar.estimate(pick_column(_sig.table, column), method=method)


def column_estimate(sig: LoadedSignal, column: str, method: str = "auto") -> VarianceEstimate:
    """A single-signal estimate of one column of the signal's table, cached."""
    return _column_estimate_cached(sig.table_digest, column, method, sig)


def load_simulated_sensors(noise_stds: Sequence[float] = (1.0, 2.0, 3.0), seed: int = 0) -> None:
    """Make simulated redundant sensors (``simulate_sensors``) the signal."""
    from noisevar.estimators.compare import simulate_sensors

    table = simulate_sensors("fast-slow", noise_stds, n=6000, seed=seed, drift=3.0)
    sig = make_signal(table, None, table.sample_period, "generated", None)
    _set_signal(sig)


# ---------------------------------------------------------------- Kalman filters
#: Position / other state groups of each filter scenario, for the RMSE table.
KALMAN_STATE_GROUPS: dict[str, dict[str, tuple[int, ...]]] = {
    "gps-circle": {"position (m)": (0, 1), "speed (m/s)": (2,), "heading (rad)": (3,)},
    "noise-step": {"position (m)": (0, 2), "velocity (m/s)": (1, 3)},
    "noise-ramp": {"position (m)": (0, 2), "velocity (m/s)": (1, 3)},
    "outliers": {"position (m)": (0, 2), "velocity (m/s)": (1, 3)},
}


@st.cache_resource(max_entries=6, show_spinner=False)
def kalman_scenario(name: str, seed: int, size: float, factor: float) -> Any:
    """A seeded filter scenario of :mod:`noisevar.systems.scenarios` (one run), cached.

    ``size`` is the duration in seconds for ``gps-circle`` and the number of
    steps otherwise; ``factor`` the noise increase of ``noise-step`` / ``noise-ramp``.
    """
    from noisevar.systems.scenarios import SCENARIOS

    if name not in SCENARIOS:
        raise NoisevarError(f"unknown scenario {name!r}; choose one of {list(SCENARIOS)}")
    if name == "gps-circle":
        return SCENARIOS[name](runs=1, seed=int(seed), duration=float(size))
    if name in ("noise-step", "noise-ramp"):
        return SCENARIOS[name](runs=1, seed=int(seed), n_steps=int(size), factor=float(factor))
    return SCENARIOS[name](runs=1, seed=int(seed), n_steps=int(size))


def make_filter_strategy(
    name: str, settings: dict[str, Any], h_smooth: Any, R_true: np.ndarray | None = None
) -> Any:
    """A fresh R-adaptation strategy object from the page's settings."""
    from noisevar.kalman.strategies import make_strategy, strategy_spec

    if name == "oracle" and R_true is None:
        raise NoisevarError("the oracle filter needs the true R: only for scenarios")
    tunable = strategy_spec(name).defaults()
    params = {k: settings[k] for k in tunable if settings.get(k) is not None}
    if "h_smooth" in strategy_spec(name).needs:
        params.pop("window", None)  # the page's window is RAE/IAE's; SOMD uses all samples so far
    return make_strategy(name, h_smooth=h_smooth, R_true=R_true, **params)


@st.cache_resource(max_entries=24, show_spinner=False)
def _scenario_run_cached(
    scenario_key: str, strategy: str, settings_json: str, huber: float | None, _sc: Any
) -> Any:
    from noisevar.kalman import HuberUpdate

    settings = json.loads(settings_json)
    strat = make_filter_strategy(strategy, settings, _sc.h_smooth, _sc.R_true[_sc.first_step :])
    robust = HuberUpdate(kappa=huber) if huber else None
    return _sc.run(strat, robust=robust)


def scenario_run(
    sc: Any, scenario_key: str, strategy: str, settings: dict[str, Any], huber: float | None
) -> Any:
    """One strategy on a scenario (:meth:`Scenario.run`), cached by scenario and settings."""
    return _scenario_run_cached(scenario_key, strategy, _key(settings), huber, sc)


@st.cache_resource(max_entries=16, show_spinner=False)
def _data_run_cached(
    table_digest: str,
    columns: tuple[str, ...],
    period: float,
    h: float,
    r0_factor: float,
    strategy: str,
    settings_json: str,
    huber: float | None,
    _sig: LoadedSignal,
) -> tuple[Any, np.ndarray, np.ndarray]:
    from noisevar.kalman import HuberUpdate, run_filter

    z = sensor_matrix(_sig, columns)
    quick = np.array([column_estimate(_sig, c).variance for c in columns])
    r0 = quick * r0_factor
    from noisevar.systems.scenarios import constant_velocity_model

    model = constant_velocity_model(z[0], period, h, r0, columns)
    settings = json.loads(settings_json)
    h_smooth = float(settings.get("h_smooth", 9e-4))
    strat = make_filter_strategy(strategy, settings, h_smooth)
    robust = HuberUpdate(kappa=huber) if huber else None
    return run_filter(model, z, strategy=strat, robust=robust), z, quick


def data_run(
    sig: LoadedSignal,
    columns: Sequence[str],
    h: float,
    r0_factor: float,
    strategy: str,
    settings: dict[str, Any],
    huber: float | None,
) -> tuple[Any, np.ndarray, np.ndarray]:
    """One strategy on chosen columns of the loaded table, cached.

    The model is :func:`noisevar.systems.scenarios.constant_velocity_model`.

    Returns
    -------
    (FilterResult, ndarray, ndarray)
        The run, the measurements ``(N, m)`` and each channel's quick
        single-signal variance estimate (method auto).
    """
    period = float(sig.sample_period or 1.0)
    return _data_run_cached(
        sig.table_digest,
        tuple(columns),
        period,
        float(h),
        float(r0_factor),
        strategy,
        _key(settings),
        huber,
        sig,
    )


@st.cache_resource(max_entries=4, show_spinner=False)
def table1(runs: int, seed: int) -> dict[str, Any]:
    """The gps-circle experiment (the paper's Table 1) with ``runs`` Monte Carlo runs, cached."""
    import argparse

    from noisevar.experiments import discover

    exp = discover()["gps-circle"]
    parser = argparse.ArgumentParser()
    if exp.add_arguments is not None:
        exp.add_arguments(parser)
    args = parser.parse_args([])
    args.runs = int(runs)
    args.seed = int(seed)
    return exp.run(args)


def filter_summary(result: Any, groups: dict[str, tuple[int, ...]] | None) -> dict[str, Any]:
    """One row of the page's filter table (:func:`noisevar.kalman.evaluation.filter_summary`)."""
    from noisevar.kalman.evaluation import filter_summary as summary

    return summary(result, groups)


# ------------------------------------------------------ the other seed systems
@st.cache_resource(max_entries=4, show_spinner=False)
def fusion_data(fault: str, steps: int, runs: int, seed: int, noise_factor: float, bias: float):
    """:func:`noisevar.systems.fusion.simulate_fusion` for the page's settings, cached."""
    from noisevar.systems.fusion import FusionScenario, simulate_fusion

    scen = FusionScenario(
        n_steps=int(steps), fault=fault, noise_factor=float(noise_factor), bias_sigmas=float(bias)
    )
    return simulate_fusion(scen, seed=int(seed), runs=int(runs))


@st.cache_resource(max_entries=16, show_spinner=False)
def _fusion_run_cached(data_key: str, config: str, false_alarm: float, _data: Any):
    from noisevar.systems.fusion import run_fusion

    local, _, iso = config.partition("+")
    return run_fusion(_data, local=local, isolation=bool(iso), false_alarm=float(false_alarm))


def fusion_run(data: Any, data_key: str, config: str, false_alarm: float) -> Any:
    """``run_fusion`` for a configuration like ``"vb+isolation"``, cached."""
    return _fusion_run_cached(data_key, config, float(false_alarm), data)


@st.cache_resource(max_entries=4, show_spinner=False)
def _fusion_equivalence_cached(data_key: str, _data: Any) -> float:
    from noisevar.systems.fusion import max_abs_diff_vs_centralized

    return max_abs_diff_vs_centralized(_data)


def fusion_equivalence(data: Any, data_key: str) -> float:
    """Largest |fused − centralised| state difference (fixed R, no isolation), cached."""
    return _fusion_equivalence_cached(data_key, data)


def fusion_row(result: Any, data: Any) -> dict[str, Any]:
    """A row of the fusion table: position RMSE and, with isolation, how often sensor 1 was cut."""
    row: dict[str, Any] = {"configuration": result.label, "position RMSE (m)": result.rmse()}
    if "+isolation" in result.label:
        in_fault, healthy = result.isolated_fraction(0)
        row["sensor 1 isolated in fault"] = in_fault
        row["sensor 1 isolated when healthy"] = healthy
    return row


@st.cache_resource(max_entries=6, show_spinner=False)
def robust_run(
    outliers: bool,
    magvar: float,
    burst_rate: float,
    kappa: float,
    iterations: int,
    runs: int,
    seed: int,
) -> Any:
    """:func:`noisevar.systems.robust.run_robust` on a simulated fly-over, cached."""
    from noisevar.systems.robust import RobustScenario, run_robust, simulate_robust

    scen = RobustScenario(
        magvar_deg=float(magvar), outliers=bool(outliers), burst_rate=float(burst_rate)
    )
    data = simulate_robust(scen, seed=int(seed), runs=int(runs))
    return run_robust(data, kappa=float(kappa), iterations=int(iterations))


#: The carrier filters the page shows (``comparison_variants`` names).
CARRIER_FILTERS = ("ekf", "aekf", "ekf_matched", "aekf_paper_q")


@st.cache_resource(max_entries=6, show_spinner=False)
def carrier_runs(
    settings_json: str, runs: int, seed: int, window: int, nominal_cn0: float
) -> dict[str, Any]:
    """The realistic comparison (``carrier.compare``) on the same signals, cached.

    ``ekf`` is designed for ``nominal_cn0``; ``aekf`` adapts from that design
    (eq. 22 R, stabilised Q); ``ekf_matched`` knows the true noise;
    ``aekf_paper_q`` is the paper's eq. 26 (it runs away).
    """
    from noisevar.systems.carrier import CarrierScenario, compare, comparison_variants

    scen = CarrierScenario(**json.loads(settings_json))
    variants = comparison_variants(nominal_cn0_dbhz=float(nominal_cn0))
    chosen = {k: variants[k] for k in CARRIER_FILTERS}
    return compare(scen, chosen, seed=int(seed), runs=int(runs), window=int(window))


@st.cache_resource(max_entries=4, show_spinner=False)
def carrier_sweep(
    settings_json: str, cn0: tuple[float, ...], runs: int, seed: int, nominal_cn0: float
) -> Any:
    """:func:`noisevar.systems.carrier.cn0_sweep` of the page's filters for its scenario, cached."""
    from noisevar.systems.carrier import CarrierScenario, cn0_sweep, comparison_variants

    scen = CarrierScenario(**json.loads(settings_json))
    variants = comparison_variants(nominal_cn0_dbhz=float(nominal_cn0))
    chosen = {k: variants[k] for k in CARRIER_FILTERS}
    return cn0_sweep(tuple(cn0), runs=int(runs), seed=int(seed), scenario=scen, variants=chosen)


@st.cache_resource(max_entries=8, show_spinner=False)
def latency_run(settings_json: str, seed: int, max_delay: float) -> Any:
    """:func:`noisevar.systems.latency.run_latency` on a simulated flight, cached."""
    from noisevar.systems.latency import LatencyScenario, run_latency, simulate_latency

    record = simulate_latency(LatencyScenario(**json.loads(settings_json)), seed=int(seed))
    return run_latency(record, max_delay_s=float(max_delay))
