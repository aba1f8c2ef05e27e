"""R's interval for a moment estimator (docs/algorithms.md §E1 *Kurtosis*, *Glitches in R*).

:func:`honest_interval` widens the method's Gaussian χ² interval for the measured
kurtosis and correlation. When a few lone glitches carry much of R, ``R = C + G``:
``C`` the noise without them, ``G`` their share. R's sampling distribution is then not a
scaled χ² (which the kurtosis widening assumes) but ``C`` plus a Poisson number of
glitches times their energies: ``G``'s interval is the gamma interval of a weighted
Poisson sum (Fay & Feuer 1997; Garwood's exact Poisson interval when the energies are
equal), ``C``'s a χ² interval with the core's own kurtosis, and the two are added by the
method of variance estimates recovery (MOVER: Zou & Donner 2008).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf, norm_cdf
from noisevar.diagnostics import NoiseDiagnostics, glitches_apart
from noisevar.diagnostics.glitches import bridged, deviations, lone
from noisevar.diagnostics.plan import DIAG_ORDER, DIAG_SPAN
from noisevar.diagnostics.tails import heavy_tails as heavy_tails  # the tail rules, for
from noisevar.diagnostics.tails import kurtosis_from_moments  # noise_model (no edge to
from noisevar.diagnostics.tails import tail_index as tail_index  # diagnostics there)
from noisevar.diagnostics.tails import tails_shape as tails_shape
from noisevar.diagnostics.tails import unreliable_tail as unreliable_tail
from noisevar.estimators.results import VarianceEstimate, chi2_interval
from noisevar.numeric.fir import residual_sequence

#: A lone glitch's deviation from the line through its two neighbours holds noise of
#: variance 1.5 σ² (its own sample and half of each neighbour's): subtracted from its energy.
NOISE_IN_DEVIATION = 1.5
#: At most this many lone outlying samples are counted as a Poisson number of glitches:
#: more, and their count's interval is near the normal one the kurtosis widening gives.
FEW_GLITCHES = 10
#: A lone glitch this close to the record's edge is in R even among a jump's left-out
#: samples: ``auto`` counts it as inside (its shortest span - 1, ``auto._edges``).
EDGE_IN_R = 10
#: The normal 97.5 % quantile.
Z95 = 1.959963984540054


def poisson_sum_interval(weights: NDArray, level: float = 0.95) -> tuple[float, float]:
    """Interval of the mean of ``Σ w_j X_j``, ``X_j`` Poisson, from one draw each ``x_j = 1``.

    The gamma interval of Fay & Feuer (1997): with ``y = Σ w``, ``v = Σ w²``, ``m = max w``,
    ``(v / 2y · χ²_{a/2}(2y²/v),  (v + m²) / 2(y + m) · χ²_{1-a/2}(2(y + m)²/(v + m²)))``.

    Parameters
    ----------
    weights : ndarray
        The observed events' weights (> 0): here each glitch's energy over ``n``.
    level : float
        Confidence level.

    Returns
    -------
    (low, high) : tuple of float

    Notes
    -----
    Equal weights ``w`` give Garwood's exact Poisson interval times ``w``:
    ``(w χ²_{a/2}(2k) / 2, w χ²_{1-a/2}(2k + 2) / 2)``; one glitch: ``0.0253 w .. 5.57 w``.
    Unequal energies count as fewer events (``2y²/v`` dof, ``y²/v`` the effective count).
    """
    w = np.asarray(weights, dtype=float)
    a = 1.0 - level
    y, v, m = float(w.sum()), float(np.sum(w**2)), float(w.max())
    lo = v / (2.0 * y) * float(chi2_ppf(a / 2.0, 2.0 * y * y / v))
    up = 2.0 * (y + m) ** 2 / (v + m * m)
    hi = (v + m * m) / (2.0 * (y + m)) * float(chi2_ppf(1.0 - a / 2.0, up))
    return lo, hi


def mover_sum(value: float, parts: list[tuple[float, float, float]]) -> tuple[float, float]:
    """Interval of a sum of independent parts from each part's interval (MOVER).

    ``Σ x ∓ sqrt(Σ (x - x_lo)²)`` below, ``sqrt(Σ (x_hi - x)²)`` above (Zou & Donner
    2008): each side of each part's interval stands for its spread on that side, so skewed
    parts (Poisson, χ²) keep their shape. ``parts``: ``(x, x_lo, x_hi)``; ``value`` = Σ x.
    """
    p = np.asarray(parts, dtype=float)
    lo = value - float(np.sqrt(np.sum((p[:, 0] - p[:, 1]) ** 2)))
    hi = value + float(np.sqrt(np.sum((p[:, 2] - p[:, 0]) ** 2)))
    return max(lo, 0.0), hi


@dataclass(frozen=True)
class LoneGlitches:
    """A record's lone outlying samples in R, each with its squared size.

    Attributes
    ----------
    at : ndarray of int
        Their samples (record indices).
    squares : ndarray of float
        ``d²`` each (squared units of the record as estimated), ``d`` its distance from
        the line through its neighbours.
    level : float
        σ², the diagnostics' level their sizes were read against.
    core_kurtosis : float or None
        The noise kurtosis with them bridged (None: unknown; the record's is used).
    """

    at: NDArray
    squares: NDArray
    level: float
    core_kurtosis: float | None

    def within(self, inside: NDArray | None) -> LoneGlitches:
        """Those at the samples ``inside`` (a mask of the record; None: all)."""
        if inside is None:
            return self
        keep = (self.at < inside.size) & inside[np.minimum(self.at, inside.size - 1)]
        return LoneGlitches(self.at[keep], self.squares[keep], self.level, self.core_kurtosis)


def lone_glitches(
    outliers: NDArray | None, diag: NoiseDiagnostics, read: Callable[[int, int], NDArray] | None
) -> LoneGlitches | None:
    """The lone glitches R counts, sized (None: none, or more than :data:`FEW_GLITCHES`).

    The diagnostics' (``diag.glitches``, at most 0.1 % of the samples) with their sizes;
    else the method's outlying samples ``outliers`` that come alone
    (:func:`~noisevar.diagnostics.glitches.lone`), sized off ``read`` as the diagnostics
    size theirs (a short record: one glitch in fewer than 1000 samples).
    """
    prof = diag.level_profile
    level = float(prof.quiet_variance if prof.quiet.any() else prof.pooled_level)
    if not (np.isfinite(level) and level > 0):
        return None
    if diag.glitches:
        at = np.array([g.index for g in diag.glitches])
        sigmas = np.array([g.sigmas for g in diag.glitches])
        core = diag.core_kurtosis
    else:
        if outliers is None or read is None or not 0 < outliers.size <= 2 * FEW_GLITCHES:
            return None
        if glitches_apart(outliers.size, diag.n):  # apart, yet not listed: not lone
            return None
        at = lone(outliers)
        if not 0 < at.size <= FEW_GLITCHES or at.size < np.unique(outliers).size:
            return None  # a burst beside them: the kurtosis interval's case
        sigmas = deviations(at, read, diag.n) / np.sqrt(level)
        core = _bridged_kurtosis(read(0, diag.n), at)
    squares = sigmas**2 * level
    ok = np.isfinite(squares)
    if not ok.any():
        return None
    return LoneGlitches(at[ok], squares[ok], level, core)


def _bridged_kurtosis(x: NDArray, at: NDArray) -> float | None:
    """The noise kurtosis of the diagnostics' residual of ``x`` with ``at`` bridged (a
    record of fewer than ``2e4`` samples: one pass; None when too short)."""
    d = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    if x.size < 4 * d.size:
        return None
    e = np.convolve(bridged(x, at), d / np.sqrt(np.dot(d, d)), mode="valid")
    e2 = e * e
    return kurtosis_from_moments(float(e2.mean()), float(np.mean(e2 * e2)), d)


def off_jumps(runs: list[tuple[int, int]], n: int) -> NDArray:
    """The samples of a record of ``n`` whose glitches R counts: off the ``runs`` left out
    around level jumps, and the first and last ``EDGE_IN_R`` whatever (a glitch there
    counts in R as inside: ``auto._edges``, docs/algorithms.md §F5.4)."""
    out = ~ranges_mask(runs, n)
    out[:EDGE_IN_R] = out[n - EDGE_IN_R :] = True
    return out


def listed_in_r(diag: NoiseDiagnostics, inside: NDArray) -> NoiseDiagnostics:
    """``diag`` listing only the glitches at the samples ``inside`` (:func:`off_jumps`): those
    R counts. A jump's own sample stands out of its neighbours' line like a glitch, and 20
    steps read "20 outlying samples" that R "counts as noise" (issue 26). The diagnostics'
    correlation findings still leave every outlying sample out (``from_sums``)."""
    kept = tuple(g for g in diag.glitches if g.index < inside.size and inside[g.index])
    return diag if len(kept) == len(diag.glitches) else replace(diag, glitches=kept)


def record_glitches(
    record: Any, outliers: NDArray | None, diag: NoiseDiagnostics
) -> LoneGlitches | None:
    """:func:`lone_glitches` of a record (``estimators.pipeline.Record``): read off its
    ``reader()``, or its samples ``z`` when it is in segments (a glitch's neighbours)."""
    read = record.reader()
    z = getattr(record, "z", None)
    if read is None and z is not None:
        read = lambda a, b: z[a:b]  # noqa: E731
    return lone_glitches(outliers, diag, read)


def glitches_within(lone: LoneGlitches | None, inside: NDArray) -> LoneGlitches | None:
    """``lone`` at the samples ``inside`` only (None stays None)."""
    return None if lone is None else lone.within(inside)


def glitch_interval(
    variance: float,
    n_used: int,
    eta: float,
    kurtosis: float,
    glitches: LoneGlitches,
    core: float | None = None,
    n: int | None = None,
) -> tuple[float, float] | None:
    """R's interval as its core's plus its lone glitches' share (None: none in R).

    Parameters
    ----------
    variance : float
        R, glitches in.
    n_used : int
        Residuals in R.
    eta : float
        The method's ``n / ν₀`` times the correlation excess (:func:`honest_interval`).
    kurtosis : float
        The core's noise kurtosis (the glitches' own left out when known).
    glitches : LoneGlitches
        Those in R.
    core : float, optional
        R without its outlying samples (``core_variance``): the σ² each glitch's energy
        ``d² - 1.5 σ²`` is taken against, and ``G`` is at most ``R - core`` (a glitch at
        the record's edge reads larger off its one neighbour than it counts in R).
    n : int, optional
        Samples in the record: a glitch at its first or last sample may be a level step
        of one sample (:func:`edge_step`), and the share's lower end leaves it out.

    Returns
    -------
    (low, high) or None
    """
    # σ² on R's own residual (the core), else the diagnostics' (which a fast signal raises)
    s2 = core if core is not None and 0 < core < variance else glitches.level
    energy = glitches.squares - NOISE_IN_DEVIATION * s2
    step = edge_step(glitches.at, n)[energy > 0]
    energy = energy[energy > 0]
    if energy.size == 0 or not (variance > 0 and n_used > 0):
        return None
    g = min(float(energy.sum()) / n_used, variance)
    if core is not None and 0 < core < variance:
        g = min(g, variance - core)
    c = variance - g
    dof = n_used / (eta + max(kurtosis - 3.0, 0.0) / 2.0)
    c_lo, c_hi = chi2_interval(c, dof) if c > 0 else (0.0, 0.0)
    g_lo, g_hi = poisson_sum_interval(energy * (g / energy.sum()))
    if step.any():  # the share without the edge sample(s): the inner glitches' lower end
        inner = energy[~step] * (g / energy.sum())
        g_lo = poisson_sum_interval(inner)[0] if inner.size else 0.0
    # the split: d² - a² = 2 a ν with ν of variance 1.5 σ², so var = 6 σ² Σ a² / n²
    split = Z95 * np.sqrt(4.0 * NOISE_IN_DEVIATION * s2 * energy.sum()) / n_used
    return mover_sum(variance, [(c, c_lo, c_hi), (g, g_lo, g_hi), (0.0, -split, split)])


def edge_step(at: NDArray, n: int | None) -> NDArray:
    """Which glitches at the samples ``at`` sit at the first or last of ``n`` samples.

    A lone far-off sample at the record's edge cannot be told from a level step of one
    sample (the first GPS fix of a KITTI drive, before a 2.9 s gap: R 0.077 with it, 0.0085
    without): inside the record a glitch has a neighbour on each side that agree without
    it, at the edge only one. R counts it as noise (a glitch), but its interval reaches the
    reading without it (docs/algorithms.md §E1 *Glitches in R*). ``n`` None: none.
    """
    at = np.asarray(at)
    if n is None:
        return np.zeros(at.size, dtype=bool)
    return (at == 0) | (at == n - 1)


def ranges_mask(ranges: list[tuple[int, int]], n: int) -> NDArray:
    """The samples of ``n`` inside the sample ranges ``ranges`` (a sub-estimate's ``inside``)."""
    out = np.zeros(n, dtype=bool)
    for a, b in ranges:
        out[a:b] = True
    return out


def honest_interval(
    r: VarianceEstimate, diag: NoiseDiagnostics, glitches: LoneGlitches | None = None
) -> VarianceEstimate:
    """Widen a moment estimator's interval for the noise's kurtosis and correlation.

    ``ν = n / (η c + (κ - 3) / 2)`` with ``η = n / ν₀`` the method's own factor, ``κ``
    the noise kurtosis and ``c`` the excess of the residual's correlation over white
    noise's (1 when the noise passes the whiteness test) (docs/algorithms.md §E1). With
    lone glitches in R (``glitches``, those at R's samples), each side of ``ci95`` is the
    wider of that χ² interval's and the core's plus the glitches' share
    (:func:`glitch_interval`); ``dof`` stays the χ² one.
    """
    if not (r.dof > 0 and r.n_used > 0):
        return r
    eta = r.n_used / r.dof
    w = diag.whiteness
    c = 1.0
    if not w.white:
        c = max(1.0, (1 + 2 * np.sum(w.acf**2)) / (1 + 2 * np.sum(w.expected**2)))
    # the method's own reading (blind to a fast signal) or the diagnostics' (whose block
    # levels see a level that changes within a block), whichever says the tails are heavier
    kurt = diag.kurtosis if r.kurtosis is None else max(r.kurtosis, diag.kurtosis)
    excess = max(kurt - 3.0, 0.0) / 2.0
    lone = None
    if glitches is not None:
        core = kurt if glitches.core_kurtosis is None else glitches.core_kurtosis
        lone = glitch_interval(
            r.variance, r.n_used, eta * c, core, glitches, r.core_variance, diag.n
        )
    if c == 1.0 and excess == 0.0 and lone is None:
        return r
    dof = float(r.n_used / (eta * c + excess))
    lo, hi = chi2_interval(r.variance, dof)
    notes = r.notes
    if lone is not None:
        lo, hi = min(lo, lone[0]), max(hi, lone[1])
        notes = [*notes, sizes_seen(glitches.squares.size)]
    return replace(r, dof=dof, ci95=(lo, hi), notes=notes)


def sizes_seen(k: int) -> str:
    """What R's interval assumes when ``k`` lone glitches are in it (docs/algorithms.md §E1
    *Glitches in R*: no interval from a few glitches can bound the sizes not seen)."""
    which = "a lone glitch" if k == 1 else f"{k} lone glitches"
    return (
        f"R holds {which}: its ci95 counts a Poisson number of glitches of the sizes seen; "
        "larger glitches, which so few cannot rule out, would put the long-run R above it"
    )


#: Within this factor of the coloured-noise threshold either side, the whiteness test's
#: p-value does not decide between the per-block spans and the coloured-noise span: a few
#: samples more or less move it that far. Dropping 1-3 samples moves log10 p by 1.03 on
#: the PX4 log's magnetometer (tests/data) and by at most 0.39 on 99 % of seeded AR(1)
#: records near the threshold (``benchmarks/colour_edge.py``): 30 (1.48 decades) holds
#: the real move with a margin, and leaves p < 3e-3 of white noise the one extra pass.
EDGE_FACTOR = 30.0


def edge_weight(p: float, threshold: float, factor: float | None = None) -> float:
    """The coloured-noise estimate's weight at whiteness p-value ``p``: 0 at and above
    ``threshold * factor``, 1 at and below ``threshold / factor``, linear in ``log p``
    between (1/2 at the threshold; ``factor`` :data:`EDGE_FACTOR` unless given)."""
    factor = EDGE_FACTOR if factor is None else factor
    if not factor > 1.0:
        return float(p < threshold)
    w = np.log(threshold * factor / max(p, 1e-300)) / np.log(factor * factor)
    return float(np.clip(w, 0.0, 1.0))


def at_edge(white: VarianceEstimate, coloured: VarianceEstimate, w: float) -> VarianceEstimate:
    """R at the edge of white noise: the two estimates weighed, its interval covering both.

    Parameters
    ----------
    white, coloured : VarianceEstimate
        The method's estimate with its own parameters and with its coloured-noise
        parameters, each with its interval.
    w : float
        The coloured estimate's weight (:func:`edge_weight`), strictly between 0 and 1.

    Returns
    -------
    VarianceEstimate
        The one of the two with the larger weight, with ``R = white^(1-w) coloured^w``,
        its interval that of the two estimates' mixture with weights ``1 - w, w``
        (:func:`mixture_interval`: model uncertainty), and a note that says both.

    Notes
    -----
    docs/algorithms.md §E1 *At the edge of white*. Weighing in logs keeps R continuous
    in ``log p``, so that a p-value that crosses the threshold moves R by little.
    """
    a, b = white.variance, coloured.variance
    main = coloured if w > 0.5 else white
    if not (a > 0 and b > 0 and 0.0 < w < 1.0):
        return main

    def mix(x: float, y: float) -> float:
        return float(x ** (1.0 - w) * y**w) if x > 0 and y > 0 else (1.0 - w) * x + w * y

    lo, hi = mixture_interval((white, coloured), (1.0 - w, w))
    core = main.core_variance
    if white.core_variance is not None and coloured.core_variance is not None:
        core = mix(white.core_variance, coloured.core_variance)
    span = ", ".join(f"{k}={v}" for k, v in coloured.params.items() if white.params.get(k) != v)
    note = (
        f"the noise is at the edge of white: R with {span} is {b / a:.3g} times R with the "
        f"method's own parameters; R weighs the two by the whiteness test ({w:.0%} the "
        "former), and its ci95 is that of their mixture"
    )
    return replace(
        main, variance=mix(a, b), ci95=(lo, hi), core_variance=core, notes=[*main.notes, note]
    )


def differenced(result: VarianceEstimate, d: NDArray, r: NDArray) -> VarianceEstimate:
    """``result`` for MA(q) noise of correlations ``r`` (lags 1..q) seen through the residual ``d``.

    Notes
    -----
    docs/algorithms.md §E2: ``E[e²] = σ² (Σd² + 2 Σ_j r_j Σ_i d_i d_{i+j})``, so an
    estimate normalised for white noise (``mean(e²) / Σd²``) is ``1 + 2 Σ_j r_j α_j``
    times σ², the variance per sample (``α_j`` the filter's autocorrelation at lag j).
    Differenced white noise (``r = (-1/2,)``) seen through a smoother's residual (``α₁``
    near -0.8) reads about 1.8 times too high without it; a central difference
    (``r = (0, -1/2)``) about 0.6 times.
    """
    r = np.atleast_1d(np.asarray(r, dtype=float))
    factor = 1.0 / (1.0 + 2.0 * float(r @ _lag_alpha(d, r.size)))
    if not (np.isfinite(factor) and factor > 0):
        return result
    core = None if result.core_variance is None else result.core_variance * factor
    lo, hi = result.ci95
    values = ", ".join([f"{x:+.2f}" for x in r[:4]] + ["..."] * (r.size > 4))  # AR(1): φ^k
    said = f"correlations {values} at lags 1-{r.size}" if r.size > 1 else ""
    said = said or f"lag-1 correlation {values}"
    notes = [
        *result.notes,
        f"the noise is correlated over short lags ({said}: differenced data, or AR(1) noise "
        f"of negative φ): the white-noise estimate was multiplied by "
        f"{factor:.3g}, the residual's response to such noise",
    ]
    return replace(
        result, variance=result.variance * factor, ci95=(lo * factor, hi * factor),
        core_variance=core, notes=notes,
    )  # fmt: skip


def _lag_alpha(d: NDArray, q: int) -> NDArray:
    """The filter ``d``'s autocorrelation at lags 1..q."""
    dd = float(np.dot(d, d))
    return np.array([np.dot(d[:-j], d[j:]) / dd if j < d.size else 0.0 for j in range(1, q + 1)])


def mixture_interval(
    ests: tuple[VarianceEstimate, ...], weights: tuple[float, ...]
) -> tuple[float, float]:
    """The 95 % interval of a mixture of the estimates' sampling distributions.

    Each estimate's ``log R`` is taken as a split normal through its ci95 (its own
    asymmetry kept: ``(log R - log lo) / 1.96`` below R, ``(log hi - log R) / 1.96`` above);
    the mixture's 2.5 % and 97.5 % quantiles are found by bisection in ``log R``
    (Bayesian model averaging: docs/algorithms.md §E1 *At the edge of white*).
    """
    r = np.log([e.variance for e in ests])
    lo = np.log([max(e.ci95[0], e.variance * 1e-12) for e in ests])
    hi = np.log([max(e.ci95[1], e.variance) for e in ests])
    below = np.maximum((r - lo) / Z95, 1e-12)
    above = np.maximum((hi - r) / Z95, 1e-12)
    wts = np.asarray(weights, float)

    def cdf(x: float) -> float:
        u = x - r
        return float(
            sum(
                w * norm_cdf(v)
                for w, v in zip(wts, np.where(u < 0, u / below, u / above), strict=True)
            )
        )

    def quantile(q: float) -> float:
        a, b = float(lo.min()), float(hi.max())
        for _ in range(60):
            m = 0.5 * (a + b)
            a, b = (m, b) if cdf(m) < q else (a, m)
        return float(np.exp(0.5 * (a + b)))

    return quantile(0.025), quantile(0.975)
