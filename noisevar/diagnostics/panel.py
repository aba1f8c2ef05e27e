"""What the dashboard's Noise panel draws: residual distribution, QQ, ACF, level profile.

:func:`noise_panel_data` looks at the same residual as :func:`~noisevar.diagnostics.diagnose`
(``DIAG_SPAN``, ``DIAG_ORDER``), each scaled by its wide block's robust level and the whole
standardised to unit mean square, so the histogram shows the noise's shape, not its level.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.diagnostics.assumptions import SHORT_RECORD, unchecked
from noisevar.diagnostics.plan import DIAG_ORDER, DIAG_SPAN
from noisevar.diagnostics.profile import block_bounds, robust_levels
from noisevar.diagnostics.results import NoiseDiagnostics
from noisevar.diagnostics.verdict import under_half_a_step
from noisevar.errors import NoisevarError
from noisevar.numeric.fir import residual_sequence

#: At most this many residuals kept for drawing (the histogram counts every one).
PANEL_RESIDUALS = 20_000
#: At most this many points of the QQ plot.
QQ_POINTS = 2_000
#: Order statistics the Student-t is fitted to (spread evenly over the sorted residuals).
T_FIT_POINTS = 4_000
#: Histogram bins; the histogram spans at most ``±HIST_REACH`` standard deviations.
HIST_BINS = 80
HIST_REACH = 8.0
#: Points of the pdf curves.
PDF_POINTS = 300
#: Wide blocks (samples) whose robust level scales the residuals, as for the kurtosis.
SCALE_BLOCK = 256


@dataclass(frozen=True)
class NoisePanelData:
    """Everything the Noise panel's figures draw, computed from the record.

    Attributes
    ----------
    residuals : ndarray
        Standardised residuals, at most :data:`PANEL_RESIDUALS` evenly spaced in the record.
    n_residuals : int
        Residuals computed (the histogram counts all of them).
    bin_edges, density : ndarray
        Histogram (density over all residuals; ``outside`` of them fall beyond the edges).
    outside : int
    pdf_x, normal_pdf, t_pdf : ndarray
        Unit normal and fitted Student-t densities.
    t_dof, t_scale : float
        The Student-t fitted by maximum likelihood (``scipy.stats.t.fit``, location 0) to
        evenly spread order statistics of the standardised residuals.
    qq_normal, qq_sample, qq_t : ndarray
        Normal quantiles, sorted residuals at those ranks, and the fitted t's quantiles.
    lags, acf, acf_expected, acf_band : ndarray
        The whiteness test's autocorrelation, white-noise null and 95 % half-width.
    white, p_value :
        The whiteness test's outcome.
    block_x, block_half, variance, lo, hi : ndarray
        Level profile: block centres and half-widths (samples, or the times given), levels
        and their 95 % intervals.
    quiet : ndarray of bool
    quiet_variance : float or None
        The quiet level, on the same residual as R (None: the record has none; its
        ``diag.quiet.reason`` says why).
    x_title : str
    unmeasured_x : ndarray, shape (k, 2)
        Stretches moving too fast to measure (``LevelProfile.unmeasured``), first and last
        sample (or time) of each.
    """

    residuals: NDArray
    n_residuals: int
    bin_edges: NDArray
    density: NDArray
    outside: int
    pdf_x: NDArray
    normal_pdf: NDArray
    t_pdf: NDArray
    t_dof: float
    t_scale: float
    qq_normal: NDArray
    qq_sample: NDArray
    qq_t: NDArray
    lags: NDArray
    acf: NDArray
    acf_expected: NDArray
    acf_band: NDArray
    white: bool
    p_value: float
    block_x: NDArray
    block_half: NDArray
    variance: NDArray
    lo: NDArray
    hi: NDArray
    quiet: NDArray
    quiet_variance: float | None
    x_title: str
    unmeasured_x: NDArray = field(default_factory=lambda: np.zeros((0, 2)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (arrays as lists, non-finite values as None)."""
        out: dict[str, Any] = {}
        for key, val in self.__dict__.items():
            arr = np.asarray(val)
            if arr.dtype.kind == "f":
                out[key] = np.where(np.isfinite(arr), arr, None).tolist()
            else:
                out[key] = arr.tolist()
        return out


def standard_residuals(z: NDArray, diag: NoiseDiagnostics) -> NDArray:
    """Residuals of every uniform segment (split at ``diag.gaps``), scaled to unit level."""
    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    cuts = [0, *sorted({g.index for g in diag.gaps if 0 < g.index < z.size}), z.size]
    parts = [
        np.convolve(z[a:b], d[::-1], mode="valid")
        for a, b in zip(cuts[:-1], cuts[1:], strict=True)
        if b - a >= 2 * DIAG_SPAN
    ]
    if not parts:
        raise NoisevarError(f"no uniform stretch of {2 * DIAG_SPAN} samples: nothing to draw")
    # e / ||d||: the noise's scale
    e = np.concatenate(parts) / np.sqrt(np.dot(d, d))
    wide = block_bounds(e.size, SCALE_BLOCK)
    level = np.repeat(robust_levels(e**2, wide), np.diff(np.r_[wide, e.size]))
    u = e / np.sqrt(np.maximum(level, np.finfo(float).tiny))
    rms = float(np.sqrt(np.mean(u**2)))
    return u / rms if rms > 0 else u


def _quantile_ranks(m: int, points: int) -> NDArray:
    """Ranks evenly spread over ``0..m-1``, every one of the extreme tails included."""
    tail = min(m, points // 20)
    body = np.linspace(0, m - 1, max(points - 2 * tail, 2)).astype(int)
    return np.unique(np.r_[body, np.arange(tail), m - 1 - np.arange(tail)])


def noise_panel_data(
    z: ArrayLike, diag: NoiseDiagnostics, t: ArrayLike | None = None
) -> NoisePanelData:
    """The Noise panel's data for the record ``z`` that ``diag`` describes.

    Parameters
    ----------
    z : array_like, shape (n,)
        The finite samples given to the estimate.
    diag : NoiseDiagnostics
        ``estimate(z).diagnostics``.
    t : array_like, shape (n,), optional
        Sample times (the level profile's abscissa), else sample numbers.

    Returns
    -------
    NoisePanelData
    """
    from scipy import stats  # here: import noisevar stays lean (scipy.stats is heavy)

    z = np.asarray(z, dtype=float).ravel()
    if z.size != diag.n or not np.all(np.isfinite(z)):
        raise NoisevarError(
            f"give the {diag.n} finite samples the diagnostics were computed from "
            f"(got {z.size} samples)"
        )
    u = standard_residuals(z, diag)
    m = u.size
    srt = np.sort(u)
    reach = float(min(HIST_REACH, max(np.max(np.abs(u)), 4.0)))
    edges = np.linspace(-reach, reach, HIST_BINS + 1)
    counts, _ = np.histogram(u, edges)
    dens = counts / (m * np.diff(edges))
    fit_at = srt[np.linspace(0, m - 1, min(m, T_FIT_POINTS)).astype(int)]
    dof, _, scale = stats.t.fit(fit_at, floc=0.0)
    x = np.linspace(-reach, reach, PDF_POINTS)
    ranks = _quantile_ranks(m, QQ_POINTS)
    p = (ranks + 0.5) / m
    keep = np.linspace(0, m - 1, min(m, PANEL_RESIDUALS)).astype(int)
    return NoisePanelData(
        residuals=u[keep],
        n_residuals=int(m),
        bin_edges=edges,
        density=dens,
        outside=int(m - counts.sum()),
        pdf_x=x,
        normal_pdf=stats.norm.pdf(x),
        t_pdf=stats.t.pdf(x, dof, scale=scale),
        t_dof=float(dof),
        t_scale=float(scale),
        qq_normal=stats.norm.ppf(p),
        qq_sample=srt[ranks],
        qq_t=stats.t.ppf(p, dof, scale=scale),
        **_acf_fields(diag),
        **_profile_fields(diag, t),
    )


def _acf_fields(diag: NoiseDiagnostics) -> dict[str, Any]:
    w = diag.whiteness
    return {
        "lags": np.arange(1, w.acf.size + 1),
        "acf": np.asarray(w.acf),
        "acf_expected": np.asarray(w.expected),
        "acf_band": np.asarray(w.band),
        "white": w.white,
        "p_value": float(w.p_value),
    }


def _profile_fields(diag: NoiseDiagnostics, t: ArrayLike | None) -> dict[str, Any]:
    prof = diag.level_profile
    a, b = prof.start.astype(float), prof.stop.astype(float) - 1.0
    moved = np.array(prof.unmeasured, dtype=float).reshape(-1, 2) - [0.0, 1.0]
    if t is not None:
        tt = np.asarray(t, dtype=float).ravel()
        if tt.size != diag.n:
            raise NoisevarError(f"give one time per sample ({diag.n}), got {tt.size}")
        idx = np.arange(tt.size)
        a, b, moved = (np.interp(x, idx, tt) for x in (a, b, moved))
    return {
        "unmeasured_x": moved,
        "block_x": 0.5 * (a + b),
        "block_half": 0.5 * (b - a),
        "variance": np.asarray(prof.variance),
        "lo": np.asarray(prof.lo),
        "hi": np.asarray(prof.hi),
        "quiet": np.asarray(prof.quiet, dtype=bool),
        "quiet_variance": None if diag.quiet_variance is None else float(diag.quiet_variance),
        "x_title": "sample" if t is None else "time (s)",
    }


def verdict_severity(
    diag: NoiseDiagnostics | None, variance: float | None = None, n: int | None = None
) -> str:
    """``"ok"``, ``"caution"`` (heavy tails, gaps, a short record) or ``"warning"`` (a white
    R misleads).

    With the estimate's ``variance``, a level that varies on a grid with noise under half
    a step (:func:`~noisevar.diagnostics.verdict.under_half_a_step`) is neither a warning
    nor, with it, heavy tails a caution: rounding makes both (a level that follows the
    offset within a step, an error that is mostly zero), and the verdict says so. A record
    too short for some checks (:func:`~noisevar.diagnostics.assumptions.unchecked`; ``diag``
    None: too short to diagnose, of ``n`` samples) is a caution, or a warning when the
    checks it allows fail; no diagnostics and no ``n``: ``"ok"`` (nothing to say).
    """
    if diag is None:
        return "caution" if n is not None and n < SHORT_RECORD else "ok"
    if unchecked(diag.n, diag):
        return "caution" if diag.white and diag.identifiable else "warning"
    f = diag.flags
    # the verdict's own case: a varying level explained by rounding (make_verdict)
    rounding = f["level_varies"] and variance is not None and under_half_a_step(diag, variance)
    if not (f["identifiable"] and f["white"]) or (f["level_varies"] and not rounding):
        return "warning"
    if (f["heavy_tailed"] and not rounding) or diag.fourth_moment_unreliable or f["gaps"]:
        return "caution"
    return "ok"


def assumption_rows(estimates: Iterable[Any]) -> list[dict[str, str]]:
    """One row per method: the assumptions that hold and fail on this record, in words.

    Parameters
    ----------
    estimates : iterable of VarianceEstimate
        One per method (their ``.assumptions``).

    Returns
    -------
    list of dict
        Keys ``method``, ``holds``, ``fails``, ``meaning``.
    """
    rows = []
    for est in estimates:
        held = getattr(est, "assumptions", None) or {}
        ok = [k for k, v in held.items() if v]
        bad = [k for k, v in held.items() if not v]
        diag = getattr(est, "diagnostics", None)
        gaps = unchecked(diag.n if diag is not None else 0, diag)
        if bad:
            meaning = (
                f"its number is not a trustworthy R here: the record lacks {' and '.join(bad)}"
            )
        elif gaps:  # what a short record cannot check is neither held nor failed
            meaning = f"too few samples to check {' or '.join(gaps)}: untested here"
        elif not held:
            meaning = "it states no assumption about the noise"
        else:
            meaning = "everything it assumes holds on this record"
        rows.append(
            {
                "method": est.method,
                "holds": ", ".join(ok) or "-",
                "fails": ", ".join(bad) or "-",
                "meaning": meaning,
            }
        )
    return rows
