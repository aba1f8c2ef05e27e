"""A headerless table whose rows end in text (a photo log's file names): its first line is a
row, not the header, when it is written as the rows under it are."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence

#: digits, masked when two text cells are compared
_DIGITS = re.compile(r"\d")
#: lines under the first compared with it
_ROWS = 5


def _shape(cells: Sequence[str], is_number: Callable[[str], bool]) -> list[str | None]:
    """A row's shape: None for a number, a text cell with its digits masked."""
    return [None if is_number(c) else _DIGITS.sub("0", c.strip()) for c in cells]


def first_line_is_row(lines: Sequence[Sequence[str]], is_number: Callable[[str], bool]) -> bool:
    """Whether the first of ``lines`` (each split into cells) is a data row of a headerless
    table rather than its header.

    Parameters
    ----------
    lines : sequence of sequence of str
        The table's first lines, split into cells.
    is_number : callable
        Whether a cell is a number as the table writes them.

    Returns
    -------
    bool
        True when the first line holds a number and each line under it (up to five) has
        the first's shape: numbers in the same cells, the same text where it has text,
        only digits changed.

    Notes
    -----
    A photo log's lines (a GPS time, east, north, height, three angles, then the photo's
    file name ``..._00805_0.tif``) are not all numbers, so the first was read as the header:
    its numbers named the columns and the first epoch was lost. A header's names differ
    from the text below them in more than their digits (``name`` over ``Alice``).
    """
    if len(lines) < 2:
        return False
    first = _shape(lines[0], is_number)
    if all(s is not None for s in first):
        return False
    return all(_shape(ln, is_number) == first for ln in lines[1 : _ROWS + 1])
