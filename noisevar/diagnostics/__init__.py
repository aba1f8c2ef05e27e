"""Diagnostics of a record's noise: whiteness, tails, quantisation, gaps, level along the record.

:func:`diagnose` looks at the record once, whatever the estimator; every
:class:`~noisevar.estimators.results.VarianceEstimate` carries the result at
``.diagnostics`` with a one-sentence verdict (docs/algorithms.md §E1-§E3).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.power_law import power_law_types
from noisevar.diagnostics.profile import LevelProfile, block_bounds, level_profile, robust_levels
from noisevar.diagnostics.quantisation import find_lsb
from noisevar.diagnostics.results import NoiseDiagnostics
from noisevar.diagnostics.segments import Gap, Segmentation, split_dropped, split_times
from noisevar.diagnostics.tails import noise_kurtosis, tail_index
from noisevar.diagnostics.verdict import make_notes, make_verdict
from noisevar.diagnostics.whiteness import WHITE_LAGS, WhitenessTest, whiteness_test
from noisevar.errors import NoisevarError

__all__ = [
    "Gap",
    "LevelProfile",
    "NoiseDiagnostics",
    "Segmentation",
    "WhitenessTest",
    "diagnose",
    "split_dropped",
    "split_times",
    "with_verdict",
]

#: At most this many samples enter the whiteness tests (spread over the record).
WHITE_MAX = 2**18
#: Samples per block of the level that the kurtosis is taken relative to.
SHAPE_BLOCK = 256
#: Span and order of the local-polynomial residual the diagnostics look through.
DIAG_SPAN = 21
DIAG_ORDER = 3


def _filtered(x: NDArray, d: NDArray) -> NDArray:
    """``d * x`` at the centred samples (``d`` symmetric): compiled when numba is there."""
    from noisevar.estimators import auto

    if auto.USE_COMPILED and auto._fir is not None:
        out = np.empty(x.size - d.size + 1)
        auto._fir.symmetric_fir(np.ascontiguousarray(x), d[d.size // 2 :].copy(), out, False)
        return out
    return np.convolve(x, d[::-1], mode="valid")


def _residuals(
    z: NDArray, segments: tuple[tuple[int, int], ...], exclude: NDArray | None
) -> tuple[NDArray, NDArray, NDArray]:
    """Interior residuals of every segment joined with unused separators, keep mask, positions.

    A residual whose window touches an ``exclude``-d sample (a level jump) is not kept.
    """
    from noisevar.estimators.auto import residual_sequence

    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    h = DIAG_SPAN // 2
    parts, keep, pos = [], [], []
    for a, b in segments:
        if b - a < 2 * DIAG_SPAN:
            continue
        e = _filtered(z[a:b], d)
        pos += [np.arange(a + h, b - h), np.zeros(WHITE_LAGS, dtype=int)]
        ok = np.ones(e.size, dtype=bool)
        if exclude is not None:
            near = np.convolve(exclude[a:b].astype(float), np.ones(DIAG_SPAN), mode="valid")
            ok = near == 0
        parts += [e, np.zeros(WHITE_LAGS)]
        keep += [ok, np.zeros(WHITE_LAGS, dtype=bool)]
    if not parts or not np.any(np.concatenate(keep)):
        raise NoisevarError(
            f"no stretch of the record has {2 * DIAG_SPAN} uniformly sampled samples "
            f"(span {2 * h + 1}) free of jumps: nothing to diagnose"
        )
    return np.concatenate(parts), np.concatenate(keep), np.concatenate(pos)


def _spread(e: NDArray, keep: NDArray, most: int = WHITE_MAX) -> tuple[NDArray, NDArray]:
    """At most ``most`` samples of ``e`` in 16 windows spread over the record, with separators.

    The whiteness tests need a few hundred thousand samples, not all of a long record.
    """
    if e.size <= most:
        return e, keep
    width = most // 16
    starts = np.linspace(0, e.size - width, 16).astype(int)
    sep = np.zeros(WHITE_LAGS)
    parts = [x for a in starts for x in (e[a : a + width], sep)]
    kept = [x for a in starts for x in (keep[a : a + width], sep.astype(bool))]
    return np.concatenate(parts), np.concatenate(kept)


def _increments(z: NDArray, segments: tuple[tuple[int, int], ...]) -> WhitenessTest:
    """Box-Pierce on the first difference within segments (the null: a random walk)."""
    parts, keep = [], []
    for a, b in segments:
        dz = np.diff(z[a:b])
        parts += [dz, np.zeros(WHITE_LAGS)]
        keep += [np.ones(dz.size, dtype=bool), np.zeros(WHITE_LAGS, dtype=bool)]
    dz, ok = _spread(np.concatenate(parts), np.concatenate(keep))
    return whiteness_test(dz, np.ones(1), keep=ok)


def diagnose(
    z: NDArray, segmentation: Segmentation | None = None, exclude: NDArray | None = None
) -> NoiseDiagnostics:
    """Look at a record's noise once: whiteness, tails, grid, gaps, level profile.

    Parameters
    ----------
    z : ndarray, shape (n,)
        Finite samples.
    segmentation : Segmentation, optional
        Uniform segments (from sample times or dropped samples); default one segment.
    exclude : ndarray of bool, shape (n,), optional
        Samples to leave out (around level jumps: signal, not noise).

    Returns
    -------
    NoiseDiagnostics
        Its verdict speaks of the record's own level until :func:`with_verdict` gives
        it an estimate.
    """
    from noisevar.estimators.auto import residual_sequence

    seg = segmentation or Segmentation(((0, z.size),), ())
    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    e, keep, pos = _residuals(z, seg.segments, exclude)
    used, pos = e[keep], pos[keep]
    sq = used**2 / np.dot(d, d)
    # the shape of the noise, not its level: residuals over their block's level
    first = block_bounds(sq.size)
    robust = robust_levels(sq, first)
    # the shape over the level of wide blocks' medians: spikes stay in it, level changes not
    wide = block_bounds(sq.size, SHAPE_BLOCK)
    local = np.repeat(robust_levels(sq, wide), np.diff(np.r_[wide, sq.size]))
    scaled = used / np.sqrt(np.maximum(local, np.finfo(float).tiny))
    kurt = noise_kurtosis(scaled, d) if np.all(np.isfinite(scaled)) else 3.0
    eta = float(np.sum(white_null_acf_sq(d)))
    # ν per sample = 1 / (η + (κ - 3) / 2)   (docs/algorithms.md §E1)
    profile = level_profile(sq, pos, 1.0 / (eta + max(kurt - 3.0, 0.0) / 2.0), eta, robust)
    # a level changing along the record widens the sample autocorrelations by Σσ⁴ n / (Σσ²)²
    top = float(np.max(local)) if local.size else 0.0
    # n Σσ⁴ / (Σσ²)², on levels over their largest (no overflow near the float limit)
    hetero = float(np.mean((local / top) ** 2) / np.mean(local / top) ** 2) if top > 0 else 1.0
    e_w, keep_w = _spread(e, keep)
    white = whiteness_test(e_w, d, keep=keep_w, inflation=hetero)
    types: tuple[tuple[int, int], ...] = ()
    if not white.white:  # say which coloured noise (costly: only when it is coloured)
        a, b = max(seg.segments, key=lambda s: s[1] - s[0])
        try:
            types = power_law_types(z[a:b])
        except NoisevarError:
            types = ()
    diag = NoiseDiagnostics(
        n=int(z.size),
        whiteness=white,
        increments=_increments(z, seg.segments),
        kurtosis=kurt,
        tail_index=tail_index(e_w[keep_w]),
        lsb=find_lsb(z),
        gaps=seg.gaps,
        jitter=seg.jitter,
        level_profile=profile,
        power_law=types,
    )
    return with_verdict(diag, float(np.mean(sq)))


def white_null_acf_sq(d: NDArray) -> NDArray:
    """``ρ_d(m)²`` for every lag: their sum is the sequence's ``η`` (docs/algorithms.md §F1)."""
    r = np.correlate(d, d, mode="full") / np.dot(d, d)
    return r**2


def with_verdict(
    diag: NoiseDiagnostics, variance: float, core: float | None = None, outliers: float = 0.0
) -> NoiseDiagnostics:
    """``diag`` with its verdict and notes written for an estimate of ``variance``."""
    return replace(
        diag, verdict=make_verdict(diag, variance, core, outliers), notes=make_notes(diag)
    )
