"""Haar wavelet variance at dyadic scales, its robust variant, and its covariance.

docs/algorithms.md §E10. The MODWT Haar coefficient at scale ``tau`` (samples, even) is
``W_t = (sum of the last tau/2 samples - sum of the tau/2 before) / tau``; its variance
``nu^2(tau) = E W^2`` is half the overlapping Allan variance at ``m = tau/2`` samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy import sparse, stats

from noisevar.errors import NoisevarError

#: Fewest Haar coefficients per scale: the largest scale is at most half the record.
SMALLEST_SCALE = 2
#: Huber clipping point (in robust standard deviations) of the robust wavelet variance.
HUBER_C = 2.0
#: Scales at most this many octaves apart are integrated on one fine grid; farther
#: pairs average the larger scale's oscillation (:func:`_pair`).
BAND = 2
#: Low-frequency grid: up to ``LOW_CYCLES / tau_small`` cycles/sample, ``STEPS`` points
#: per oscillation period of the larger scale's filter.
LOW_CYCLES = 32
STEPS = 16
#: Log-spaced points of the high-frequency tail, where the oscillations are averaged.
TAIL_POINTS = 256


def dyadic_scales(n: int) -> NDArray:
    """Scales ``2, 4, ..., 2^J`` (samples) with ``2^J <= n / 2``."""
    if n < 2 * SMALLEST_SCALE:
        raise NoisevarError(f"The record is too short for a wavelet variance: {n} samples.")
    top = int(math.floor(math.log2(n / 2.0)))
    return 2.0 ** np.arange(1, top + 1)


def haar_wv(
    x: NDArray, tau: NDArray, robust: bool = False, c: float = HUBER_C
) -> tuple[NDArray, NDArray]:
    """Haar wavelet variance of each row of ``x`` (axes, n) at scales ``tau``.

    Returns
    -------
    nu : ndarray, shape (axes, scales)
        The wavelet variances (classical mean of ``W^2``, or Huber's winsorised one).
    m : ndarray, shape (scales,)
        Coefficients behind each scale, ``n - tau + 1``.

    Notes
    -----
    A pyramid of moving sums: ``D_h(k) = x_k + ... + x_(k+h-1)`` of the centred row,
    ``t W_k = D_h(k+h) - D_h(k)`` at ``t = 2h``, and ``D_2h(k) = D_h(k) + D_h(k+h)``;
    each level by blocks of :data:`BLOCK` values that stay in cache, in one buffer
    (``D_2h(k)`` overwrites ``D_h(k)``, read for the last time). ``tau`` must be powers
    of two (:func:`dyadic_scales`).
    """
    x = np.asarray(x, dtype=float)
    t_int = tau.astype(int)
    if np.any(t_int < 2) or np.any(t_int & (t_int - 1)) or np.any(t_int != tau):
        raise NoisevarError("The Haar wavelet scales must be powers of two from 2.")
    n = x.shape[-1]
    m = (n - tau + 1).astype(float)
    mean = x.mean(axis=-1)
    buf = np.empty(n)  # the levels' moving sums, reused row after row
    nu = np.empty((x.shape[0], tau.size))
    for i in range(x.shape[0]):
        nu[i] = _levels(x[i], float(mean[i]), buf, t_int, robust, c)
    return nu, m


#: Values of a row (or of all rows) processed at once: a block stays in cache.
BLOCK = 2**16
#: The first levels are computed together, tile by tile (:func:`_fused`), while their
#: look-ahead (the sum of their half-scales) stays within this share of a block.
FUSED_SHARE = 8


def _levels(
    row: NDArray, mean: float, buf: NDArray, tau: NDArray, robust: bool, c: float
) -> NDArray:
    """The wavelet variance of one row (read where it lies, never written) at ``tau``.

    The first level reads the row itself, centred block by block (the robust variance
    centres it whole); the first levels of the classical variance are fused
    (:func:`_fused`); each next level overwrites the last in ``buf``.
    """
    nu = np.empty(tau.size)
    d, centre = row, mean
    if robust:
        d, centre = np.subtract(row, mean, out=buf), None
    h = 1  # d holds the n - h + 1 moving sums D_h
    if not robust:
        h = _fused(row, mean, buf, tau, nu)
        if h > 1:
            d, centre = buf[: row.size - h + 1], None
    while h <= tau[-1] // 2:
        t, count = 2 * h, d.size - h
        wanted, deeper = t in tau, 2 * t <= tau[-1]
        j = int(np.searchsorted(tau, t))
        if wanted and robust:
            nu[j] = huber_variance((d[h : h + count] - d[:count]) / t, c)
        # one pass: t W = D_h(k+h) - D_h(k) and D_2h(k) = D_h(k) + D_h(k+h), k < count
        total = _pass(d, buf, h, count, (wanted and not robust, deeper), centre)
        if wanted and not robust:
            nu[j] = total / float(t * t) / count
        if not deeper:
            break
        d, centre, h = buf[:count], None, t
    return nu


def _fused(row: NDArray, mean: float, out: NDArray, tau: NDArray, nu: NDArray) -> int:
    """The first levels of :func:`_levels` (classical), tile by tile; returns the
    half-scale ``h`` of the moving sums ``D_h`` left in ``out`` (1: none fused).

    Notes
    -----
    Each tile of :data:`BLOCK` coefficients reads the row with the levels' look-ahead
    and keeps its levels in cache, instead of one pass over the record per level: the
    same sums of the same values, block by block as :func:`_pass` (the same numbers to
    the last bit), with one pass over memory for the fused levels.
    """
    halves = []
    while 2 ** (len(halves) + 1) <= BLOCK // FUSED_SHARE and 2 ** (len(halves) + 2) <= tau[-1]:
        halves.append(2 ** len(halves))
    if not halves:
        return 1
    n, look = row.size, 2 * halves[-1] - 1
    tiles = (np.empty(BLOCK + look), np.empty(BLOCK + look))
    w = np.empty(BLOCK)
    totals = np.zeros(len(halves))
    for a in range(0, n - 1, BLOCK):
        cur = np.subtract(
            row[a : min(a + BLOCK + look, n)], mean, out=tiles[0][: min(BLOCK + look, n - a)]
        )
        for i, h in enumerate(halves):
            k = min(BLOCK, n - 2 * h + 1 - a)  # this tile's coefficients at t = 2h
            if k > 0 and 2 * h in tau:
                np.subtract(cur[h : h + k], cur[:k], out=w[:k])
                totals[i] += float(np.einsum("i,i->", w[:k], w[:k]))
            size = cur.size - h  # D_2h on [a, a + size)
            if size <= 0:
                break
            cur = np.add(cur[:size], cur[h : h + size], out=tiles[(i + 1) % 2][:size])
        else:
            k = min(BLOCK, n - 2 * halves[-1] + 1 - a)
            out[a : a + k] = cur[:k]
    for i, h in enumerate(halves):
        if 2 * h in tau:
            nu[int(np.searchsorted(tau, 2 * h))] = totals[i] / float(4 * h * h) / (n - 2 * h + 1)
    return 2 * halves[-1]


def _pass(
    d: NDArray, out: NDArray, h: int, count: int, what: tuple[bool, bool], centre: float | None
) -> float:
    """By blocks: ``sum (D_h(k+h) - D_h(k))^2`` if ``what[0]``, and the next level's
    ``D_h(k) + D_h(k+h)`` into ``out`` if ``what[1]``; ``d - centre`` if ``centre``."""
    squares, sums = what
    total = 0.0
    buf = np.empty(min(BLOCK, count))
    cbuf = np.empty(min(BLOCK, count) + h) if centre is not None else None
    for k0 in range(0, count, BLOCK):
        k1 = min(k0 + BLOCK, count)
        if cbuf is not None:
            cen = cbuf[: k1 - k0 + h]
            np.subtract(d[k0 : k1 + h], centre, out=cen)
            lo, hi = cen[: k1 - k0], cen[h : h + k1 - k0]
        else:
            lo, hi = d[k0:k1], d[k0 + h : k1 + h]
        if squares:
            w = buf[: k1 - k0]
            np.subtract(hi, lo, out=w)
            total += float(np.einsum("i,i->", w, w))
        if sums:
            np.add(lo, hi, out=out[k0:k1])
    return total


def huber_variance(w: NDArray, c: float = HUBER_C, passes: int = 30) -> float:
    """Huber's proposal-2 variance of zero-mean ``w``: ``mean(min(w^2, c^2 s^2)) = kappa s^2``.

    ``kappa = E min(Z^2, c^2)`` for a standard normal ``Z`` makes it consistent for Gaussian
    coefficients; the start is the MAD's.
    """
    kappa = _kappa(c)
    s2 = (1.482602218505602 * float(np.median(np.abs(w)))) ** 2
    sq = w * w
    for _ in range(passes):
        if s2 <= 0:
            return float(np.mean(sq))
        new = float(np.mean(np.minimum(sq, c * c * s2))) / kappa
        if abs(new - s2) <= 1e-9 * s2:
            return new
        s2 = new
    return s2


@lru_cache(maxsize=8)
def _kappa(c: float) -> float:
    tail = 2.0 * stats.norm.sf(c)
    return float(1.0 - tail - 2.0 * c * stats.norm.pdf(c) + c * c * tail)


@lru_cache(maxsize=8)
def robust_inflation(c: float = HUBER_C) -> float:
    """Asymptotic variance of Huber's wavelet variance over the classical one (Gaussian).

    From the influence function of the scale M-estimator with ``psi(z) = min(z^2, c^2)``:
    ``var = 4 s^4 Var psi(Z) / (E[Z psi'(Z)])^2 / n`` against ``2 s^4 / n``.
    """
    p_in = 1.0 - 2.0 * stats.norm.sf(c)
    m2 = p_in - 2.0 * c * stats.norm.pdf(c)  # E[Z^2; |Z| < c]
    m4 = 3.0 * m2 - 2.0 * c**3 * stats.norm.pdf(c)  # E[Z^4; |Z| < c]
    tail = 1.0 - p_in
    var_psi = m4 + c**4 * tail - _kappa(c) ** 2
    return float(2.0 * var_psi / (2.0 * m2) ** 2)


@lru_cache(maxsize=4)
def _average(m: int) -> float:
    """Mean of ``sin^4(a) sin^4(2^m a)`` over a period."""
    a = (np.arange(4096) + 0.5) * math.pi / 4096
    return float(np.mean(np.sin(a) ** 4 * np.sin(2**m * a) ** 4))


@lru_cache(maxsize=16)
def _grid(tau: tuple[float, ...]) -> tuple[tuple[NDArray, ...], NDArray, NDArray, list]:
    """Frequencies (with ``sin^2(pi f)``, ``cos(2 pi f)``), weights and pair index of
    ``int |H_i|^2 |H_j|^2 S^2 df`` for each pair of scales."""
    freqs, weights, index, pairs = [], [], [], []
    for i, ta in enumerate(tau):
        for j in range(i, len(tau)):
            fs, ws = _pair(ta, tau[j], j - i)
            index.append(np.full(sum(a.size for a in fs), len(pairs)))
            freqs += fs
            weights += ws
            pairs.append((i, j))
    f = np.concatenate(freqs)
    trig = (f, np.sin(np.pi * f) ** 2, np.cos(2.0 * np.pi * f))
    return trig, np.concatenate(weights), np.concatenate(index), pairs


def _pair(ta: float, tb: float, m: int) -> tuple[list[NDArray], list[NDArray]]:
    """Nodes and weights of ``2 int_0^1/2 |H_a|^2 |H_b|^2 g(f) df`` (``tb = 2^m ta``).

    Up to ``LOW_CYCLES / tb`` (all of it within :data:`BAND` octaves: up to
    ``LOW_CYCLES / ta``) the product is sampled ``STEPS`` times per period of the
    larger scale's filter; beyond, that filter's ``sin^4`` is replaced by its mean (3/8),
    and beyond ``LOW_CYCLES / ta`` both by the mean of their product.
    """
    fs, ws = [], []
    top = min(LOW_CYCLES / (ta if m <= BAND else tb), 0.5)
    step = 1.0 / (STEPS * tb)
    f = (np.arange(max(1, int(round(top / step)))) + 0.5) * step
    fs.append(f)
    ws.append(2.0 * step * _h2(f, ta) * _h2(f, tb))
    if m > BAND and top < 0.5:
        mid = min(LOW_CYCLES / ta, 0.5)
        step = 1.0 / (STEPS * ta)
        f = top + (np.arange(max(1, int(round((mid - top) / step)))) + 0.5) * step
        f = f[f < mid]
        fs.append(f)
        ws.append(2.0 * step * _h2(f, ta) * 1.5 / (tb**2 * np.sin(np.pi * f) ** 2))
        top = mid
    if top < 0.5:
        edges = np.geomspace(top, 0.5, TAIL_POINTS + 1)
        g = np.sqrt(edges[1:] * edges[:-1])
        env = 16.0 * _average(min(m, 6)) / (ta**2 * tb**2 * np.sin(np.pi * g) ** 4)
        fs.append(g)
        ws.append(2.0 * np.diff(edges) * env)
    return fs, ws


def _h2(f: NDArray, tau: float) -> NDArray:
    """Squared Haar filter gain at ``tau``: ``4 sin^4(pi f tau / 2) / (tau sin pi f)^2``."""
    return 4.0 * np.sin(np.pi * f * tau / 2.0) ** 4 / (tau * np.sin(np.pi * f)) ** 2


def covariance_nodes(tau: NDArray, diagonal: bool = False) -> tuple[NDArray, NDArray, NDArray]:
    """The frequencies of :func:`wv_covariance`'s integrals, with ``sin^2(pi f)`` and
    ``cos(2 pi f)`` (cached per scales); ``diagonal``: those of the variances only."""
    return _nodes(_key(tau), diagonal)[0]


def pair_integrals(tau: NDArray, g: NDArray, diagonal: bool = False) -> NDArray:
    """``2 int |H_i|^2 |H_j|^2 g df`` for each pair of scales ``i <= j`` (in the order of
    :func:`covariance_matrix`; ``diagonal``: ``i = j`` only), ``g`` on
    :func:`covariance_nodes`."""
    return _nodes(_key(tau), diagonal)[1] @ g


def covariance_matrix(
    tau: NDArray, m: NDArray, a: NDArray, inflation: float = 1.0, diagonal: bool = False
) -> NDArray:
    """``cov(nu_i, nu_j) = 2 a_ij / M_i``, ``a`` the :func:`pair_integrals` of ``S^2``,
    ``M_i`` the smaller scale's (more numerous) coefficients (``diagonal``: a diagonal
    matrix of the variances)."""
    _, _, rows, cols = _nodes(_key(tau), diagonal)
    cov = np.zeros((tau.size, tau.size))
    cov[rows, cols] = 2.0 * a / m[rows] * inflation
    cov[cols, rows] = cov[rows, cols]
    return cov


def _key(tau: NDArray) -> tuple[float, ...]:
    return tuple(np.asarray(tau, dtype=float).tolist())


@lru_cache(maxsize=32)
def _nodes(tau: tuple[float, ...], diagonal: bool) -> tuple:
    """The distinct frequencies of :func:`_grid` (with ``sin^2``, ``cos``), the sparse
    matrix of its weights (pairs x frequencies), and the pairs' rows and columns;
    ``diagonal``: its ``i = j`` pairs only."""
    trig, w, idx, pairs = _grid(tau)
    ij = np.array(pairs, dtype=int)
    freqs, inverse = np.unique(trig[0], return_inverse=True)
    first = np.zeros(freqs.size, dtype=int)
    first[inverse] = np.arange(inverse.size)
    weights = sparse.csr_matrix((w, (idx, inverse)), shape=(len(pairs), freqs.size))
    keep = np.flatnonzero(ij[:, 0] == ij[:, 1]) if diagonal else np.arange(len(pairs))
    weights = weights[keep]
    used = np.unique(weights.indices)
    nodes = tuple(a[first[used]] for a in trig)
    return nodes, sparse.csr_matrix(weights[:, used]), ij[keep, 0], ij[keep, 1]


def wv_covariance(
    tau: NDArray, m: NDArray, spectrum: Callable[..., NDArray], inflation: float = 1.0
) -> NDArray:
    """Asymptotic covariance of the wavelet variances of a Gaussian process of ``spectrum``.

    ``cov(nu_i, nu_j) = 2 / M int |H_i|^2 |H_j|^2 S^2 df`` (Percival 1995; Percival &
    Walden 2000, §8.3, for ``i = j``), ``M`` the coefficients of the smaller scale (the
    more numerous: each of the larger scale's ``M_j`` squares meets all the smaller's,
    so the double sum is ``M_j C`` over ``M_i M_j``; dividing by ``M_j`` made the top
    scales' correlations exceed 1).
    ``spectrum(f, s2, c2)``
    takes the frequencies with ``sin^2(pi f)`` and ``cos(2 pi f)``.
    """
    s = spectrum(*covariance_nodes(tau))
    return covariance_matrix(tau, m, pair_integrals(tau, s * s), inflation)


@lru_cache(maxsize=16)
def _flicker(tau: tuple[float, ...]) -> NDArray:
    out = []
    for t in tau:
        top = min(LOW_CYCLES / t, 0.5)
        step = 1.0 / (STEPS * t)
        f = (np.arange(max(1, int(round(top / step)))) + 0.5) * step
        total = np.sum(_h2(f, t) / (2.0 * math.pi * f)) * step
        if top < 0.5:
            edges = np.geomspace(top, 0.5, TAIL_POINTS + 1)
            g = np.sqrt(edges[1:] * edges[:-1])
            env = 1.5 / (t**2 * np.sin(np.pi * g) ** 2) / (2.0 * math.pi * g)
            total += np.sum(np.diff(edges) * env)
        out.append(2.0 * total)
    return np.array(out)


def flicker_wv(tau: NDArray) -> NDArray:
    """Haar WV of flicker of spectrum ``1 / (2 pi |f|)`` (B = 1), integrated numerically.

    It tends to ``ln 2 / pi`` at large scales, and is 30 % higher at ``tau = 2``.
    """
    return _flicker(tuple(float(t) for t in np.atleast_1d(tau)))
