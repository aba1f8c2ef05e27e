"""Block arithmetic: sums, counts, maxima and medians per block, widened masks (``auto``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d

try:  # the compiled kernels (numba); the NumPy paths below are the reference
    from noisevar.numeric import _blocks_numba, _select_numba
except ImportError:  # pragma: no cover - numba not installed
    _select_numba = _blocks_numba = None  # type: ignore[assignment]

#: The compiled row medians of :func:`row_medians` while true (and numba is installed);
#: false selects NumPy's partition (the same numbers, tested).
COMPILED_MEDIANS: bool = _select_numba is not None


def block_sums(x: NDArray, block: int, nb: int) -> NDArray:
    """Sums over ``nb`` consecutive blocks of ``block`` samples (the rest joins the last)."""
    sums = x[: nb * block].reshape(nb, block).sum(axis=1, dtype=float)
    sums[-1] += x[nb * block :].sum()
    return sums


def block_maxima(x: NDArray, block: int, nb: int) -> NDArray:
    """Maxima over the blocks of :func:`block_sums` (the rest joins the last)."""
    out = x[: nb * block].reshape(nb, block).max(axis=1)
    if x.size > nb * block:
        out[-1] = max(out[-1], x[nb * block :].max())
    return out


def abs_block_maxima(x: NDArray, block: int, nb: int, off: int = 0, back: bool = False) -> NDArray:
    """:func:`block_maxima` of ``|x|`` over ``x[off:]`` (``back``: over ``x[::-1][off:]``).

    The same numbers (a maximum is one of the values); compiled when numba is installed,
    without the ``|x|`` copy.
    """
    if _blocks_numba is None:
        a = np.abs(x)
        return block_maxima((a[::-1] if back else a)[off:], block, nb)
    bits = np.ascontiguousarray(x, dtype=float).view(np.int64)
    return _blocks_numba.abs_block_maxima(bits, block, nb, off, back)


def block_square_sums(x: NDArray, block: int, nb: int) -> NDArray:
    """Sums of ``x²`` over the blocks of :func:`block_sums`, without a squared copy of ``x``."""
    head = x[: nb * block].reshape(nb, block)
    sums = np.einsum("ij,ij->i", head, head)
    tail = x[nb * block :]
    sums[-1] += tail @ tail
    return sums


def block_medians(x: NDArray, block: int, nb: int, stride: int) -> NDArray:
    """Median of every ``stride``-th sample of each of the first ``nb`` blocks.

    A row-wise sort of the small ``(nb, block / stride)`` array, with the values of
    ``np.median(..., axis=1)``.
    """
    y = np.sort(x[: nb * block].reshape(nb, block)[:, ::stride], axis=1)
    k = y.shape[1]
    return y[:, k // 2] if k % 2 else 0.5 * (y[:, k // 2 - 1] + y[:, k // 2])


def medians_needed(
    x: NDArray, block: int, nb: int, scale: float, off: int = 0, back: bool = False
) -> NDArray | None:
    """Which of the ``nb`` blocks' medians a value may exceed ``scale`` times (None: no numba).

    Parameters
    ----------
    x : ndarray, shape (m,)
        Values ``>= 0`` (others only make blocks needed).
    block, nb : int
        Block ``b`` holds positions ``off + b block`` to ``off + (b + 1) block`` (``m - 1 - p``
        for position ``p`` when ``back``: the grid of the reversed values); ``block <= m``.
    scale : float
        Positive.

    Returns
    -------
    ndarray of bool, shape (nb,), or None
        False where no value of the block, nor of the positions before the first block or
        after the last (they take the first's and the last's level), exceeds ``scale``
        times the block's median or any level above it: that median need not be taken.

    Notes
    -----
    Compiled (:func:`noisevar.numeric._blocks_numba.medians_needed`): the largest value and
    one count per block, two passes the processor vectorises, against a sort of the block.
    """
    if _blocks_numba is None:
        return None
    bits = np.ascontiguousarray(x, dtype=float).view(np.int64)
    return _blocks_numba.medians_needed(bits, block, nb, off, back, float(scale))


def row_medians(x: NDArray) -> NDArray:
    """``np.median(x, axis=1)`` (the same numbers) of a 2-D float array with no NaN.

    Parameters
    ----------
    x : ndarray, shape (r, k), k >= 1
        Not changed.

    Returns
    -------
    ndarray, shape (r,)

    Notes
    -----
    Compiled: each row narrowed by sampled bands (:mod:`noisevar.numeric._select_numba`),
    3-4x faster than NumPy's partition on rows of thousands of values; order statistics
    are the row's values whatever the algorithm. (On rows of a few hundred values NumPy's
    vectorised sort is faster: :func:`block_medians` sorts.)
    """
    if COMPILED_MEDIANS and _select_numba is not None:
        out = np.empty(x.shape[0])
        _select_numba.row_medians(np.ascontiguousarray(x, dtype=float), out)
        return out
    v = np.array(x, dtype=float)  # a copy, partitioned in place
    k = v.shape[1] // 2
    v.partition(k, axis=1)
    if v.shape[1] % 2:
        return v[:, k].copy()
    # the largest of the lower half: the same order statistic as partition((k - 1, k))
    return (v[:, :k].max(axis=1) + v[:, k]) / 2.0


def chosen_above_sums(
    sq: NDArray, choice: NDArray, local: NDArray, halves: NDArray, block: int
) -> tuple[NDArray, NDArray] | None:
    """Per block: sum and count of its chosen row's values above its levels (None: no numba).

    Parameters
    ----------
    sq : ndarray, shape (k, n)
        Rows of values; block ``b`` reads row ``choice[b]`` (the last block the rest too).
    choice : ndarray of int, shape (nb,)
    local : ndarray, shape (nb,)
        Each block's own level: a value is above when it exceeds it and (more than one
        block) the level ``halves[t // (block / 2)]`` of its half block (the last past them).
    halves : ndarray, shape (2 nb,)
    block : int
        Even.

    Returns
    -------
    (ndarray, ndarray) or None
        The sums (added in sample order, as ``np.bincount``'s weights) and the counts.
    """
    if _blocks_numba is None or block % 2:
        return None
    return _blocks_numba.chosen_above_sums(
        np.ascontiguousarray(sq, dtype=float), _int64(choice), local.astype(float), halves, block
    )


def _int64(x: NDArray) -> NDArray:
    return np.ascontiguousarray(x, dtype=np.int64)


def runs_of(mask: NDArray, offset: int = 0) -> list[tuple[int, int]]:
    """The runs of True in the boolean ``mask`` as ``(start, stop)`` ranges (plus ``offset``)."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.view(np.int8), 0])) + offset
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def dilate(mask: NDArray, half: int) -> NDArray:
    """``mask`` widened by ``half`` samples on each side (cheap when few are set)."""
    idx = np.flatnonzero(mask)
    if idx.size > mask.size // 64:
        return maximum_filter1d(mask.view(np.uint8), 2 * half + 1).view(bool)
    out = np.zeros_like(mask)
    span = (idx[:, None] + np.arange(-half, half + 1)).ravel()
    out[span[(span >= 0) & (span < mask.size)]] = True
    return out


def flagged_per_block(idx: NDArray, block: int, nb: int) -> NDArray:
    """How many of the sample indices ``idx`` fall in each block of :func:`block_sums`."""
    return np.bincount(np.minimum(idx // block, nb - 1), minlength=nb).astype(float)


def block_counts(block: int, nb: int, n: int) -> NDArray:
    """Samples per block of :func:`block_sums` (the rest joins the last)."""
    counts = np.full(nb, float(block))
    counts[-1] += n - nb * block
    return counts


def kept_block_sums(x: NDArray, idx: NDArray, block: int, nb: int) -> NDArray:
    """:func:`block_sums` of ``x`` with the samples ``idx`` counted as zero; ``x`` untouched.

    Only the blocks that hold a flagged sample are summed again, from a copy
    of those blocks alone (exactly: subtracting the flagged values instead
    would let a huge outlier swamp its block's sum).
    """
    sums = block_sums(x, block, nb)
    body = x[: nb * block].reshape(nb, block)
    inside = idx[idx < nb * block]
    rows_of = inside // block
    blocks = np.unique(rows_of)
    last = body[-1].sum()
    if blocks.size:
        rows = body[blocks]  # a copy of the flagged blocks only
        rows[np.searchsorted(blocks, rows_of), inside % block] = 0.0
        sums[blocks] = rows.sum(axis=1)
        if blocks[-1] == nb - 1:
            last = sums[-1]
    rest = x[nb * block :]
    tail = idx[idx >= nb * block]
    if tail.size:
        rest = rest.copy()
        rest[tail - nb * block] = 0.0
    if rest.size and (tail.size or (blocks.size and blocks[-1] == nb - 1)):
        sums[-1] = last + rest.sum()  # the rest of the record joins the last block
    return sums
