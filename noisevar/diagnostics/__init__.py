"""Diagnostics of a record's noise: whiteness, tails, quantisation, gaps, level along the record.

:func:`diagnose` looks at the record once, whatever the estimator; every
:class:`~noisevar.estimators.results.VarianceEstimate` carries the result at
``.diagnostics`` with a one-sentence verdict (docs/algorithms.md §E1-§E3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.glitches import Glitch, bridge_blocks, bridged, deviations, lone
from noisevar.diagnostics.notes import make_notes
from noisevar.diagnostics.plan import (
    DIAG_ORDER,
    DIAG_SPAN,
    PROFILE_MIN_KEPT,
    DiagPlan,
    make_plan,
    probe_of,
)
from noisevar.diagnostics.power_law import POWER_LAW_MAX, power_law_types, without_jumps
from noisevar.diagnostics.profile import (
    MOTION_RUN,
    LevelProfile,
    on_both_grids,
    profile_from_blocks,
)
from noisevar.diagnostics.results import NoiseDiagnostics
from noisevar.diagnostics.segments import Gap, Segmentation, split_dropped, split_times
from noisevar.diagnostics.sums import DiagSums, diag_part
from noisevar.diagnostics.tails import kurtosis_from_moments, tail_index
from noisevar.diagnostics.verdict import make_verdict
from noisevar.diagnostics.verdict_parts import other_still_clause
from noisevar.diagnostics.whiteness import WHITE_LAGS, WhitenessTest, whiteness_test
from noisevar.errors import NoisevarError
from noisevar.numeric.blocks import runs_of
from noisevar.numeric.fir import residual_sequence

__all__ = [
    "Gap",
    "Glitch",
    "LevelProfile",
    "NoiseDiagnostics",
    "Segmentation",
    "WhitenessTest",
    "diagnose",
    "from_sums",
    "glitches_apart",
    "lone_apart",
    "on_both_grids",
    "profile_from_sums",
    "profile_of",
    "split_dropped",
    "split_times",
    "with_verdict",
]


#: Residuals the whiteness test of the still stretches needs at least.
STILL_WHITE_MIN = 400
#: Glitches are left out of the correlation findings while they are at most this share of
#: the samples: a few each dominate the sample autocorrelation; many are the noise's tails
#: (a hand-held IMU: 1.6 %), which the tests must see, and whose set moves with the block
#: grid (reversed, 44 against 40: the verdict's colour flipped).
GLITCHES_APART = 1e-3


def glitches_apart(count: int, n: int) -> bool:
    """Whether ``count`` outlying samples of ``n`` are few enough to leave out of the
    correlation findings: at most :data:`GLITCHES_APART` of the samples, or one (a start-up
    value in a record of 600 samples made a coloured record read as a random walk)."""
    return 0 < count <= max(1.0, GLITCHES_APART * n)


def lone_apart(glitches: NDArray | None, n: int) -> NDArray | None:
    """The lone glitches of ``glitches`` (:func:`~.glitches.lone`) when few enough to leave
    out of the correlation findings (:func:`glitches_apart`), else None.

    Beside a burst the outlying samples are too many to leave out, yet a lone one still
    holds the sample autocorrelation: MIDC's accumulated irradiance opens with the day
    before's total, one increment of 99.99 % of the increments' sum of squares, and read
    as a random walk (increments' autocorrelation 0.001, p = 1; 0.99 without it).
    """
    if glitches is None:
        return None
    one = lone(glitches)
    return one if glitches_apart(one.size, n) else None


def diagnose(
    z: NDArray,
    segmentation: Segmentation | None = None,
    exclude: NDArray | None = None,
    glitches: NDArray | None = None,
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
    glitches : ndarray of int, optional
        Outlying samples (the estimator's, one per spike): left out of the correlation
        findings, and the lone ones bridged in the level profile (see :func:`from_sums`).

    Returns
    -------
    NoiseDiagnostics
        Its verdict speaks of the record's own level until :func:`with_verdict` gives
        it an estimate.
    """
    seg = segmentation or Segmentation(((0, z.size),), ())
    plan = make_plan(z.size, seg.segments, probe_of(z.__getitem__, z.size))
    sums = DiagSums(plan)
    for i, (a, b) in enumerate(seg.segments):
        sums.add(diag_part(z[a:b], a, (a, b), i, plan, None if exclude is None else exclude[a:b]))
    a, b = max(seg.segments, key=lambda s: s[1] - s[0])
    head = lambda: z[a : min(b, a + POWER_LAW_MAX)]  # noqa: E731
    jumps = None if exclude is None else runs_of(exclude)
    return from_sums(sums, seg, head, glitches=glitches, read=lambda p, q: z[p:q], jumps=jumps)


def from_sums(
    sums: DiagSums,
    seg: Segmentation,
    head: Callable[[], NDArray],
    spawn: Callable[[Callable[[], Any]], Callable[[], Any]] | None = None,
    glitches: NDArray | None = None,
    read: Callable[[int, int], NDArray] | None = None,
    jumps: list[tuple[int, int]] | None = None,
) -> NoiseDiagnostics:
    """The diagnostics from their sums; ``head()`` gives the start of the longest segment.

    ``jumps``: the runs of samples left out around level jumps (record indices), cut out of
    ``head()`` for the power-law identification (:func:`~.power_law.without_jumps`).

    ``glitches`` (record indices of outlying samples, one per spike), when at most
    :data:`GLITCHES_APART` of the samples, are left out of the correlation findings: the
    residual's and the increments' whiteness tests (whose samples within reach of one are
    not kept) and the power-law identification (on ``head()`` with each bridged). One
    glitch dominates a sample autocorrelation: inside the record its residual's shape made
    coloured noise read white, and its two increments a random walk read as measurable
    noise; at the first sample its one increment did neither (issue 26). The tails keep
    them: they are noise, and in R. Beside a burst (more outlying samples than that), the
    lone ones alone are left out when as few (:func:`lone_apart`): a burst of motion
    elsewhere does not make a start-up value part of the noise's correlation. The level
    profile reads the blocks within reach of a
    lone one (:func:`~noisevar.diagnostics.glitches.lone`) with it bridged, when
    ``read(a, b)`` gives samples ``a .. b`` (the sums are then changed in place, and the
    reversed grid's in ``sums.back`` too): one sample is never a regime of its own
    (:mod:`noisevar.diagnostics.glitches`). They are listed in ``.glitches``.

    ``spawn(f)`` starts ``f`` in another thread and returns what waits for its result:
    the power-law identification (numpy, which releases the interpreter) then runs
    beside the level profile (default: one after the other; the same numbers).

    A record in memory is summed by :func:`diagnose`; a record read in chunks adds each
    chunk's :func:`~noisevar.diagnostics.sums.diag_part` to a
    :class:`~noisevar.diagnostics.sums.DiagSums` laid on
    :func:`~noisevar.diagnostics.plan.make_plan`'s grid, then calls this.

    Notes
    -----
    docs/algorithms.md §E1-§E3: the kurtosis is taken on residuals over their block's
    robust level (spikes stay in it, level changes do not); the whiteness test's null
    covariance is widened by ``n Σσ⁴ / (Σσ²)²`` for a level that changes along the record.
    """
    plan, d = sums.plan, residual_sequence(DIAG_SPAN, DIAG_ORDER)
    e_w, keep_w = sums.white.joined()
    dz, used = sums.incr.joined()
    apart = glitches is not None and glitches_apart(glitches.size, plan.n)
    lone_ones = lone(glitches) if apart and read is not None else np.zeros(0, dtype=int)
    out = glitches if apart else lone_apart(glitches, plan.n)
    if out is not None and out.size:
        keep_w, used, head = _without_glitches(sums, keep_w, used, head, seg, out)
    if lone_ones.size and read is not None:
        _bridge(sums, lone_ones, read)

    # the increments' test and the tails (numpy, which releases the interpreter) beside
    # the whiteness test and the level profile (PELT: Python); the same numbers
    # the increments' null widened as the residual's: a walk whose steps change in size
    # (by day and by night) has white increments of a level that changes
    hetero = _hetero(sums.wide)

    def beside() -> tuple[WhitenessTest, float]:
        inc = whiteness_test(dz, np.ones(1), keep=used, inflation=hetero)
        return inc, tail_index(e_w[keep_w])

    aside = spawn(beside) if spawn is not None else beside
    white = whiteness_test(e_w, d, keep=keep_w, inflation=hetero)

    def kinds() -> tuple[tuple[int, int], ...]:
        a0 = max(seg.segments, key=lambda s: s[1] - s[0])[0]
        cut = [(a - a0, b - a0) for a, b in jumps or ()]
        try:
            return power_law_types(without_jumps(np.asarray(head()), cut))
        except NoisevarError:
            return ()

    # say which coloured noise (costly: only when it is coloured)
    types = (lambda: ()) if white.white else (spawn or _now)(kinds)
    # second differences on a grid: the samples sit on one that moves linearly (a trend)
    lsb = sums.held_step(sums.lsb())
    profile, blocks, total, kept, kurt = _profile(sums, lsb)
    still_white = _still_whiteness(plan, profile, e_w, keep_w, sums, d, blocks)
    still_incr = _still_increments(profile, dz, used, sums.incr.joined_slots())
    increments, tails = aside()
    diag = NoiseDiagnostics(
        n=plan.n,
        whiteness=white,
        increments=increments,
        kurtosis=kurt,
        tail_index=tails,
        lsb=lsb,
        gaps=seg.gaps,
        jitter=seg.jitter,
        level_profile=profile,
        power_law=types(),
        still_whiteness=still_white,
        still_increments=still_incr,
        glitches=_sized(lone_ones, read, plan.n, profile),
        core_kurtosis=_bridged_kurtosis(sums, d) if lone_ones.size else kurt,
    )
    return with_verdict(diag, float(total.sum() / kept))


def _bridged_kurtosis(sums: DiagSums, d: NDArray) -> float:
    """The noise kurtosis of the profile's residuals on one scale, lone glitches bridged.

    One scale for the record (``Σ e²`` and ``Σ e⁴`` from each block's ``Σ e²/L`` and
    ``Σ e⁴/L²``): each block's own robust level ``L``, the median of a few squares, is
    noisy enough to raise a kurtosis taken over it (white noise: 3.55, up to 4.2). Used
    for a record of one level only (the glitch verdict), where one scale is right.
    """
    kept = np.array([v for v in sums.profile.values() if v[0] >= PROFILE_MIN_KEPT])
    count, level, k2, k4 = kept[:, 0], kept[:, 2], kept[:, 4], kept[:, 5]
    top = float(np.max(level, initial=0.0))
    if not (np.isfinite(top) and top > 0):
        return 3.0
    w = level / top
    with np.errstate(over="ignore", invalid="ignore"):
        m2, m4 = np.sum(k2 * w) / count.sum(), np.sum(k4 * w * w) / count.sum()
    return kurtosis_from_moments(m2, m4, d)


def _bridge(sums: DiagSums, glitches: NDArray, read: Callable[[int, int], NDArray]) -> None:
    """:func:`~noisevar.diagnostics.glitches.bridge_blocks` on the sums and the reversed
    grid's (``sums.back``, read backwards)."""
    bridge_blocks(sums, glitches, read)
    if sums.back is not None:
        n = sums.plan.n
        back = sums.back
        bridge_blocks(back, np.sort(n - 1 - glitches), lambda a, b: read(n - b, n - a)[::-1])


def _sized(
    glitches: NDArray, read: Callable[[int, int], NDArray] | None, n: int, prof: LevelProfile
) -> tuple[Glitch, ...]:
    """The lone glitches with their size over the quiet level's standard deviation."""
    if read is None or glitches.size == 0:
        return ()
    level = prof.quiet_variance if prof.quiet.any() else prof.pooled_level
    if not (np.isfinite(level) and level > 0):
        return ()
    dev = deviations(glitches, read, n) / np.sqrt(level)
    return tuple(
        Glitch(int(g), float(s)) for g, s in zip(glitches, dev, strict=True) if np.isfinite(s)
    )


def _now(f: Callable[[], Any]) -> Callable[[], Any]:
    """``f`` run now, its result returned by what is returned (``from_sums``'s ``spawn``)."""
    out = f()
    return lambda: out


def profile_of(
    z: NDArray,
    segmentation: Segmentation,
    exclude: NDArray | None = None,
    glitches: NDArray | None = None,
    lsb: float | None = None,
    block: int | None = None,
) -> LevelProfile:
    """The level profile of :func:`diagnose` alone (the same numbers, none of the rest).

    For the reversed record's block grid (the still stretches on both grids,
    :func:`on_both_grids`): no whiteness test, increments, quantisation or power law.
    ``glitches``: lone glitches (``NoiseDiagnostics.glitches``' indices), bridged;
    ``lsb``: the record's grid step (``NoiseDiagnostics.lsb``), for its regimes;
    ``block``: the profile's block size (default: the record's own).
    """
    plan = make_plan(z.size, segmentation.segments, np.zeros(0), block)
    sums = DiagSums(plan)
    for i, (a, b) in enumerate(segmentation.segments):
        x = None if exclude is None else exclude[a:b]
        sums.add(diag_part(z[a:b], a, (a, b), i, plan, x, profile_only=True))
    if glitches is not None and glitches.size:
        bridge_blocks(sums, np.sort(glitches), lambda p, q: z[p:q])
    return profile_from_sums(sums, lsb)


def profile_from_sums(sums: DiagSums, lsb: float | None = None) -> LevelProfile:
    """The level profile of :func:`from_sums` alone (sums made with ``profile_only``);
    ``lsb`` the record's grid step (``NoiseDiagnostics.lsb``)."""
    return _profile(sums, lsb)[0]


def _profile(
    sums: DiagSums, lsb: float | None
) -> tuple[LevelProfile, list[int], NDArray, float, float]:
    """The level profile, its blocks, their sums of squares, the kept count, the kurtosis
    (regimes held on the grid of step ``lsb`` are one still level)."""
    sums.check()
    plan, d = sums.plan, residual_sequence(DIAG_SPAN, DIAG_ORDER)
    # blocks left with a handful of residuals (around jumps) say nothing of the level
    blocks = sorted(b for b, v in sums.profile.items() if v[0] >= PROFILE_MIN_KEPT)
    count, total, robust, medians, k2, k4 = (
        np.array([sums.profile[b][i] for b in blocks], dtype=float) for i in range(6)
    )
    kept = float(count.sum())
    # a held block (level 0: its residuals are 0, not float rounding) adds nothing to the
    # tails' sums and has no noise to count in them (issue 26)
    live = float(count[robust > 0].sum()) or kept
    kurt = kurtosis_from_moments(sums.k2 / live, sums.k4 / live, d)
    eta = float(np.sum(white_null_acf_sq(d)))
    starts = np.array(blocks) * plan.profile.size
    stops = plan.profile.stop(np.array(blocks))
    # ν per sample = 1 / (η + (κ - 3) / 2)   (docs/algorithms.md §E1)
    profile = profile_from_blocks(
        _sample_of(plan, starts), _sample_of(plan, stops - 1) + 1, count, total / count,
        robust, 1.0 / (eta + max(kurt - 3.0, 0.0) / 2.0), eta, medians, (k2, k4, d), lsb,
    )  # fmt: skip
    profile = replace(profile, unmeasured=_unmeasured(sums))
    return profile, blocks, total, kept, kurt


def _unmeasured(sums: DiagSums) -> tuple[tuple[int, int], ...]:
    """Sample ranges of runs of :data:`~.profile.MOTION_RUN` profile blocks or more that keep
    fewer than :data:`~.plan.PROFILE_MIN_KEPT` residuals each (``LevelProfile.unmeasured``).

    A vehicle that drives, then parks: its drive is all level jumps to the jump detector,
    every residual there is left out, and the profile saw the parked part alone, one still
    level, while R held the drive (3.9x the parked level, "white Gaussian noise").
    """
    plan = sums.plan
    thin = np.ones(plan.profile.count, dtype=bool)
    thin[[b for b, v in sums.profile.items() if v[0] >= PROFILE_MIN_KEPT]] = False
    out = []
    for a, b in runs_of(thin):
        if b - a >= MOTION_RUN:
            ends = np.array([a * plan.profile.size, plan.profile.end(b - 1) - 1])
            first, last = _sample_of(plan, ends)
            out.append((int(first), int(last) + 1))
    return tuple(out)


def _without_glitches(
    sums: DiagSums,
    keep_w: NDArray,
    used: NDArray,
    head: Callable[[], NDArray],
    seg: Segmentation,
    glitches: NDArray,
) -> tuple[NDArray, NDArray, Callable[[], NDArray]]:
    """The whiteness windows' and increments' kept masks, and ``head``, without ``glitches``."""
    plan, g = sums.plan, np.unique(glitches)

    def residual_sample(pos: int) -> int | None:
        return int(_sample_of(plan, _residual_slots(plan, np.array([pos])))[0])

    d0 = np.cumsum([0] + [b - a - 1 + WHITE_LAGS for a, b in plan.segments])

    def increment_sample(pos: int) -> int | None:  # difference z[k+1] - z[k]
        for (a, b), s0 in zip(plan.segments, d0, strict=False):
            if s0 <= pos < s0 + b - a - 1:
                return int(pos - s0 + a)
        return None

    # a residual reaches h samples either way
    near = _reaching(sums.white.joined_runs(), residual_sample, g, -plan.h, plan.h)
    touch = _reaching(sums.incr.joined_runs(), increment_sample, g, 0, 1)
    a0 = max(seg.segments, key=lambda s: s[1] - s[0])[0]

    def calm() -> NDArray:
        x = np.asarray(head())
        return bridged(x, g[(g >= a0) & (g < a0 + x.size)] - a0)

    return keep_w & ~near, used & ~touch, calm


def _reaching(
    runs: list[tuple[int, int]],
    sample: Callable[[int], int | None],
    g: NDArray,
    lo: int,
    hi: int,
) -> NDArray:
    """Over the positions of ``runs`` (:meth:`~noisevar.diagnostics.plan.Windows.joined_runs`):
    whether one of the sorted samples ``g`` lies within ``k + lo .. k + hi`` of the sample ``k``.

    ``sample(position)``: the sample of a run's first position (None: none); the run's
    samples follow it one by one. Each glitch marks the positions it reaches, run by run.
    """
    edges = np.zeros(sum(size for _, size in runs) + 1, dtype=np.int64)
    at = 0
    for pos, size in runs:
        k0 = sample(pos) if pos >= 0 else None
        if k0 is not None:
            i = g[np.searchsorted(g, k0 + lo) : np.searchsorted(g, k0 + size - 1 + hi, "right")]
            np.add.at(edges, at + np.clip(i - hi - k0, 0, size), 1)
            np.add.at(edges, at + np.clip(i - lo - k0 + 1, 0, size), -1)
        at += size
    return np.cumsum(edges[:-1]) > 0


def _still_whiteness(
    plan: DiagPlan,
    profile: LevelProfile,
    e: NDArray,
    keep: NDArray,
    sums: DiagSums,
    d: NDArray,
    blocks: list[int],
) -> WhitenessTest | None:
    """The whiteness test on the quiet blocks alone, when the level varies.

    The evidence that orders the verdict: motion that leaks through the smoother makes
    a record non-white while its still stretches stay white. (Each whiteness-window
    position's profile block is found only then.)
    """
    if all(r.still for r in profile.regimes):
        return None
    quiet_ids = np.asarray(blocks)[profile.quiet]
    inside = keep & _in_blocks(plan, sums.white.joined_runs(), quiet_ids)
    if np.count_nonzero(inside) < STILL_WHITE_MIN:
        return None
    try:
        return whiteness_test(e, d, keep=inside)
    except NoisevarError:
        return None


def _still_increments(
    profile: LevelProfile, dz: NDArray, used: NDArray, slots: NDArray
) -> WhitenessTest | None:
    """The increments' whiteness test on the still stretches alone, when the level varies.

    ``slots``: each increment's sample (-1: an unused slot). Too few there: not tested.
    """
    if all(r.still for r in profile.regimes):
        return None
    inside = used & (slots >= 0)
    inside &= _in_ranges(slots, profile.still_stretches)
    try:
        return whiteness_test(dz, np.ones(1), keep=inside)
    except NoisevarError:
        return None


def _in_ranges(x: NDArray, ranges: list[tuple[int, int]]) -> NDArray:
    """Whether each of ``x`` lies in one of the sample ranges ``[a, b)``."""
    out = np.zeros(x.size, dtype=bool)
    for a, b in ranges:
        out |= (x >= a) & (x < b)
    return out


def _in_blocks(plan: DiagPlan, runs: list[tuple[int, int]], ids: NDArray) -> NDArray:
    """Whether each position of the joined whiteness windows lies in a profile block ``ids``.

    ``runs``: :meth:`~noisevar.diagnostics.plan.Windows.joined_runs`. The blocks of
    :func:`_residual_slots` (each position's residual slot over the block size), read run by
    run: a run's slots follow one by one, and its residual slots too between the segments'
    starts (integers: the same positions, no array of slots).
    """
    out = np.zeros(sum(size for _, size in runs), dtype=bool)
    firsts = np.array([s for s in plan.slot0 if s is not None], dtype=int)
    if firsts.size == 0 or ids.size == 0:
        return out
    starts = firsts + WHITE_LAGS * np.arange(firsts.size)
    wanted, size, at = {int(b) for b in ids}, plan.profile.size, 0
    for lo, n in runs:
        cuts = [lo, *(int(s) for s in starts if lo < s < lo + n), lo + n] if lo >= 0 else []
        for p, q in zip(cuts, cuts[1:], strict=False):  # one segment's rank each
            r0 = p - WHITE_LAGS * max(int(np.searchsorted(starts, p, side="right")) - 1, 0)
            for b in wanted.intersection(range(r0 // size, (r0 + q - p - 1) // size + 1)):
                a, z = max(b * size, r0), min((b + 1) * size, r0 + q - p)
                out[at + p - lo + a - r0 : at + p - lo + z - r0] = True
        at += n
    return out


def _residual_slots(plan: DiagPlan, white: NDArray) -> NDArray:
    """The residual slot of each whiteness-window position (-1 stays -1).

    Segment ``k`` (in order, of those diagnosed) lays its windows ``k * WHITE_LAGS`` after
    its residual slots, so that no lag crosses from one segment into the next.
    """
    firsts = np.array([s for s in plan.slot0 if s is not None], dtype=int)
    if firsts.size == 0:
        return np.full(white.size, -1)
    starts = firsts + WHITE_LAGS * np.arange(firsts.size)
    rank = np.maximum(np.searchsorted(starts, white, side="right") - 1, 0)
    return np.where(white >= 0, white - WHITE_LAGS * rank, -1)


def _sample_of(plan: DiagPlan, slots: NDArray) -> NDArray:
    """The record index of residual slots (each segment's slots start at its ``a + h``)."""
    out = np.empty(slots.size, dtype=int)
    firsts = [(s, a) for s, (a, _) in zip(plan.slot0, plan.segments, strict=True) if s is not None]
    starts = np.array([s for s, _ in firsts])
    which = np.searchsorted(starts, slots, side="right") - 1
    out[:] = slots - starts[which] + np.array([a for _, a in firsts])[which] + plan.h
    return out


def _hetero(wide: dict[int, tuple[int, float]]) -> float:
    """``n Σσ⁴ / (Σσ²)²`` over the kept residuals, from their blocks' levels."""
    count = np.array([c for c, _ in wide.values()], dtype=float)
    level = np.array([v for _, v in wide.values()])
    top = float(level.max()) if level.size else 0.0
    if not top > 0:
        return 1.0
    x = level / top  # levels over their largest: no overflow near the float limit
    n = count.sum()
    return float((count @ x**2 / n) / (count @ x / n) ** 2)


def white_null_acf_sq(d: NDArray) -> NDArray:
    """``ρ_d(m)²`` for every lag: their sum is the sequence's ``η`` (docs/algorithms.md §F1)."""
    r = np.correlate(d, d, mode="full") / np.dot(d, d)
    return r**2


def with_verdict(
    diag: NoiseDiagnostics,
    variance: float,
    core: float | None = None,
    outliers: float = 0.0,
    still: float | None = None,
    still_gap: str | None = None,
) -> NoiseDiagnostics:
    """``diag`` with its verdict and notes written for an estimate of ``variance``.

    ``still``: the same method's estimate on the still regimes alone, when there is one;
    ``still_gap``: why there is none (:func:`make_verdict`).
    """
    verdict = make_verdict(diag, variance, core, outliers, still, still_gap)
    verdict += other_still_clause(diag)
    return replace(diag, verdict=verdict, notes=make_notes(diag))
