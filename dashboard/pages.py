"""The page registry (one line per page) and the frame drawn around every page.

``app.py`` hands :data:`PAGES` to ``st.navigation``, Streamlit's own page registry (as in
Streamlit's hello app), draws :func:`frame` and runs the page ``st.navigation`` returns. A
new page is one script in ``app_pages/`` plus one line in :data:`PAGES`; the first line
of the script's docstring is its blurb on the home page.

Notes
-----
The scripts live in ``app_pages/``, not ``pages/``: with a ``pages/`` folder beside
``app.py``, Streamlit's classic discovery runs a page script on its own, without the
frame, until some session calls ``st.navigation``. A page's URL path is its file name
(``Two_sensors.py`` is ``/Two_sensors``); its title is that name with spaces.
"""

from __future__ import annotations

import ast
import functools
from dataclasses import dataclass
from pathlib import Path

import streamlit as st

from dashboard.loading import restore_from_recipe
from dashboard.state import (
    CARD_KEY,
    LoadedSignal,
    current_signal,
    signal_card,
    sync_url,
    url_recipe,
    url_upload,
)
from dashboard.text import plain
from dashboard.url_params import clean_query_params, reset_page_controls
from dashboard.widgets import page_head
from noisevar.errors import NoisevarError

ROOT = Path(__file__).resolve().parents[1]
#: The sidebar at the start: Streamlit's choice by width (collapsed on a phone, where it
#: covered 77 % of the first screen; open on a desktop).
SIDEBAR = "auto"


@dataclass(frozen=True)
class PageInfo:
    """A page of the dashboard.

    Attributes
    ----------
    path : str
        The script, relative to the repository root (``app_pages/Name.py``).
    title : str
        Title (menu, browser tab, links): the file name with spaces.
    icon : str
        Material icon.
    """

    path: str
    title: str
    icon: str

    @property
    def url_path(self) -> str:
        """The page's URL path (Streamlit takes it from the file name)."""
        return Path(self.path).stem

    @property
    def blurb(self) -> str:
        """One line for the home page: the first line of the script's docstring."""
        return _first_doc_line(str(ROOT / self.path))

    def st_page(self) -> st.Page:
        """The page for ``st.navigation`` (a new object each run, as Streamlit needs)."""
        return st.Page(self.path, title=self.title, icon=self.icon)


@functools.cache
def _first_doc_line(path: str) -> str:
    doc = ast.get_docstring(ast.parse(Path(path).read_text(encoding="utf-8"))) or ""
    return doc.strip().split("\n\n")[0].replace("\n", " ")


HOME = PageInfo("app_pages/Home.py", "Home", ":material/home:")
SIGNAL = PageInfo("app_pages/Signal.py", "Signal", ":material/show_chart:")
ESTIMATOR = PageInfo("app_pages/Estimator.py", "Estimator", ":material/tune:")

#: Every page, in menu order (the first, Home, opens at the app's root URL).
PAGES = (
    HOME,
    SIGNAL,
    ESTIMATOR,
    PageInfo("app_pages/Compare.py", "Compare", ":material/leaderboard:"),
    PageInfo("app_pages/Adaptive_filter.py", "Adaptive filter", ":material/route:"),
    PageInfo("app_pages/Two_sensors.py", "Two sensors", ":material/compare_arrows:"),
    PageInfo("app_pages/Fusion.py", "Fusion", ":material/hub:"),
    PageInfo("app_pages/Robust_filter.py", "Robust filter", ":material/shield:"),
    PageInfo("app_pages/Carrier_tracking.py", "Carrier tracking", ":material/satellite_alt:"),
    PageInfo("app_pages/Latency.py", "Latency", ":material/timer:"),
    PageInfo("app_pages/Noise_model.py", "Noise model", ":material/ssid_chart:"),
    PageInfo("app_pages/Fleet.py", "Fleet", ":material/factory:"),
)


def frame(page: st.Page) -> LoadedSignal | None:
    """What every page shares, drawn before it runs: config, the signal, the sidebar card.

    The signal named in the link is restored when none is loaded, and every query
    parameter is checked before any widget reads it.

    Parameters
    ----------
    page : st.Page
        The page ``st.navigation`` chose (its title names the browser tab).

    Returns
    -------
    LoadedSignal or None
        The loaded signal (pages read it with :func:`dashboard.state.current_signal`).
    """
    st.set_page_config(
        page_title=f"{page.title} · noisevar",
        page_icon=page.icon,
        layout="wide",
        initial_sidebar_state=SIDEBAR,
    )
    clean_query_params()  # shared links are untrusted: before any widget reads the URL
    page_head()
    sig = current_signal()
    if sig is None:
        recipe = url_recipe()
        if recipe:
            try:
                with st.spinner("Reopening the signal named in the link..."):
                    sig = restore_from_recipe(recipe)
            except (NoisevarError, ValueError) as exc:
                st.warning(
                    f"Could not reopen the signal named in the link ({plain(recipe, 200)}): "
                    f"{plain(exc)}"
                )
        elif url_upload():
            st.info(
                f"This link was made from an uploaded file, **{plain(url_upload(), 200)}**. "
                "Uploaded data never goes into a link: upload the file again on the Signal page, "
                "and the link's settings apply to it.",
                icon=":material/upload_file:",
            )
    else:
        sync_url(sig)
    _sidebar(sig)
    return sig


def _sidebar(sig: LoadedSignal | None) -> None:
    """Under Streamlit's page menu: the card naming the current signal."""
    with st.sidebar:
        st.divider()
        st.markdown("**noisevar** · measurement-noise variance")
        slot = st.empty()
        st.session_state[CARD_KEY] = slot
        signal_card(slot, sig)
        st.page_link(SIGNAL.path, label="Load or change the signal", icon=":material/upload:")
        st.button(
            "Reset to defaults",
            key="nv_reset_page",
            icon=":material/restart_alt:",
            on_click=reset_page_controls,
            help="Every control of this page back to its default (the signal stays).",
        )


def page_links(columns: int = 3) -> None:
    """A card per page (link and blurb), for the home page."""
    cols = st.columns(columns)
    for i, page in enumerate(p for p in PAGES if p is not HOME):
        with cols[i % columns], st.container(border=True):
            st.page_link(page.path, label=page.title, icon=page.icon)
            st.caption(page.blurb)
