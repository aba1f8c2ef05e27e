"""SOMD with an alpha-beta-gamma virtual sensor (docs/algorithms.md §A5-§A8), vectorised.

One core computes, for ``k`` channels at once, the smoothing and tracking filters and
the squared mutual differences ``(ΔZ1 - ΔZ2)²``. The unselected estimate is their
mean over the settled samples; window selection (§A5) runs per channel on the same
arrays. :func:`somd_variance_windows` and :func:`somd_variance_records` are the
unselected estimate over many windows and runs, on the same core.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError, NoWindowKept
from noisevar.estimators._input import check_window
from noisevar.estimators.difference import sequence_efficiency
from noisevar.estimators.params import PAPER_H_SMOOTH, PAPER_WINDOW, PARAMS, SOMD_PARAMS
from noisevar.estimators.results import SomdDetails, VarianceEstimate, chi2_interval
from noisevar.estimators.spec import MethodSpec
from noisevar.filters.abg import (
    abg_filter,
    check_h,
    settling_samples,
    somd_bias_factor,
    somd_sequence,
)
from noisevar.filters.selection import select_windows

#: The estimator's defaults that decide when a batch window is long enough.
TRACK_RATIO = 30.0
MIN_WINDOWS = 2
WINDOW = PAPER_WINDOW


@lru_cache(maxsize=256)
def _somd_efficiency(h: float) -> float:
    """``sum ρ²`` of the sequence ``Δ(g - δ)`` behind one smoothing ``h``."""
    seq = somd_sequence(h)
    seq = seq[: max(8, int(np.argmax(np.cumsum(seq**2) > (1 - 1e-10) * np.sum(seq**2))) + 1)]
    return sequence_efficiency(seq)


def _as_h_tuple(h_smooth: float | Sequence[float] | None) -> tuple[float, ...]:
    if h_smooth is None:
        return (PAPER_H_SMOOTH,)
    if isinstance(h_smooth, int | float | np.floating):
        return (check_h(h_smooth, "h_smooth"),)
    hs = tuple(check_h(h, "h_smooth") for h in h_smooth)
    if not hs:
        raise NoisevarError("h_smooth is empty: give at least one smoothing h")
    return hs


def mutual_squares(z: NDArray, smooth: NDArray) -> NDArray:
    """``(ΔZ1 - ΔZ2)²`` along the last axis: ``Z1`` the virtual sensor, ``Z2`` the samples."""
    # ΔZ1 - ΔZ2 (docs/algorithms.md §A7, eq. 8)
    return (np.diff(smooth, axis=-1) - np.diff(z, axis=-1)) ** 2


@dataclass(frozen=True)
class _Setup:
    """Validated SOMD settings for records of ``n`` samples."""

    paper: bool
    hs: tuple[float, ...]
    ht: float
    m: int
    gamma_amp: float
    gamma_ang: float
    angle: str
    skip: int
    factors: tuple[float, ...]

    def params(self, select: bool) -> dict:
        hs = self.hs
        return {
            "h_smooth": list(hs) if len(hs) > 1 else hs[0],
            "h_track": self.ht,
            "window": self.m,
            "gamma_amp": self.gamma_amp,
            "gamma_ang": self.gamma_ang,
            "angle": self.angle,
            "select": bool(select),
        }


def _setup(  # noqa: PLR0913 - the SOMD parameters
    n: int,
    paper: bool,
    h_smooth: float | Sequence[float] | None,
    h_track: float | None,
    track_ratio: float,
    window: int,
    gamma_amp: float,
    gamma_ang: float,
    angle: str | None,
) -> _Setup:
    hs = _as_h_tuple(h_smooth)
    if h_track is None:
        h_track = min(hs) * PARAMS["track_ratio"].validate(track_ratio)
    ht = check_h(h_track, "h_track")
    m = check_window(window, n)
    gamma_amp = PARAMS["gamma_amp"].validate(gamma_amp)
    gamma_ang = PARAMS["gamma_ang"].validate(gamma_ang)
    angle = PARAMS["angle"].validate(angle or ("paper" if paper else "scaled"))
    skip = max(settling_samples(h) for h in (*hs, ht))
    if n - skip < 2 * m:
        raise NoisevarError(
            f"too few samples: the filters need {skip} samples to settle (h_smooth={min(hs):g}) "
            f"and then at least two windows of {m}; give more than {skip + 2 * m} samples "
            "or a larger h_smooth, or the default method (no filters to settle)"
        )
    factors = tuple(2.0 if paper else somd_bias_factor(h) for h in hs)
    return _Setup(paper, hs, ht, m, gamma_amp, gamma_ang, angle, skip, factors)


@dataclass
class _Core:
    """Filter outputs and window sums of ``k`` channels (``n_h`` smoothing filters)."""

    smooth: NDArray  # (n_h, k, n)
    track: NDArray  # (k, n)
    sq: NDArray  # (n_h, k, n): (ΔZ1 - ΔZ2)², 0 at the last sample
    per_h: NDArray  # (n_h, k, n_windows): each window's estimate for each h
    counts: NDArray  # (n_windows,)


def _core(z: NDArray, s: _Setup) -> _Core:
    """The vectorised part of SOMD for ``z`` of shape ``(k, n)``."""
    k, n = z.shape
    nh, m = len(s.hs), s.m
    smooth = np.stack([abg_filter(z, h, axis=-1) for h in s.hs])
    track = abg_filter(z, s.ht, axis=-1)
    sq = np.concatenate([mutual_squares(z, smooth), np.zeros((nh, k, 1))], axis=-1)
    n_win = n // m
    counts = np.full(n_win, m, dtype=float)
    if n_win * m == n:
        counts[-1] -= 1  # last sample has no forward difference
    win_sq = sq[..., : n_win * m].reshape(nh, k, n_win, m)
    # window estimate = sum((ΔZ1 - ΔZ2)²) / count / c(h)
    per_h = win_sq.sum(axis=-1) / counts / np.asarray(s.factors)[:, None, None]
    return _Core(smooth, track, sq, per_h, counts)


def _details(s: _Setup, c: _Core, i: int, selection, kept, window_var, mask) -> SomdDetails:
    return SomdDetails(
        h_smooth=s.hs,
        h_track=s.ht,
        smooth_output=c.smooth[:, i],
        track_output=c.track[i],
        selection=selection,
        kept_windows=kept,
        window_variance=window_var,
        sample_mask=mask,
        bias_factor=s.factors,
        skip=s.skip,
    )


def _result(s: _Setup, variance: float, n_used: int, n: int, select: bool, notes, details):
    eff = float(np.mean([_somd_efficiency(h) for h in s.hs]))
    dof = n_used / eff
    method = "somd-paper" if s.paper else "somd"
    return VarianceEstimate(
        method,
        variance,
        chi2_interval(variance, dof),
        n_used,
        n,
        dof,
        s.params(select),
        notes,
        details,
    )


def _unselected(z: NDArray, s: _Setup, c: _Core, notes: list[list[str]]) -> list[VarianceEstimate]:
    """Every channel's estimate over all settled samples, at once."""
    k, n = z.shape
    starts = np.arange(c.counts.size) * s.m
    in_record = starts >= s.skip
    window_var = np.where(in_record, c.per_h.mean(axis=0), np.nan)
    # var = mean over h of mean_{k >= skip}(ΔZ1 - ΔZ2)² / c(h)
    tail = c.sq[..., s.skip : n - 1]
    variance = np.mean(tail.mean(axis=-1) / np.asarray(s.factors)[:, None], axis=0)
    mask = np.zeros(n, dtype=bool)
    mask[s.skip : n - 1] = True
    n_used = n - 1 - s.skip
    return [
        _result(
            s,
            float(variance[i]),
            n_used,
            n,
            False,
            notes[i],
            _details(s, c, i, None, in_record, window_var[i], mask.copy()),
        )
        for i in range(k)
    ]


def _selected(z: NDArray, s: _Setup, c: _Core, i: int, notes: list[str]) -> VarianceEstimate:
    """Channel ``i``'s estimate over the windows kept by eq. [19] (§A5, §A6)."""
    n, m = z.shape[-1], s.m
    amplitude = "paper" if s.paper else "symmetric"  # somd is invariant to the signal's sign
    sels = [
        select_windows(
            z[i],
            sm,
            c.track[i],
            m,
            s.gamma_amp,
            s.gamma_ang,
            s.angle,
            skip=s.skip,
            amplitude=amplitude,
        )
        for sm in c.smooth[:, i]
    ]
    passing = np.stack([sel.kept for sel in sels])
    kept = passing.any(axis=0)
    if not kept.any():
        _no_window_kept(s, c, i, sels[0], kept, notes)
    per_h = c.per_h[:, i]
    with np.errstate(invalid="ignore"):
        # a window's estimate is the mean over the h that pass there (§A6)
        window_var = np.where(
            kept, np.sum(per_h * passing, axis=0) / np.maximum(passing.sum(axis=0), 1), np.nan
        )
    variance = float(np.nanmean(window_var))
    mask = np.repeat(kept, m)
    mask = np.concatenate([mask, np.zeros(n - mask.size, dtype=bool)])
    n_used = int(c.counts[kept].sum())
    details = _details(s, c, i, sels[0], kept, window_var, mask)
    return _result(s, variance, n_used, n, True, notes, details)


def _no_window_kept(s: _Setup, c: _Core, i: int, selection, kept, notes) -> None:
    n = c.track.shape[-1]
    summ = selection.rejection_summary()
    details = _details(
        s, c, i, selection, kept, np.full(kept.size, np.nan), np.zeros(n, dtype=bool)
    )
    nan = float("nan")
    method = "somd-paper" if s.paper else "somd"
    diagnosis = VarianceEstimate(method, nan, (nan, nan), 0, n, 0.0, s.params(True), notes, details)
    raise NoWindowKept(
        f"no window kept: of {summ['windows']} windows, {summ['failed_amplitude']} failed "
        f"the amplitude test (gamma_amp={s.gamma_amp:g}) and {summ['failed_angle']} the "
        f"angle test (gamma_ang={s.gamma_ang:g} deg); relax gamma_amp towards 1 or "
        "gamma_ang, use a longer window, or turn selection off",
        summ,
        diagnosis,
    )


def somd_channels(  # noqa: PLR0913 - the SOMD parameters
    z: NDArray,
    *,
    paper: bool,
    h_smooth: float | Sequence[float] | None = None,
    h_track: float | None = None,
    track_ratio: float = 30.0,
    window: int = PAPER_WINDOW,
    gamma_amp: float = 0.5,
    gamma_ang: float = 10.0,
    angle: str | None = None,
    select: bool = True,
    notes: list[list[str]] | None = None,
) -> list[VarianceEstimate]:
    """SOMD of ``k`` validated channels, ``z`` of shape ``(k, n)``.

    See :func:`somd_estimate` for the parameters; ``notes`` holds one list per channel.
    Without selection all channels are computed at once; with it, the filters are.
    """
    k, n = z.shape
    notes = [list(nt) for nt in notes] if notes is not None else [[] for _ in range(k)]
    s = _setup(n, paper, h_smooth, h_track, track_ratio, window, gamma_amp, gamma_ang, angle)
    c = _core(z, s)
    if not select:
        return _unselected(z, s, c, notes)
    return [_selected(z, s, c, i, notes[i]) for i in range(k)]


def somd_estimate(
    z: NDArray, *, paper: bool, notes: list[str] | None = None, **params: object
) -> VarianceEstimate:
    """SOMD with an alpha-beta-gamma virtual redundant sensor (docs/algorithms.md §A5-§A8).

    ``var = E[(ΔZ1 - ΔZ2)²] / c`` over the samples of the kept windows, ``Z1`` the
    smoothing filter's one-step prediction and ``Z2`` the samples; ``c = 2`` as printed
    (``paper=True``) or the exact ``c(h)`` of §A8.

    Parameters
    ----------
    z : ndarray, shape (n,)
        Validated samples.
    paper : bool
        Paper-literal factor 2, angle convention and amplitude test; otherwise ``c(h)``
        and the symmetric amplitude test (invariant to the signal's sign).
    notes : list of str, optional
        Remarks carried into the result.
    **params
        ``h_smooth`` (one or several ``h_S``, default 1.5e-5), ``h_track`` (default
        ``track_ratio * min(h_S)``), ``track_ratio``, ``window``, ``gamma_amp``,
        ``gamma_ang`` (degrees), ``angle`` ({"scaled", "paper"}), ``select``.

    Returns
    -------
    VarianceEstimate
        With :class:`~noisevar.estimators.results.SomdDetails`.

    Raises
    ------
    NoWindowKept
        Selection kept no window (the refused estimate is its ``diagnosis``).
    """
    return somd_channels(np.asarray(z)[None, :], paper=paper, notes=[notes or []], **params)[0]


def _somd(z: NDArray, notes: list[list[str]], **p: object) -> list[VarianceEstimate]:
    return somd_channels(z, paper=False, notes=notes, **p)


def _somd_paper(z: NDArray, notes: list[list[str]], **p: object) -> list[VarianceEstimate]:
    p.setdefault("gamma_ang", 5.0)
    return somd_channels(z, paper=True, notes=notes, **p)


SOMD = MethodSpec(
    "somd",
    "SOMD, alpha-beta-gamma virtual sensor, exact c(h) correction",
    "somd",
    _somd,
    SOMD_PARAMS,
    vectorised=True,
)
SOMD_PAPER = MethodSpec(
    "somd-paper",
    "SOMD exactly as printed (factor 1/2)",
    "somd",
    _somd_paper,
    SOMD_PARAMS,
    vectorised=True,
)


# ------------------------------------------------------------------- batch helpers
def _batch_setup(h: float, paper: bool) -> tuple[float, int, float]:
    """``h``, the settling length and the factor of the estimator's defaults."""
    h = check_h(h, "h_smooth")
    ht = check_h(h * TRACK_RATIO, "h_track")
    skip = max(settling_samples(h), settling_samples(ht))
    return h, skip, 2.0 if paper else somd_bias_factor(h)


def somd_variance_windows(
    z: NDArray, bounds: Sequence[tuple[int, int]], h: float, paper: bool = False
) -> NDArray:
    """SOMD variance (no selection) of ``z[:, start:stop]`` for every window and run.

    Windows that share a start share one filter pass: a growing window's filter output
    is a prefix of the longer one's, so cumulative sums give them all.

    Parameters
    ----------
    z : ndarray, shape (B, N)
        One channel of ``B`` runs.
    bounds : sequence of (start, stop)
        Windows (``stop`` exclusive).
    h : float
        Smoothing ``h_S`` (``h_T = 30 h_S``, the estimator's default).
    paper : bool
        Factor 2 (paper) instead of ``c(h)``.

    Returns
    -------
    ndarray, shape (B, len(bounds))
        ``estimate(window, method="somd", h_smooth=h, select=False).variance`` (or
        ``"somd-paper"``); NaN where a window is too short for the filters to settle.
    """
    h, skip, factor = _batch_setup(h, paper)
    z = np.asarray(z, dtype=float)
    B = z.shape[0]
    out = np.full((B, len(bounds)), np.nan)
    by_start: dict[int, list[int]] = {}
    for i, (start, stop) in enumerate(bounds):
        if stop - start - skip >= MIN_WINDOWS * WINDOW:
            by_start.setdefault(int(start), []).append(i)
    for start, idx in by_start.items():
        seg = z[:, start : max(bounds[i][1] for i in idx)]
        sq = mutual_squares(seg, abg_filter(seg, h, axis=-1))
        csum = np.concatenate([np.zeros((B, 1)), np.cumsum(sq, axis=-1)], axis=-1)
        for i in idx:
            n = bounds[i][1] - start
            out[:, i] = (csum[:, n - 1] - csum[:, skip]) / (n - 1 - skip) / factor
    return out


def somd_variance_records(z: NDArray, h: float, paper: bool = False) -> NDArray:
    """SOMD variance (no selection) of every whole record of a batch at once.

    Parameters
    ----------
    z : ndarray, shape (B, N)
        One channel of ``B`` runs.
    h : float
        Smoothing ``h_S`` (``h_T = 30 h_S``, the estimator's default).
    paper : bool
        Factor 2 (paper) instead of ``c(h)``.

    Returns
    -------
    ndarray, shape (B,)
        ``estimate(z[b], method="somd", h_smooth=h, select=False).variance`` (or
        ``"somd-paper"``) for each run; all NaN when the records are too short for the
        filters to settle or hold NaN/Inf (where :func:`noisevar.estimate` refuses them).
    """
    h, skip, factor = _batch_setup(h, paper)
    z = np.asarray(z, dtype=float)
    B, n = z.shape
    if n - skip < MIN_WINDOWS * WINDOW or not np.all(np.isfinite(z)):
        return np.full(B, np.nan)
    sq = mutual_squares(z, abg_filter(z, h, axis=-1))
    # var = mean_{k >= skip}(ΔZ1 - ΔZ2)² / c
    return sq[:, skip:].mean(axis=1) / factor
