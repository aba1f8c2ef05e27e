"""Compiled (numba) kernel behind :func:`noisevar.numeric.blocks.chosen_above_sums`.

Each block's values of its own chosen row, compared with the block's level and the
bracketing level of their half block, summed where above in sample order (as
``np.bincount`` adds its weights): the same comparisons and the same additions as the
NumPy path, without its gathered copy, mask and index arrays. ``nogil``: the chunks of a
record run in parallel threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Every bit of a float64 but its sign.
_MAGNITUDE = 0x7FFFFFFFFFFFFFFF


@njit(cache=True, nogil=True)
def chosen_above_sums(sq, choice, local, halves, block):  # pragma: no cover - compiled
    """Per block ``b``: the sum and count of ``v = sq[choice[b], t]`` over its samples ``t``
    with ``v > local[b]`` and (more than one block) ``v > halves[t // (block / 2)]``.

    The last block takes the rest of the row; its half blocks past the grid read the last.
    """
    nb = local.shape[0]
    n = sq.shape[1]
    half = block // 2
    last = halves.shape[0] - 1
    sums = np.zeros(nb)
    counts = np.zeros(nb)
    for b in range(nb):
        row = sq[choice[b]]
        lv = local[b]
        stop = n if b == nb - 1 else (b + 1) * block
        s = 0.0
        k = 0
        for t in range(b * block, stop):
            v = row[t]
            if v > lv and (nb == 1 or v > halves[min(t // half, last)]):
                s += v
                k += 1
        sums[b] = s
        counts[b] = k
    return sums, counts


@njit(cache=True, nogil=True)
def _top_bits(v):  # pragma: no cover - compiled
    """The largest of ``v`` (integers from 0 up: a loop the compiler vectorises)."""
    top = v[0]
    for i in range(1, v.shape[0]):
        top = max(top, v[i])
    return top


@njit(cache=True, nogil=True)
def _count_below(v, t):  # pragma: no cover - compiled
    """How many of ``v`` are below ``t``."""
    k = 0
    for i in range(v.shape[0]):
        if v[i] < t:
            k += 1
    return k


@njit(cache=True, nogil=True)
def medians_needed(bits, block, nb, off, back, scale):  # pragma: no cover - compiled
    """Per block: whether a value within its reach may exceed ``scale`` times its median.

    ``bits``: float64 values as their int64 bit patterns (for values ``>= +0`` the same
    order; a negative value or ``-0`` counts as below any level, a NaN as above it: both
    can only make a block needed). Block ``b`` holds grid positions ``off + b block`` to
    ``off + (b + 1) block`` (position ``p`` is value ``p``, or ``m - 1 - p`` when ``back``);
    its reach adds the positions before the first block and after the last. A block is
    not needed when at most ``(block - 1) // 2`` of its values are below the least ``t``
    with ``t scale`` at least the reach's largest value: its median is then at least ``t``.
    """
    m = bits.shape[0]
    need = np.ones(nb, dtype=np.bool_)
    low = (block - 1) // 2
    one = np.empty(1, dtype=np.int64)
    as_float = one.view(np.float64)
    for b in range(nb):
        lo, hi = off + b * block, off + (b + 1) * block
        elo = 0 if b == 0 else lo
        ehi = m if b == nb - 1 else hi
        if back:
            lo, hi, elo, ehi = m - hi, m - lo, m - ehi, m - elo
        one[0] = _top_bits(bits[elo:ehi])
        top = as_float[0]
        if not (top >= 0.0 and top < np.inf):  # NaN or inf: the median decides
            continue
        t = top / scale
        while t * scale < top:
            t = np.nextafter(t, np.inf)
        as_float[0] = t
        need[b] = _count_below(bits[lo:hi], one[0]) > low
    return need


@njit(cache=True, nogil=True)
def abs_block_maxima(bits, block, nb, off, back):  # pragma: no cover - compiled
    """The largest ``|x|`` of each block, from ``x``'s int64 bit patterns ``bits``.

    Block ``b`` holds positions ``off + b block`` to ``off + (b + 1) block``, the last one
    the rest too (position ``p`` is value ``p``, or ``m - 1 - p`` when ``back``). The sign
    bit cleared, the patterns of ``|x|`` are ordered as the values: the largest pattern is
    the largest value's.
    """
    m = bits.shape[0]
    out = np.empty(nb, dtype=np.int64)
    for b in range(nb):
        lo, hi = off + b * block, off + (b + 1) * block
        if b == nb - 1:
            hi = m
        if back:
            lo, hi = m - hi, m - lo
        v = bits[lo:hi]
        top = v[0] & _MAGNITUDE
        for i in range(1, v.shape[0]):
            top = max(top, v[i] & _MAGNITUDE)
        out[b] = top
    return out.view(np.float64)
