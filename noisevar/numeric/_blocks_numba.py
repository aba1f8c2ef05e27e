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
