"""The record's edges for ``auto``: one-sided residual rows, and a glitch there (§F5.1, §F5.4).

The first and last ``span // 2`` samples have no centred window: their residuals are
the rows of ``I - P`` of a polynomial fit over the first (last) ``span`` samples
(:func:`edge_residual_rows`). Each row's square has expectation ``σ²`` for white
noise, but a lone glitch there is seen with another weight than inside the record
(span 5, order 3: 4 % of it at sample 0, 179 % at sample 2; inside: 100 %), and its
largest square need not be its own sample. :func:`edge_glitches` puts it back at its
sample and gives it the weight it has inside.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from noisevar.numeric.fir import centred_fir, centred_rows, residual_sequence

#: Samples of the one-sided fit that locates and sizes a glitch at an edge (at least;
#: the block's own span when longer): long enough that the fit is not the glitch's (span 5,
#: order 3, leaves one degree of freedom), short enough not to leak a fast signal (21 read
#: false glitches at the edges of a monthly series with a 12-sample season).
EDGE_FIT_SPAN = 11
#: Detecting spans up to this one see a glitch at the edge too weakly in their own
#: squares (span 5: 4 % of it at sample 0); longer ones keep their own (span 11: 41 %).
EDGE_DETECT_MAX = 7
#: Degree of that fit (``auto``'s default order, whatever the order asked of the residual).
EDGE_ORDER = 3


@lru_cache(maxsize=64)
def edge_residual_rows(span: int, order: int) -> tuple[NDArray, NDArray]:
    """Rows of ``I - P`` for the first and last ``span // 2`` samples of a ``span`` window.

    ``P`` is the hat matrix of a polynomial fit of degree ``order`` over the
    window; row ``h = span // 2`` is the interior sequence ``d``. The edge rows
    let the estimator use every sample, not only those a centred span fits.
    """
    h = span // 2
    i = np.arange(span, dtype=float) - h
    v = np.vander(i / max(h, 1), order + 1)
    q, _ = np.linalg.qr(v)
    resid = np.eye(span) - q @ q.T
    head, tail = resid[:h].copy(), resid[span - h :].copy()
    head.setflags(write=False)
    tail.setflags(write=False)
    return head, tail


@lru_cache(maxsize=64)
def edge_weights(span: int, order: int) -> NDArray:
    """Weight of sample ``j`` (``0 .. span - 2``) of the record's start in ``Σ e²/(I-P)_kk``.

    A unit impulse at ``j`` adds ``w_j`` to the sum of the normalised squared
    residuals of :func:`~noisevar.estimators.auto.core._residual_squares`; inside the
    record ``w = 1`` (the centred sequence has unit norm), and from ``j = span - 1`` on too.
    The end is the mirror image (the fit's design is symmetric).
    """
    h = span // 2
    head, _ = edge_residual_rows(span, order)
    d = residual_sequence(span, order)
    unit2 = d**2 / np.sum(d**2)
    j = np.arange(2 * h)
    w = np.sum(head[:, : 2 * h] ** 2 / np.diag(head[:, :h])[:, None], axis=0)
    # interior rows k = h .. j + h reach sample j with the coefficient d[j - k + h]
    for k in range(h, 3 * h):
        reach = np.abs(j - k) <= h
        w[reach] += unit2[j[reach] - k + h]
    w.setflags(write=False)
    return w


@lru_cache(maxsize=64)
def _fit_rows(span: int, order: int) -> tuple[NDArray, NDArray]:
    """``I - P`` of a polynomial fit over ``span`` samples, and its diagonal."""
    i = np.arange(span, dtype=float)
    q, _ = np.linalg.qr(np.vander(i / max(span - 1, 1), order + 1))
    rows = np.eye(span) - q @ q.T
    rows.setflags(write=False)
    return rows, np.diag(rows).copy()


def deleted_residuals(z: NDArray, reach: int, order: int, span: int = 0) -> tuple[NDArray, NDArray]:
    """Each of the first ``reach`` samples less a fit without it: ``e_k / (I-P)_kk``, and its t.

    The fit is a polynomial of degree ``order`` over the first ``max(11, span, reach + 1)``
    samples (:data:`EDGE_FIT_SPAN`; the record, if shorter). The standardised value
    ``t_k = e_k / sqrt((I-P)_kk)`` peaks at a lone glitch, whatever its size
    (``|(I-P)_kj| <= sqrt((I-P)_kk (I-P)_jj)``), and ``e_j / (I-P)_jj`` is its size.
    """
    fit = min(max(EDGE_FIT_SPAN, span, reach + 1), z.size)
    rows, diag = _fit_rows(fit, order)
    reach = min(reach, fit)
    e = centred_rows(rows[:reach], z[:fit], np.arange(reach))
    return e / diag[:reach], np.abs(e) / np.sqrt(diag[:reach])


def _one_edge(
    z: NDArray, peaks: NDArray, span: int, detect: int, order: int
) -> tuple[NDArray, float]:
    """:func:`edge_glitches` at the record's start (``z`` read from it)."""
    w = edge_weights(span, order)
    reach = max(w.size, 2 * detect - 1)
    size, t = deleted_residuals(z, reach, EDGE_ORDER, span)
    # the detecting span's edge rows see a glitch there on several samples (span 5,
    # order 3: the same square on three): the deleted residual tells its own, searched
    # as far as a glitch reaches into them (one just past them is that one: merged)
    at = int(np.argmax(t[: 2 * detect - 1]))
    if not explains(z, at, reach, span):
        return peaks, 0.0  # a jump or fast motion at the edge: its samples count as they are
    moved = np.unique(np.where(peaks < detect - 1, at, peaks))
    near = moved[moved < w.size]
    return moved, float(np.sum((1.0 - w[near]) * size[near] ** 2))


def explains(z: NDArray, at: int, reach: int, span: int) -> bool:
    """Whether one glitch at sample ``at`` explains the start of ``z`` better than one jump.

    Over the deleted residuals' fit (:func:`deleted_residuals`' samples), a cubic plus the
    glitch (``at`` alone) leaves no more residual sum of squares than a cubic plus a
    step at any sample ``2 .. reach - 1`` (a step at 1 is a glitch at 0): both add one
    parameter, so the one that fits better is what the edge holds.
    """
    fit = min(max(EDGE_FIT_SPAN, span, reach + 1), z.size)
    k = np.arange(fit, dtype=float)
    base = np.vander(k / max(fit - 1, 1), EDGE_ORDER + 1)
    y = z[:fit]

    def rss(extra: NDArray) -> float:
        a = np.column_stack([base, extra])
        return float(np.sum((y - a @ np.linalg.lstsq(a, y, rcond=None)[0]) ** 2))

    glitch = rss((k == at).astype(float))
    return all(glitch <= rss((k >= s).astype(float)) for s in range(2, min(reach, fit - 1)))


def edge_glitches(
    z: NDArray,
    peaks: NDArray,
    spans: tuple[int, int],
    detect: int,
    order: int,
    ends: tuple[bool, bool] = (True, True),
) -> tuple[NDArray, float, float]:
    """Outlying samples at the record's edges: their true sample, and what they lack in R.

    Parameters
    ----------
    z : ndarray, shape (m,)
        The samples (a window whose first/last sample is the record's when ``ends`` says so).
    peaks : ndarray of int
        Outlying samples (window indices, sorted; one per spike).
    spans : (int, int)
        The span the total uses in the first and in the last block.
    detect : int
        The span whose squares found ``peaks``.
    order : int
        Polynomial degree.
    ends : (bool, bool)
        Whether the window starts (ends) where the record does.
    Returns
    -------
    peaks : ndarray of int
        ``peaks`` with those within ``detect - 1`` samples of an edge at the sample where
        the deleted residual peaks (:func:`deleted_residuals`; two glitches there are one).
    first, last : float
        What to add to the first (last) block's sum of squares so that each glitch there
        counts ``δ²`` as inside: ``(1 - w_j) δ̂²`` (:func:`edge_weights`).

    Notes
    -----
    docs/algorithms.md §F5.4: the size ``δ̂`` is the deleted residual of the glitch's sample
    in a fit of degree ``order`` over the first ``max(11, span)`` samples; on noise of
    level ``σ`` it adds about ``σ²`` per glitch, as a glitch's cross terms do inside.
    """
    m = z.size
    add = [0.0, 0.0]
    out = peaks
    if not peaks.size or m < 2 * (order + 2):
        return out, 0.0, 0.0
    for side, forward in enumerate((True, False)):
        if not ends[side]:
            continue
        x = z if forward else z[::-1]
        own = out if forward else np.sort(m - 1 - out)
        edge = own[own < max(spans[side], detect) - 1]
        if not edge.size:
            continue
        moved, add[side] = _one_edge(x, edge, spans[side], detect, order)
        rest = own[own >= max(spans[side], detect) - 1]
        own = np.union1d(moved, rest)
        out = own if forward else np.sort(m - 1 - own)
    return out, add[0], add[1]


def bridge_edges(z: NDArray, runs: list[tuple[int, int]]) -> NDArray:
    """``z`` with the glitch of each outlying run ``(a, b)`` at an edge set to the fit without it.

    Inside the record a glitch makes one or two residuals outlying; at an edge the
    one-sided rows spread it over several (up to ``span // 2 + 1``), too many for the
    step detector's bridge (§F5.3), whose window medians then see a jump. The run's
    sample where the deleted residual peaks (:func:`deleted_residuals`) is the glitch:
    only that sample is replaced, so that a jump or a burst at the edge stays what it is.
    """
    out = z.copy()
    for a, b in runs:
        x = z if a == 0 else z[::-1]
        size, t = deleted_residuals(x, b - a, EDGE_ORDER)
        j = int(np.argmax(t))
        out[j if a == 0 else z.size - 1 - j] -= size[j]
    return out


def detection_squares(z: NDArray, sq0: NDArray, span: int, ends: tuple[bool, bool]) -> NDArray:
    """``sq0`` with the first and last ``span - 1`` samples seen as inside, for the outlier test.

    For a detecting span up to :data:`EDGE_DETECT_MAX` (else ``sq0`` itself): where a
    glitch has another weight than inside (:func:`edge_weights`), each sample's
    square is the larger of its own and its standardised deleted residual's ``t²``
    (:func:`deleted_residuals`, degree :data:`EDGE_ORDER`): both have expectation ``σ²``
    on white noise, and a glitch at the edge is seen about as inside (span 5, order 3:
    a 38σ glitch at sample 0 reads 24σ² in its own square, under a 5σ threshold).
    """
    reach = min(span - 1, z.size // 2)
    if span > EDGE_DETECT_MAX or reach < 1 or not (ends[0] or ends[1]):
        return sq0
    out = sq0.copy()
    for side, x in ((0, z), (1, z[::-1])):
        if ends[side]:
            _, t = deleted_residuals(x, reach, EDGE_ORDER)
            own = out[:reach] if side == 0 else out[::-1][:reach]
            np.maximum(own, t**2, out=own)
    return out


def lone_glitches(
    z: NDArray,
    runs: list[tuple[int, int]],
    above: Callable[[NDArray, NDArray], NDArray],
    detect: tuple[int, int],
) -> list[tuple[int, float]]:
    """Runs of outlying samples inside the record that one glitch explains: its sample and value.

    A glitch of many σ makes every residual whose window holds it outlying (span 5: five
    of them), more than the step detector's bridge takes (:data:`GLITCH_MAX`
    samples), whose window medians then see a jump: inside the record it was left out
    with a jump's neighbourhood, while at the edge (:func:`bridge_edges`) it counted. A
    run no longer than the detecting span ``detect = (span, order)`` is one glitch when,
    with the sample where the centred deleted residual (a degree-:data:`EDGE_ORDER` fit
    over ``max(11, span)`` samples) peaks set to the fit without it, none of the
    detecting span's squares around it is above its level (``above(values, idx)``, the
    outlier test's). A jump or a ringing tap is not explained by one sample: left as is.
    """
    span, order = detect
    fit = max(EDGE_FIT_SPAN, span) | 1
    hf, h = fit // 2, span // 2
    dfit = residual_sequence(fit, EDGE_ORDER)
    unit = residual_sequence(span, order)
    unit = unit / np.sqrt(np.sum(unit**2))
    out = []
    for a, b in runs:
        if b - a > span or a - hf < 0 or b + hf > z.size or a - 2 * h < h:
            continue
        if b + 2 * h + h > z.size:
            continue
        e = centred_fir(z[a - hf : b + hf], dfit)  # residuals at a .. b - 1
        j = a + int(np.argmax(np.abs(e)))
        value = z[j] - e[j - a] / dfit[hf]
        lo, hi = min(a, j - h), max(b, j + h + 1)  # the run and the glitch's reach
        x = z[lo - h : hi + h].copy()
        x[j - lo + h] = value
        sq = centred_fir(x, unit, square=True)  # the detecting squares at lo .. hi - 1
        if not above(sq, np.arange(lo, hi)).any():
            out.append((j, float(value)))
    return out
