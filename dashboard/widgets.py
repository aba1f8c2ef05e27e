"""Small reusable widgets: number formatting, figures and their downloads, errors, explanations."""

from __future__ import annotations

import base64
import functools
import logging
import math
import numbers
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import plotly.graph_objects as go
import streamlit as st

from dashboard.state import initial
from dashboard.text import plain
from dashboard.url_params import HISTORY_JS
from noisevar import report
from noisevar.errors import NoisevarError
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.budget import capped
from noisevar.figures.export import to_html, to_png
from noisevar.format import eng, wrap_words
from noisevar.params import ParamSpec

if TYPE_CHECKING:
    from pandas.io.formats.style import Styler

LOG = logging.getLogger("noisevar.dashboard")

#: The log grid of ``h`` values offered by the sliders (1, 1.5, 2, 3, 5, 7 per decade).
H_MANTISSAS = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0)


def fmt(v: float | None, digits: int = 4, unit: str = "") -> str:
    """A number for display: :func:`noisevar.format.eng` (``n/a`` for None/NaN)."""
    return eng(v, unit, digits)


@functools.cache
def _plotly_chunk() -> str | None:
    """The file name of Streamlit's plotly.js chunk (``PlotlyChart.<hash>.js``), if one."""
    found = sorted((Path(st.__file__).parent / "static" / "static" / "js").glob("PlotlyChart.*.js"))
    return found[0].name if len(found) == 1 else None


#: Streamlit's animated running icon (its status widget, while a script runs).
RUNNING_ICON = "stStatusWidgetRunningIcon"
#: Wrap long metric values instead of cutting them with "…".
_METRIC_CSS = (
    "<style>"
    "[data-testid='stMetricValue'], [data-testid='stMetricValue'] * {"
    "white-space: normal !important; overflow: visible !important; "
    "text-overflow: clip !important; overflow-wrap: anywhere;}"
    "[data-testid='stMetricValue'] {font-size: 1.6rem;}"
    "[data-testid='stMetricLabel'] p {white-space: normal !important;}"
    # labels of toggles, widgets and buttons wrap instead of ending in "…"
    "[data-testid='stWidgetLabel'] p, [data-testid='stCheckbox'] p, "
    "[data-testid^='stBaseButton'] p {white-space: normal !important; "
    "text-overflow: clip !important; overflow: visible !important;}"
    # this element itself takes no room (with a script, Streamlit would give it a row)
    "[data-testid='stElementContainer']:has(.nv-head) {display: none;}"
    # on a phone the answer comes first, then the controls (ANSWER_KEY, CONTROLS_KEY):
    # beside each other in columns (the Estimator), the answer's column goes up; one
    # below the other (the Noise model), the answer goes above the controls and what follows
    "@media (max-width: 640px) {"
    "[data-testid='stHorizontalBlock']:has(> [data-testid='stColumn'] .st-key-nv-controls)"
    " {flex-direction: column-reverse;}"
    ".st-key-nv-controls-top {order: 1;}"
    ".st-key-nv-controls-top ~ * {order: 2;}"
    ".st-key-nv-controls-top ~ .st-key-nv-answer {order: 0;}}"
    # a still running indicator: Streamlit's swaps six icons every 200 ms while a script
    # runs, a re-render and repaint that cost a waiting page's browser up to a tenth of a
    # CPU-s per second (issue 29: a class waiting on one server)
    f"[data-testid='{RUNNING_ICON}'] {{width: auto !important;}}"
    f"[data-testid='{RUNNING_ICON}'] > * {{display: none !important;}}"
    f"[data-testid='{RUNNING_ICON}']::after {{content: 'Running…'; white-space: nowrap; "
    "font-size: 0.875rem; opacity: 0.6;}"
    "</style><span class='nv-head'></span>"
)
#: Container keys of a page's answer and of its controls (on a phone the answer comes
#: first): controls in a column beside the answer's, or above the answer on the page.
ANSWER_KEY = "nv-answer"
CONTROLS_KEY = "nv-controls"
CONTROLS_ABOVE_KEY = "nv-controls-top"

#: Import Streamlit's plotly.js chunk by the URL its own lazy import resolves to (so the
#: module is fetched and evaluated once per tab, whoever asks first).
_PRELOAD_JS = """<script>(() => {{
  const main = document.querySelector('script[type="module"][src*="/static/js/index."]');
  if (main) import(new URL("{chunk}", main.src).href).catch(() => {{}});
}})();</script>"""


def page_head() -> None:
    """What every page adds once, in one invisible element: metric values wrap in full,
    and plotly.js starts loading, and Back and Forward keep each page's settings
    (:data:`dashboard.url_params.HISTORY_JS`).

    Notes
    -----
    Streamlit loads plotly.js (4.7 MB) when a page's first figure arrives; fetching and
    evaluating it then takes the browser over a second, after the server has finished.
    Asked for from the page's first element, it loads while the server computes.
    Without the chunk (another Streamlit build) only the style is added.
    """
    chunk = _plotly_chunk()
    preload = "" if chunk is None else _PRELOAD_JS.format(chunk=chunk)
    st.html(_METRIC_CSS + preload + HISTORY_JS, unsafe_allow_javascript=True)


#: Plain-words meaning of the abbreviations and symbols the pages use.
GLOSSARY = {
    "NIS": "Normalised innovation squared, d' S⁻¹ d: each measurement's surprise weighed by the "
    "filter's own uncertainty. Its mean is the number of channels m when the filter's noise "
    "model is right; far above, the filter is over-confident (R or Q too small).",
    "NEES": "Normalised estimation error squared, e' P⁻¹ e (needs the true state): the error "
    "weighed by the filter's claimed covariance P; its mean is the number of states when P is "
    "honest. A filter can be accurate (low RMSE) and still over-confident (NEES high): NEES "
    "judges the claimed uncertainty, RMSE the error itself.",
    "RMSE": "Root mean square error against the true state (simulations only).",
    "AHRS": "Attitude and heading reference system: an IMU whose gyros, accelerometers and "
    "magnetometers are fused into an orientation.",
    "Γ_amp": "Amplitude-test threshold: a window is kept when the smooth output is equally far "
    "above and below its fitted line in both halves of the window (ratios within 1 ± Γ_amp): "
    "the signal is straight there. Larger keeps more windows.",
    "Γ_ang": "Angle-test threshold (degrees): a window is kept when the smooth and tracking "
    "filters' slopes differ by less than Γ_ang: the smooth filter is not lagging.",
    "tanh|ln r|": "The symmetric amplitude statistic: 0 when a ratio r of envelope amplitudes is "
    "1, approaching 1 as r goes to 0 or infinity; r and 1/r score the same.",
    "h": "h = q / r, jerk spectral density over noise variance: the one number that sets an "
    "alpha-beta-gamma filter's gains. Smaller h smooths more.",
    "C/N0": "Carrier-to-noise density ratio (dB-Hz): signal power over noise power per hertz.",
}


def tex_number(value: float, digits: int = 3) -> str:
    """A number for LaTeX prose: ``1.5\\cdot10^{-5}``, ``10^{-4}``, ``2.47``.

    Page prose computes its numbers (never copies them); this writes them in an equation.
    """
    exponent = math.floor(math.log10(abs(value))) if value and math.isfinite(value) else 0
    if -3 < exponent < 4:
        return f"{value:.{digits}g}"
    mantissa = f"{value / 10.0**exponent:.{digits}g}"
    power = f"10^{{{exponent}}}"
    return power if mantissa == "1" else f"{mantissa}\\cdot{power}"


def glossary(*terms: str) -> None:
    """A collapsed "Terms" expander defining the abbreviations a section uses."""
    with st.expander("Terms used here", icon=":material/menu_book:"):
        for t in terms:
            st.markdown(f"**{t}**: {GLOSSARY[t]}")


def html_report(
    title: str,
    rows: list[dict[str, object]],
    figures: list[go.Figure],
    notes: Sequence[str] = (),
    summary: Sequence[str] = (),
) -> str:
    """The current analysis as one self-contained HTML page: numbers, notes and figures.

    Parameters
    ----------
    title : str
        Page title.
    rows : list of dict
        ``{"quantity", "value"}`` rows (numbers in engineering notation).
    figures : list of go.Figure
        Drawn interactive (plotly.js embedded once: works offline).
    notes : sequence of str
        Lines shown under the table (the command line, the config...).
    summary : sequence of str
        Sentences shown first, under the title (the verdict, the regime warning).

    Returns
    -------
    str
    """
    cells = [
        (r["quantity"], fmt(r["value"], 6) if isinstance(r["value"], float) else r["value"])
        for r in rows
    ]
    blocks = [
        report.paragraphs(summary, strong=True),
        report.table(cells),
        *(report.pre(n) for n in notes),
    ]
    return report.page(title, blocks, figures)


def table_height(n_rows: int) -> int:
    """Pixel height that shows every row of an ``st.dataframe`` (no inner scroll bar hides any).

    Streamlit draws 35-pixel rows under a 35-pixel header, plus a border.
    """
    return 35 * (int(n_rows) + 1) + 3


def h_grid(lo: float = 1e-9, hi: float = 0.3) -> list[str]:
    """``h`` values from ``lo`` to ``hi`` as strings (stable in URLs: ``1.5e-05``)."""
    out = []
    for e in range(-12, 1):
        for m in H_MANTISSAS:
            v = float(f"{m}e{e}")
            if lo * (1 - 1e-9) <= v <= hi * (1 + 1e-9):
                out.append(f"{v:g}")
    return out


@contextmanager
def guarded(context: str = "") -> Iterator[None]:
    """Show a noisevar error as one ``st.error`` (and anything unexpected without a traceback).

    Streamlit's own control flow (``st.rerun``, ``st.stop``) passes through.
    """
    try:
        yield
    except NoisevarError as exc:
        st.error(f"{context}{plain(exc)}")
    except Exception as exc:  # noqa: BLE001 - no traceback ever reaches the page
        LOG.exception("unexpected error in the dashboard")
        st.error(
            f"{context}Unexpected error ({type(exc).__name__}: {plain(exc)}). This is a bug in "
            "noisevar; the details are in the server log."
        )


@contextmanager
def lazy_expander(label: str, key: str, **kwargs: Any) -> Iterator[bool]:
    """An expander whose content the caller builds only while it is open (yields that).

    Opening or closing it reruns the script, so a closed one sends nothing to draw.
    """
    box = st.expander(label, key=key, on_change="rerun", **kwargs)
    with box:
        yield bool(box.open)


#: Session-state key of the "How it works" expander (open or closed, on every page).
HOW_IT_WORKS_KEY = "how_it_works"


def how_it_works(*blocks: str, expanded: bool = False) -> None:
    """The page's "How it works" expander: Markdown blocks, and ``$$...$$`` blocks as LaTeX.

    Lazy: its text and equations are sent only while it is open (typesetting the
    equations of a closed expander cost the browser a second when a page opened).
    """
    with lazy_expander(
        "How it works", HOW_IT_WORKS_KEY, expanded=expanded, icon=":material/school:"
    ) as is_open:
        if not is_open:
            return
        for b in blocks:
            s = b.strip()
            if s.startswith("$$") and s.endswith("$$"):
                st.latex(s[2:-2].strip())
            else:
                st.markdown(s)


#: Figure colours that read on the light and the dark theme alike (:func:`display_spec`).
INK = "#808495"
GRID = "rgba(128, 128, 128, 0.22)"
FONT = '"Source Sans", "Source Sans Pro", sans-serif'


def _plain(value: Any) -> Any:
    """``value`` with every array as a plain list (None for NaN): no base64 typed arrays."""
    if isinstance(value, dict):
        if "bdata" in value and "dtype" in value:  # plotly's typed-array encoding
            arr = np.frombuffer(base64.b64decode(value["bdata"]), dtype=value["dtype"])
            if "shape" in value:
                arr = arr.reshape([int(k) for k in str(value["shape"]).split(",")])
            return _plain(arr)
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "f":
            return np.where(np.isfinite(value), value, None).tolist()
        return value.tolist()
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


def display_spec(fig: go.Figure) -> dict[str, Any]:
    """The figure as the browser gets it: plain arrays, no template, neutral colours.

    Notes
    -----
    Streamlit remounts a chart whose spec changed and, once mounted, hands plotly the
    figure a second time (its theme effect). plotly then redraws everything if the
    layout has a ``template`` (compared by identity), if an array is base64-encoded, or
    if ``datarevision`` is unset; with none of these the second pass costs a few ms
    instead of a full draw. So: arrays as lists, no template (the page draws it with
    ``theme=None``), a fixed ``datarevision`` (a changed figure is a new chart anyway),
    and colours that read on both themes over a transparent background.
    """
    spec = fig.to_plotly_json()
    lay = {k: _plain(v) for k, v in spec["layout"].items() if k != "template"}
    lay["datarevision"] = 1
    lay["font"] = {"family": FONT, "color": INK, **lay.get("font", {})}
    lay.setdefault("paper_bgcolor", "rgba(0,0,0,0)")
    lay.setdefault("plot_bgcolor", "rgba(0,0,0,0)")
    if isinstance(lay.get("title"), dict) and lay["title"].get("text"):
        lay["title"] = {**lay["title"], "text": f"<b>{lay['title']['text']}</b>"}
    for name in {"xaxis", "yaxis", *(k for k in lay if k[1:5] == "axis")}:
        axis = lay.setdefault(name, {})
        if name.startswith("x"):
            # as Streamlit's own theme: a grid across y only, no line at x = 0
            axis.setdefault("showgrid", False)
            axis.setdefault("zeroline", False)
            # room under every subplot's x axis for its title, over the legend's rows
            # (noisevar.figures' layout reserves them under the axis's own room)
            axis.setdefault("automargin", True)
        for key in ("gridcolor", "zerolinecolor", "linecolor"):
            axis.setdefault(key, GRID)
        if "minor" in axis:  # a minor container, even without showgrid, draws a minor grid
            axis["minor"].setdefault("gridcolor", GRID)
    data = [_plain(t) for t in spec["data"]]
    for trace in data:  # a long legend entry runs off a phone's figure: break it
        if isinstance(trace.get("name"), str):
            trace["name"] = wrap_words(trace["name"])
    return {"data": data, "layout": lay}


class _Drawn(go.Figure):
    """A figure whose dict is given: Streamlit takes a ``Figure``'s ``to_dict()`` as it
    is, where it would build and validate a plain dict's figure again (~20 ms)."""

    def __init__(self, spec: dict[str, Any]) -> None:
        super().__init__()
        self._spec = spec

    def to_dict(self) -> dict[str, Any]:
        return self._spec


def show_figure(
    fig: go.Figure, key: str | None = None, select: bool | str = False, where: Any = None
) -> None:
    """Draw a Plotly figure as :func:`display_spec` sends it.

    ``select`` is True (box) or a Streamlit selection mode ("points"); the selection is
    then in ``st.session_state[key]`` and a selection reruns the page. ``where`` is the
    container (a placeholder, a column); the page by default.
    """
    capped(fig)  # the browser budget: points and shapes (noisevar.figures.budget)
    config = {"displaylogo": False, "scrollZoom": False}
    mode = "box" if select is True else select
    chart = (where or st).plotly_chart
    drawn = _Drawn(display_spec(fig))
    if mode:
        chart(
            drawn,
            width="stretch",
            key=key,
            on_select="rerun",
            selection_mode=mode,
            config=config,
            theme=None,
        )
    else:
        chart(drawn, width="stretch", key=key, config=config, theme=None)


def figure_downloads(fig: go.Figure, basename: str, key: str) -> None:
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


def _png_or_note(fig: go.Figure) -> bytes:
    try:
        return to_png(fig)
    except NoisevarError:
        LOG.exception("PNG export failed")
        raise


def csv_download(
    where: Any,
    label: str,
    data: str | Callable[[], str],
    file_name: str,
    key: str,
    help: str | None = None,
) -> None:
    """A full-width CSV download button in ``where`` (a column or ``st``), built on click."""
    where.download_button(
        label,
        data=data,
        file_name=file_name,
        mime="text/csv",
        key=key,
        on_click="ignore",
        icon=":material/table:",
        width="stretch",
        help=help,
    )


def table_and_figure_downloads(
    label: str,
    rows: list[dict[str, object]],
    file_name: str,
    key: str,
    fig: go.Figure | None,
    fig_base: str,
    fig_key: str,
) -> None:
    """A results-table CSV button beside the figure's downloads (when there is a figure)."""
    c1, c2 = st.columns([1, 2])
    csv_download(
        c1,
        label,
        data=rows_to_csv(rows),
        file_name=file_name,
        key=key,
    )
    if fig is not None:
        with c2:
            figure_downloads(fig, fig_base, fig_key)


def figure_view(views: list[str], key: str, default: str, fallback: str | None = None) -> str:
    """The segmented control choosing a page's figure.

    ``default`` is the initial choice; ``fallback`` (default ``default``) stands for
    no choice (a segmented control can be cleared).
    """
    view = st.segmented_control(
        "Figure", views, key=key, bind="query-params", **initial(key, default, "default")
    )
    return view or (default if fallback is None else fallback)


def param_input(
    spec: ParamSpec,
    key: str,
    where: Any = None,
    label: str | None = None,
    step: float = 0,
    **widget: Any,
) -> Any:
    """A URL-bound widget for one noisevar parameter, built from its spec.

    The spec gives the widget's kind (a choice, a switch, an integer or a number), its
    range (a closed bound; noisevar checks an open one), its default and its help.

    Parameters
    ----------
    spec : ParamSpec
        The parameter.
    key : str
        Widget key (and URL parameter).
    where : container, optional
        A column or container; the page by default.
    label : str, optional
        Default: the parameter's name with spaces.
    step : float
        Step of a number's +/- buttons (default 1 for an integer, Streamlit's for a float).
    **widget
        More arguments of the Streamlit widget (``placeholder``, ``disabled``...).

    Returns
    -------
    object
        The widget's value.
    """
    where = where or st
    label = label or spec.name.replace("_", " ")
    common: dict[str, Any] = {"key": key, "bind": "query-params", "help": spec.help, **widget}
    if spec.choices:
        index = spec.choices.index(spec.default) if spec.default in spec.choices else 0
        return where.selectbox(label, spec.choices, **common, **initial(key, index, "index"))
    if spec.kind == "bool":
        return where.toggle(label, **common, **initial(key, bool(spec.default)))
    integer = spec.kind == "int"
    cast = int if integer else float
    bounds = {
        "min_value": cast(spec.lo) if spec.lo is not None and spec.lo_closed else None,
        "max_value": cast(spec.hi) if spec.hi is not None else None,
    }
    default = None if spec.default is None else cast(spec.default)
    number: dict[str, Any] = {"step": step or 1} if integer else {"format": "%g"}
    if step and not integer:
        number["step"] = float(step)
    return where.number_input(label, **bounds, **number, **common, **initial(key, default))


#: What a missing cell of a table reads (never "None" or "nan").
MISSING = "—"
#: Tables of at most this many rows are drawn whole (Streamlit's default height shows
#: about ten and scrolls the rest: the Compare page's assumptions table hid two methods).
WHOLE_TABLE_ROWS = 30


def show_table(data: Any, digits: int = 4, **kwargs: Any) -> None:
    """``st.dataframe`` with every number at ``digits`` significant digits and a missing
    cell drawn as :data:`MISSING`.

    Seen in Chromium: Streamlit draws a float at six decimals (a pair's noise 1.22e-5 read
    "0.00001", 7.1e-6 "0.000007") and a null cell as a literal "None" whatever a ``Styler``'s
    ``na_rep`` says; its ``placeholder`` is the text it draws instead. Data that is not a
    ``Styler`` is drawn through :func:`blank_frame` (a ``column_config`` format still wins
    for its column); a table of up to :data:`WHOLE_TABLE_ROWS` rows is drawn whole. Every
    table of the pages is drawn here.
    """
    from pandas.io.formats.style import Styler  # (pandas' styler module: loaded when drawn)

    if not isinstance(data, Styler):
        data = blank_frame(pd.DataFrame(data), digits=digits)
    rows = len(data.data)
    if "height" not in kwargs and rows <= WHOLE_TABLE_ROWS:  # no row behind a scroll bar
        kwargs["height"] = table_height(rows)
    st.dataframe(data, placeholder=MISSING, **kwargs)


def blank_missing(rows: Sequence[dict[str, Any]], text: str = MISSING) -> list[dict[str, Any]]:
    """Table rows with every missing cell (None, or a column a row lacks) shown as ``text``.

    Streamlit's data frame draws a missing cell as a literal "None". A column that then
    mixes text with numbers shows its numbers as text (6 significant digits): Arrow cannot
    hold both in one column, and Streamlit logs a traceback when it falls back.
    """
    columns = list(dict.fromkeys(k for r in rows for k in r))
    gappy = {k for k in columns if any(r.get(k) is None for r in rows)}

    def cell(r: dict[str, Any], k: str) -> Any:
        v = r.get(k)
        if v is None:
            return text
        if k in gappy and isinstance(v, bool):
            return str(v)
        if k in gappy and isinstance(v, numbers.Real):
            return f"{v:.6g}"
        return v

    return [{k: cell(r, k) for k in columns} for r in rows]


def blank_frame(
    frame: pd.DataFrame,
    text: str = MISSING,
    digits: int = 6,
    formats: dict[str, str] | None = None,
) -> Styler:
    """A table of result rows to show: every missing cell (None, NaN, pandas' NA) as ``text``.

    A pandas ``Styler``: the numbers stay numbers (a fleet sorts by R's value, not by its
    text) shown to ``digits`` significant digits, and a missing cell reads ``text``; the reason a
    value is absent is the row's own (e.g. ``still_note``), never a "None" or "nan" cell.
    ``formats`` gives a column its own format: a printf pattern (``"%.4g"``) or ``"percent"``.
    """

    def cell(v: Any) -> Any:
        return f"{v:.{digits}g}" if isinstance(v, float) else v

    def column(fmt: str) -> Callable[[Any], str]:
        if fmt == "percent":
            return lambda v: f"{100 * v:.2f} %"
        return lambda v: fmt % v

    own = {k: column(f) for k, f in (formats or {}).items() if k in frame.columns}
    styled = frame.style.format(cell, na_rep=text)
    # (a formatter dict re-formats every column it does not name with pandas' default)
    return styled.format(own, na_rep=text, subset=list(own)) if own else styled
