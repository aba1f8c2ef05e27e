"""noisevar dashboard: ``streamlit run app.py`` from the repository root.

``st.navigation`` gets the page registry (:data:`dashboard.pages.PAGES`, scripts in
``app_pages/``), as in Streamlit's own hello app; every page runs inside the same frame
(config, the signal named in the link, the sidebar card). Settings in
``.streamlit/config.toml``: headless, bound to 127.0.0.1.
"""

from __future__ import annotations

import streamlit as st

from dashboard import trace
from dashboard.pages import PAGES, frame


def main() -> None:
    """Choose the page from the URL, draw the frame, run the page."""
    page = st.navigation([p.st_page() for p in PAGES], expanded=True)
    with trace.script_run(page.title):
        frame(page)
        page.run()


# Streamlit runs this script as __main__; a process that merely imports it (a
# multiprocessing child re-importing its parent's main module) draws nothing.
if __name__ == "__main__":
    main()
