"""One self-contained HTML page: the style and the escaping every noisevar report shares.

The Estimator page's report (``dashboard.widgets.html_report``) and the IMU noise model's
report (:mod:`noisevar.noise_model.exports.report`) are built from these blocks. Every
string goes through :func:`html.escape`; figures are drawn interactive with plotly.js
embedded once (the page works offline).
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from typing import Any

#: The page's style (one home: every report looks alike).
STYLE = (
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto}"
    "td{padding:2px 12px;border-bottom:1px solid #ddd}pre{background:#f4f4f4;padding:8px}"
)


def _cell(value: object) -> str:
    return html.escape(str(value))


def table(rows: Iterable[Sequence[object]], header: Sequence[str] = ()) -> str:
    """An HTML table of ``rows`` (each cell's text escaped), under an optional header."""
    head = "".join(f"<th>{_cell(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{_cell(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table>{f'<tr>{head}</tr>' if head else ''}{body}</table>"


def paragraphs(lines: Iterable[str], strong: bool = False) -> str:
    """Each line a paragraph (bold with ``strong``)."""
    if strong:
        return "\n".join(f"<p><strong>{_cell(s)}</strong></p>" for s in lines)
    return "\n".join(f"<p>{_cell(s)}</p>" for s in lines)


def heading(text: str, level: int = 2) -> str:
    """A heading ``<h2>`` (or ``level``)."""
    return f"<h{level}>{_cell(text)}</h{level}>"


def pre(text: str) -> str:
    """Preformatted text (a command line, a config)."""
    return f"<pre>{_cell(text)}</pre>"


def page(title: str, blocks: Iterable[str], figures: Sequence[Any] = ()) -> str:
    """The whole page: ``title``, the HTML ``blocks`` (built above) and the figures.

    Parameters
    ----------
    title : str
        Page title and first heading (escaped here).
    blocks : iterable of str
        HTML made by :func:`table`, :func:`paragraphs`, :func:`heading`, :func:`pre`.
    figures : sequence of plotly Figure
        Drawn interactive; plotly.js is embedded once, with the first.

    Returns
    -------
    str
    """
    parts = [
        f"<!doctype html><html><head><meta charset='utf-8'><title>{_cell(title)}</title>"
        f"<style>{STYLE}</style></head><body>",
        f"<h1>{_cell(title)}</h1>",
        *blocks,
    ]
    for i, fig in enumerate(figures):
        parts.append(fig.to_html(full_html=False, include_plotlyjs=i == 0))
    parts.append("<p><small>Made with noisevar.</small></p></body></html>")
    return "\n".join(parts)
