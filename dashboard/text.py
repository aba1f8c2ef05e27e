"""Untrusted text shown as text: the one escaping helper of the dashboard's message boxes.

``st.info``, ``st.warning``, ``st.error``, ``st.caption`` and ``st.markdown`` render their
body as Markdown. A value that came from outside (a link's query parameter, a file's name or
column, an error message that echoes them) must never become Markdown there: a link value
``[Re-upload here](https://example.invalid/phish)`` would be a clickable link inside the
app's own box, and ``![x](http://host/p.png)`` would make the visitor's browser fetch an
arbitrary address. :func:`plain` escapes such a value so that it renders as exactly its
characters.

Notes
-----
CommonMark lets a backslash escape any ASCII punctuation character, which then renders as
itself. The characters that can start markup are escaped: links and images (``[ ] ( ) !``),
emphasis and code (``* ~ ` \\``; ``_`` unless it sits between two letters or digits, where
it cannot open emphasis), HTML and entities (``< > &``), headings, quotes and lists
(``# > +``; ``-`` and ``N.`` at the start), tables (``|``), LaTeX (``$``), braces. GFM's
bare-address links are broken by escaping ``@`` (e-mail), the dot of ``www.`` and every
``:`` not followed by a space (``https://``, Streamlit's ``:red[...]`` directives and
``:emoji:`` shortcodes). Control characters become ``\\x..`` escapes
(:func:`noisevar.io.echo`), so a value cannot open a new block either. Ordinary words,
numbers and ``name: reason`` text read the same in the message's source as on the page.
"""

from __future__ import annotations

import re

from noisevar.io import echo

#: Characters escaped wherever they are, the ones escaped in some contexts only.
_ALWAYS = re.compile(r"""([\\`*~\[\](){}<>!&#+|$@])""")
_CONTEXT = re.compile(
    r"(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])"  # "_" that could open or close emphasis
    r"|:(?!\s|$)"  # ":" starting an address, a directive or a shortcode
    r"|(?i:(?<=www))\."  # the dot of a bare www. address
    r"|^-"  # a list marker at the start
)
_LIST_NUMBER = re.compile(r"^(\d+)\.")  # "1." at the start: an ordered list


def plain(value: object, limit: int = 2000) -> str:
    """``value`` as Markdown that renders as exactly its text (no link, image or markup).

    Parameters
    ----------
    value : object
        The untrusted value (converted with ``str``).
    limit : int
        Characters kept (a longer value is cut, its length noted).

    Returns
    -------
    str
        The escaped text, to put inside a message's Markdown.
    """
    text = _ALWAYS.sub(r"\\\1", echo(value, limit))
    text = _CONTEXT.sub(lambda m: "\\" + m.group(), text)
    return _LIST_NUMBER.sub(r"\1\\.", text)
