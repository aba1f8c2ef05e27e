"""The page registry (path, title, icon, blurb) and the frame every page script starts with.

A new page is one file in ``pages/`` plus one line in :data:`PAGES`; the page calls
``setup_page(__file__)`` first, so that it also works when its URL is the first one a
browser opens (Streamlit's classic ``pages/`` folder runs a page file on its own).
"""

from __future__ import annotations

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
from dashboard.url_params import clean_query_params
from dashboard.widgets import page_head
from noisevar.errors import NoisevarError

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class PageInfo:
    """A page of the dashboard.

    Attributes
    ----------
    path : str
        The script, relative to the repository root (``pages/N_Name.py``).
    title : str
        Title (browser tab, links).
    icon : str
        Material icon.
    blurb : str
        One line for the home page.
    """

    path: str
    title: str
    icon: str
    blurb: str


#: The home page (``app.py``).
HOME = PageInfo("app.py", "Home", ":material/home:", "")

#: Every page of ``pages/``, in menu order.
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
    PageInfo(
        "pages/10_Noise_model.py",
        "Noise model",
        ":material/ssid_chart:",
        "Allan deviation, IEEE-952 noise terms with intervals, Kalibr imu.yaml, simulation.",
    ),
    PageInfo(
        "pages/11_Fleet.py",
        "Fleet",
        ":material/factory:",
        "Many sensors at once: noise per channel, sensors outside the fleet's range flagged.",
    ),
)

#: The Signal page (linked from the sidebar and from pages without a signal).
SIGNAL_PAGE = PAGES[0].path


def page_info(script: str) -> PageInfo:
    """The registry entry of a page script (a path or ``__file__``; matched by file name)."""
    name = Path(script).name
    for page in (HOME, *PAGES):
        if Path(page.path).name == name:
            return page
    raise KeyError(f"{name} is not in dashboard.pages.PAGES: add a line for it")


def setup_page(script: str) -> LoadedSignal | None:
    """Set up a page: config, the signal (restored from the link if needed), the sidebar card.

    Call it first in every page script, as ``setup_page(__file__)``.

    Parameters
    ----------
    script : str
        The page script (its title and icon come from :data:`PAGES`).

    Returns
    -------
    LoadedSignal or None
        The loaded signal.
    """
    page = page_info(script)
    st.set_page_config(
        page_title=f"{page.title} · noisevar",
        page_icon=page.icon,
        layout="wide",
        initial_sidebar_state="expanded",
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
                st.warning(f"Could not reopen the signal named in the link ({recipe}): {exc}")
        elif url_upload():
            st.info(
                f"This link was made from an uploaded file, **{url_upload()}**. Uploaded data "
                "never goes into a link: upload the file again on the Signal page, and the "
                "link's settings apply to it.",
                icon=":material/upload_file:",
            )
    else:
        sync_url(sig)
    _sidebar(sig)
    return sig


def _sidebar(sig: LoadedSignal | None) -> None:
    """Navigation (Home first) and the card naming the current signal."""
    with st.sidebar:
        for page in (HOME, *PAGES):
            if (ROOT / page.path).is_file():
                st.page_link(page.path, label=page.title, icon=page.icon)
        st.divider()
        st.markdown("**noisevar** · measurement-noise variance")
        slot = st.empty()
        st.session_state[CARD_KEY] = slot
        signal_card(slot, sig)
        st.page_link(SIGNAL_PAGE, label="Load or change the signal", icon=":material/upload:")


def page_links(columns: int = 3) -> None:
    """A card per page (link and blurb), for the home page."""
    cols = st.columns(columns)
    shown = [p for p in PAGES if (ROOT / p.path).is_file()]
    for i, page in enumerate(shown):
        with cols[i % columns], st.container(border=True):
            st.page_link(page.path, label=page.title, icon=page.icon)
            st.caption(page.blurb)
