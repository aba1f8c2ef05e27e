"""A text table's delimiter, sniffed from its first lines: a tab, a comma, a semicolon, a bar,
or whitespace."""

from __future__ import annotations

import re

#: Lines sniffed
_SAMPLE = 50
#: a comma or semicolon at a field's edge (``1, 2``, ``3,``): a delimiter, not a mark inside
_AT_EDGE = re.compile(r"[,;](\s|$)|(^|\s)[,;]")


def _whitespace_columns(rows: list[str]) -> bool:
    """Whether ``rows`` (the lines under the first) are whitespace-separated columns, one
    width over 1, with no comma or semicolon at a field's edge."""
    widths = {len(ln.split()) for ln in rows}
    return len(widths) == 1 and widths != {1} and not any(_AT_EDGE.search(ln.strip())
                                                          for ln in rows)  # fmt: skip


def sniff_delimiter(lines: list[str]) -> str | None:
    """The delimiter of a text table from its first lines (header included).

    Parameters
    ----------
    lines : list of str
        The table's first meaningful lines.

    Returns
    -------
    str or None
        ``"\\t"``, ``","``, ``";"`` or ``"|"``; None for whitespace.

    Notes
    -----
    A tab anywhere wins; then a comma, semicolon or bar on every line the same number of
    times; then a comma or semicolon on some line, unless the lines under the first are
    whitespace-separated columns of one width with the mark only inside fields: ISMN's
    soil-moisture files write two quality flags as ``D02,D04`` in a whitespace table, and
    were read as CSV and refused ("line 25 has 2 fields but line 1 has 1").
    """
    sample = lines[:_SAMPLE]
    if any("\t" in ln for ln in sample):
        return "\t"
    for cand in (",", ";", "|"):
        counts = {ln.count(cand) for ln in sample}
        if len(counts) == 1 and counts != {0}:
            return cand
    if _whitespace_columns(sample[1:]):
        return None
    for cand in (",", ";"):
        if any(cand in ln for ln in sample):
            return cand
    return None  # whitespace
