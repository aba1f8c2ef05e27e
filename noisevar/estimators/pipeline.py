"""The one per-record pipeline: segments, the method, diagnostics, coloured noise, verdict.

:func:`run_record` is what every estimate goes through, a record in memory
(:class:`InMemory`: split at gaps, each uniform segment estimated and the segments
pooled) and a record read in chunks (the method's engine, ``spec.chunked``) alike:

1. run the method (``record.estimate``);
2. look at the noise once (``record.diagnose``: :func:`noisevar.diagnostics.diagnose`);
3. estimate again with ``spec.coloured_params`` when the noise is not white;
4. the method's finishing step (``spec.finish``);
5. conclude: the interval widened for the tails and correlation, a vibration's line taken
   out (``estimators.vibration``), the verdict, the assumptions (docs/algorithms.md §E1-§E3);
6. back to the record's units (it was scaled by an exact power of two).

What is special to a method is on its :class:`~noisevar.estimators.spec.MethodSpec`:
no method is named here.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import (
    NoiseDiagnostics,
    Segmentation,
    diagnose,
    on_both_grids,
    profile_of,
    split_dropped,
    split_times,
    with_verdict,
)
from noisevar.diagnostics.assumptions import check_assumptions
from noisevar.diagnostics.both_grids import regimes_on_both_grids
from noisevar.diagnostics.notes import still_caveat
from noisevar.diagnostics.profile import LevelProfile
from noisevar.diagnostics.regimes import QuietLevel, StillLevel
from noisevar.errors import NoisevarError
from noisevar.estimators._input import check_samples, check_times
from noisevar.estimators._scale import check_answer, held_but_for, refusing_held, unscale
from noisevar.estimators.differenced_interval import jackknife_interval
from noisevar.estimators.interval import (
    LoneGlitches,
    at_edge,
    differenced,
    edge_weight,
    glitches_within,
    honest_interval,
    listed_in_r,
    off_jumps,
    ranges_mask,
    record_glitches,
)
from noisevar.estimators.pooling import none_estimated, pool_segments
from noisevar.estimators.results import VarianceEstimate
from noisevar.estimators.spec import MethodSpec
from noisevar.estimators.still_levels import other_still_levels, own_tails
from noisevar.estimators.still_quiet import (
    above_record,
    held_digits,
    quiet_apart,
    quiet_level,
    rounding_floor,
    still_estimate,
)
from noisevar.estimators.still_set import STILL_MIN, has_still_apart, kept_still, still_gap
from noisevar.estimators.vibration import without_vibration
from noisevar.numeric.blocks import runs_of

#: The method's coloured-noise parameters are used below this whiteness p-value (far
#: below the flag's 5 %, so that white noise that fails the test by chance keeps the
#: efficient defaults).
COLOURED_P = 1e-4
#: A record in memory at least this long, in one uniform segment, goes through the
#: method's chunked engine when it has one (the same numbers, less memory, threads).
CHUNKED_MIN = 1 << 19

#: ``run(spec, z, notes, params)``: the method on one uniform finite segment.
Runner = Callable[[MethodSpec, NDArray, list[str], dict], VarianceEstimate]
#: ``jumps(z)``: the samples around level jumps of one segment, left out of the
#: diagnostics (None when none).
JumpMask = Callable[[NDArray], "NDArray | None"]


class Record(Protocol):
    """A record as the pipeline sees it (in memory, or a method's chunked engine).

    Attributes
    ----------
    exponent : int
        The samples the method sees are the record's times ``2**exponent``.
    """

    exponent: int

    def estimate(self, params: dict) -> VarianceEstimate:
        """The method's estimate of the record with ``params``."""
        ...

    def diagnose(self, result: VarianceEstimate) -> NoiseDiagnostics:
        """The record's diagnostics (``result``: the method's first estimate)."""
        ...

    def reader(self) -> Callable[[int, int], NDArray] | None:
        """Samples ``a .. b`` of a record in one uniform segment (None: several)."""
        ...


def _segmentation(raw: NDArray, t: NDArray | None, drop: bool) -> tuple[NDArray, Segmentation]:
    """The finite samples and their uniform segments (gaps from ``t`` and dropped samples)."""
    bad = ~np.isfinite(raw)
    if bad.any() and not drop:
        check_samples(raw, False)  # raises the one message for non-finite samples
    z = raw[~bad] if bad.any() else raw
    if t is not None:
        return z, split_times(check_times(t, raw.size)[~bad])
    if bad.any():
        return z, split_dropped(bad)
    return z, Segmentation(((0, z.size),), ())


def cut_out(ranges: list[tuple[int, int]], holes: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """``ranges`` less ``holes`` (both sorted, disjoint), pieces under :data:`STILL_MIN` dropped."""
    ends, out = [d for _, d in holes], []
    for a, b in ranges:
        i = bisect.bisect_right(ends, a)  # the first hole that ends after a
        while i < len(holes) and holes[i][0] < b:
            c, d = holes[i]
            if c > a:
                out.append((a, c))
            a = max(a, d)
            i += 1
        if b > a:
            out.append((a, b))
    return [(a, b) for a, b in out if b - a >= STILL_MIN]


def _by_segment(
    spec: MethodSpec, z: NDArray, seg: Segmentation, notes: list[str], params: dict, run: Runner
) -> VarianceEstimate:
    """Estimate each segment (too short ones are skipped) and pool."""
    if seg.segments == ((0, z.size),):
        return run(spec, z, notes, params)
    if len(seg.segments) == 1:
        a, b = seg.segments[0]
        return run(spec, check_samples(z[a:b])[0], notes, params)
    parts, starts, error, longest = [], [], None, 0
    for a, b in seg.segments:
        try:
            parts.append(run(spec, check_samples(z[a:b])[0], list(notes), params))
            starts.append(a)
        except NoisevarError as exc:
            error, longest = (exc, b - a) if b - a > longest else (error, longest)
    if not parts:  # the longest segment's reason: the one that says what is wrong
        raise none_estimated(error, z.size, len(seg.segments), longest)
    return pool_segments(parts, z.size, len(seg.segments) - len(parts), starts)


def _jumps(z: NDArray, seg: Segmentation, jump_mask: JumpMask) -> NDArray | None:
    """Samples around level jumps in each segment (left out of the diagnostics as signal)."""
    out = np.zeros(z.size, dtype=bool)
    for a, b in seg.segments:
        try:
            m = jump_mask(z[a:b])
        except NoisevarError:  # too short for the jump detector
            continue
        if m is not None:
            out[a:b] = m
    return out if out.any() else None


@dataclass
class InMemory:
    """A record in memory: its finite samples ``z`` in uniform segments ``seg``.

    ``run`` estimates one segment; the segments' estimates are pooled. ``jump_mask``
    finds the samples around level jumps that the diagnostics leave out (unless the
    method's own result carries them, ``result.jumps``).
    """

    spec: MethodSpec
    z: NDArray
    seg: Segmentation
    run: Runner
    jump_mask: JumpMask
    notes: list[str]
    exponent: int = 0

    def estimate(self, params: dict) -> VarianceEstimate:
        """Each segment through the method (too short ones skipped), pooled."""
        return _by_segment(self.spec, self.z, self.seg, list(self.notes), params, self.run)

    def diagnose(self, result: VarianceEstimate) -> NoiseDiagnostics:
        """:func:`noisevar.diagnostics.diagnose` of the record, its jumps left out."""
        own = result.jumps
        if own is None or own.size != self.z.size:
            jumps = _jumps(self.z, self.seg, self.jump_mask)
        else:  # the method's own mask, made over the whole record in one piece
            jumps = own if own.any() else None
        self.jump_runs = [] if jumps is None else runs_of(jumps)
        self.jumps = jumps
        return diagnose(self.z, self.seg, jumps, result.outliers)

    def back_profile(self, diag: NoiseDiagnostics) -> LevelProfile:
        """The level profile of the record reversed, the same samples left out around jumps
        (docs/algorithms.md §E1 Regimes): :func:`noisevar.diagnostics.profile_of`, once."""
        back = getattr(self, "_back", None)
        if back is None:
            n = self.z.size
            seg = Segmentation(tuple((n - b, n - a) for a, b in reversed(self.seg.segments)), ())
            jumps = getattr(self, "jumps", None)
            lone = np.array([n - 1 - g.index for g in diag.glitches], dtype=int)
            cut = None if jumps is None else jumps[::-1]
            back = profile_of(self.z[::-1], seg, cut, lone, diag.lsb)
            self._back = back
        return back

    def still_ranges(self, diag: NoiseDiagnostics) -> list[tuple[int, int]]:
        """The still stretches of ``diag`` that the reversed record's block grid finds still too."""
        back = self.back_profile(diag).still_stretches
        return on_both_grids(diag.level_profile.still_stretches, back, self.z.size)

    def estimate_in(self, params: dict, ranges: list[tuple[int, int]]) -> VarianceEstimate:
        """The method on the sample ranges ``ranges`` only, less the samples around jumps
        that the diagnostics left out, cut at the record's gaps, pooled."""
        cut = [
            (max(a, c), min(b, d))
            for a, b in cut_out(ranges, getattr(self, "jump_runs", []))
            for c, d in self.seg.segments
            if min(b, d) > max(a, c)
        ]
        seg = Segmentation(tuple(cut), ())
        return _by_segment(self.spec, self.z, seg, list(self.notes), params, self.run)

    def reader(self) -> Callable[[int, int], NDArray] | None:
        """Samples ``a .. b`` when the record is one uniform segment."""
        z = self.z
        return (lambda a, b: z[a:b]) if len(self.seg.segments) == 1 else None


def estimate_record(
    spec: MethodSpec,
    raw: NDArray,
    t: NDArray | None,
    drop: bool,
    params: dict,
    run: Runner,
    jump_mask: JumpMask,
    scaled: int = 0,
) -> VarianceEstimate:
    """One channel in memory through ``spec``: segments, pooled estimate, diagnostics, verdict.

    Parameters
    ----------
    spec : MethodSpec
    raw : ndarray, shape (n,)
        Samples as given (non-finite ones allowed with ``drop``), times ``2**scaled``.
    t : ndarray, shape (n,), optional
        Sample times.
    drop : bool
        Drop non-finite samples (each run of them is a gap).
    params : dict
        Validated method parameters (``None`` left out), in the scaled units.
    run : callable
        ``run(spec, z, notes, params)`` for one uniform finite segment.
    jump_mask : callable
        ``jump_mask(z)``: the samples around level jumps of one segment.
    scaled : int
        The exponent the samples were scaled by.

    Returns
    -------
    VarianceEstimate
        In the record's units. A long record in one segment goes through
        ``spec.chunked`` when the method has it (:data:`CHUNKED_MIN`).
    """
    z, seg = _segmentation(raw, t, drop)
    z, notes = check_samples(z)
    dropped = raw.size - z.size
    if dropped:
        notes.insert(0, f"dropped {dropped} non-finite samples")
    record: Record
    if spec.chunked is not None and len(seg.segments) == 1 and z.size >= CHUNKED_MIN:
        record = spec.chunked(
            lambda a, b: z[max(a, 0) : b], z.size, probe=z.__getitem__, note="estimated",
            notes=notes,
        )  # fmt: skip
    else:
        record = InMemory(spec, z, seg, run, jump_mask, notes)
    return refusing_held(run_record, z, scaled, spec.name)(spec, record, params, scaled=scaled)


def run_record(
    spec: MethodSpec,
    record: Record,
    params: dict,
    result: VarianceEstimate | None = None,
    scaled: int = 0,
) -> VarianceEstimate:
    """The pipeline: the method, diagnostics, coloured noise, finishing step, verdict, units.

    Parameters
    ----------
    spec : MethodSpec
    record : Record
    params : dict
        Validated method parameters (``None`` left out).
    result : VarianceEstimate, optional
        The method's estimate of the record, when it was made already (many channels
        at once).
    scaled : int
        The exponent the record was scaled by before ``record`` saw it (its own
        :attr:`~Record.exponent` is added).

    Returns
    -------
    VarianceEstimate
        In the record's units, with ``params["method"]``.
    """
    if result is None:
        result = record.estimate(params)
    try:
        diag = record.diagnose(result)
    except NoisevarError as exc:
        held_but_for(result)
        result.notes.append(f"no diagnostics: {exc}")
    else:
        diag = regimes_on_both_grids(diag, record)
        # differenced noise is corrected through the residual filter's own correlation
        # (conclude): a span chosen per block has none, so the fixed coloured-noise span
        extra = {}
        if diag.whiteness.p_value < COLOURED_P or diag.short_correlated:
            extra = _coloured_extra(spec, params)
        lone = record_glitches(record, result.outliers, diag)
        first = result
        result, still, diag = _after_diagnostics(spec, record, result, params, extra, diag, lone)
        lone = lone if result is first else record_glitches(record, result.outliers, diag)
        still, diag = kept_still(diag, result.variance, still)  # decided on R as quoted
        edge = _edge(spec, record, first, result, params, diag)
        gap = still_gap(diag, result.variance, still)  # the one rule (estimators.regimes)
        off = off_jumps(getattr(record, "jump_runs", []), diag.n)
        lone, diag = glitches_within(lone, off), listed_in_r(diag, off)
        result = conclude(spec, result, diag, record.reader(), still, gap, lone, edge)
    return _in_record_units(result, scaled + record.exponent, spec.name)


def _after_diagnostics(
    spec: MethodSpec,
    record: Record,
    result: VarianceEstimate,
    params: dict,
    extra: dict,
    diag: NoiseDiagnostics,
    lone: LoneGlitches | None = None,
) -> tuple[VarianceEstimate, VarianceEstimate | None, NoiseDiagnostics]:
    """The coloured-noise estimate (with ``extra``) and the still regimes' levels: two
    independent branches, run at once by a record that has ``branches`` (the still levels
    with the parameters the coloured result should carry: again if it carries others)."""
    own = result.params | extra | params

    def coloured() -> VarianceEstimate:
        return _coloured(spec, record, result, params) if extra else result

    def quiet(own: dict) -> tuple[VarianceEstimate | None, NoiseDiagnostics]:
        still, level = _still(spec, record, own, diag, result, lone)  # the first R: at once
        if still is None:
            return None, replace(diag, quiet=level)
        # its interval from the record's noise, with the lone glitches in the still stretches
        at = glitches_within(lone, ranges_mask(diag.level_profile.still_stretches, diag.n))
        still = rounding_floor(conclude(spec, still, diag.on_still, None, glitches=at), diag.lsb)
        still.diagnostics = None  # the diagnostics stay on the record's own result
        return still, replace(diag, other_still=_other_levels(spec, record, own, diag, still, lone))

    branches = getattr(record, "branches", None)
    if extra and branches is not None:
        again, (still, out) = branches(coloured, lambda: quiet(own))
        if repr(again.params | params) == repr(own):  # the same keys, order, types, values
            return again, still, out
    else:
        again = coloured()
    return again, *quiet(again.params | params)


def _still(
    spec: MethodSpec,
    record: Record,
    params: dict,
    diag: NoiseDiagnostics,
    first: VarianceEstimate,
    lone: LoneGlitches | None = None,
) -> tuple[VarianceEstimate | None, QuietLevel | None]:
    """The method on the still regimes' quiet stretches: the still R when apart
    (``has_still_apart``), else the quiet level measured apart when R is not it
    (:func:`~noisevar.estimators.still_quiet.quiet_apart`; docs/algorithms.md §E1)."""
    variance = first.variance
    if not has_still_apart(diag, variance):
        lone = glitches_within(lone, ranges_mask(diag.level_profile.still_stretches, diag.n))
        finish = partial(conclude, spec, diag=diag, glitches=lone)
        return None, quiet_apart(record, params, diag, variance, finish, first.core_variance)
    ranges, still = still_estimate(record, params, diag)
    held = held_digits(record, diag, still, ranges) or above_record(diag, still, first)
    return (None, held) if held is not None else (still, None)


def _other_levels(
    spec: MethodSpec,
    record: Record,
    params: dict,
    diag: NoiseDiagnostics,
    still: VarianceEstimate,
    lone: LoneGlitches | None = None,
) -> tuple[StillLevel, ...]:
    """The record's other still levels (:func:`.still_levels.other_still_levels`)."""
    kept = {k: v for k, v in params.items() if k != "method"}

    def measure(ranges: list[tuple[int, int]]) -> VarianceEstimate:
        est = record.estimate_in(kept, ranges)  # type: ignore[attr-defined]
        inside = glitches_within(lone, ranges_mask(ranges, diag.n))
        return conclude(spec, est, own_tails(diag, est), None, glitches=inside)

    return other_still_levels(diag, still, measure)


def _edge(
    spec: MethodSpec, record: Record, first: VarianceEstimate, result: VarianceEstimate,
    params: dict, diag: NoiseDiagnostics,
) -> tuple[VarianceEstimate, float] | None:  # fmt: skip
    """Near :data:`COLOURED_P` (:func:`~.interval.edge_weight`): the estimate the threshold
    did not choose and the coloured one's weight (docs/algorithms.md §E1 *At the edge of white*)."""
    w = edge_weight(diag.whiteness.p_value, COLOURED_P)
    if diag.short_correlated or not 0.0 < w < 1.0 or not _coloured_extra(spec, params):
        return None
    return (first, w) if result is not first else (_coloured(spec, record, first, params), w)


def _coloured(
    spec: MethodSpec, record: Record, result: VarianceEstimate, params: dict
) -> VarianceEstimate:
    """Estimate again with the method's parameters for coloured noise (unless the user chose)."""
    extra = _coloured_extra(spec, params)
    if not extra:
        return result
    again = record.estimate({**params, **extra})
    again.notes.append(coloured_note(extra))
    return again


def _coloured_extra(spec: MethodSpec, params: dict) -> dict:
    """The method's coloured-noise parameters the user did not set."""
    return {k: v for k, v in (spec.coloured_params or {}).items() if params.get(k) is None}


def _in_record_units(result: VarianceEstimate, e: int, method: str) -> VarianceEstimate:
    """``result``, made on the record times ``2**e``, in the record's units and checked."""
    unscale([result] if result.still is None else [result, result.still], e)
    check_answer(result)
    if e:
        rescale_diagnostics(result, e)
    result.params = {"method": method, **result.params}
    return result


def coloured_note(extra: dict) -> str:
    """What a result estimated again with the coloured-noise parameters ``extra`` says."""
    said = ", ".join(f"{k}={v}" for k, v in extra.items())
    return (
        f"the noise is not white: estimated with {said}, which lets the least of the "
        "coloured part in (the white part, or a little above it)"
    )


def conclude(
    spec: MethodSpec,
    result: VarianceEstimate,
    diag: NoiseDiagnostics,
    record: Callable[[int, int], NDArray] | None = None,
    still: VarianceEstimate | None = None,
    gap: str | None = None,
    glitches: LoneGlitches | None = None,
    edge: tuple[VarianceEstimate, float] | None = None,
) -> VarianceEstimate:
    """``result`` with the diagnostics ``diag``: honest interval, verdict, notes, assumptions.

    Parameters
    ----------
    spec : MethodSpec
        The method that made ``result``.
    result : VarianceEstimate
    diag : NoiseDiagnostics
        The record's diagnostics.
    record : callable, optional
        ``record(a, b)``: samples ``a .. b`` of the (one-segment) record (``spec.finish``).
    still : VarianceEstimate, optional
        The same method on the still regimes alone: kept as ``result.still`` and quoted
        by the verdict.
    gap : str, optional
        Why there is no ``still`` (:func:`~.still_set.still_gap`): its level is indicative only.
    glitches : LoneGlitches, optional
        The lone glitches in ``result``'s R (at the samples it was measured on): its
        interval allows for their Poisson count (:func:`~.interval.honest_interval`).
    edge : tuple, optional
        At the edge of white noise (:func:`_edge`): the other estimate and the coloured
        one's weight; R weighs the two, its interval their mixture's (:func:`~.interval.at_edge`).

    Returns
    -------
    VarianceEstimate
    """

    def own(result: VarianceEstimate) -> VarianceEstimate:
        if not (diag.short_correlated and spec.residual is not None):  # finish: its spread kept
            result = honest_interval(result, diag, glitches) if spec.moment else result
            result = result if spec.finish is None else spec.finish(result, diag, record)
            return without_vibration(result, record, diag, spec.residual)  # §E2 Vibration
        result = result if spec.finish is None else spec.finish(result, diag, record)
        d = spec.residual(result.params)
        result = differenced(result, d, diag.noise_correlation)
        result = honest_interval(result, diag, glitches) if spec.moment else result
        return jackknife_interval(result, record, diag, d)  # the correction's error in it

    result = own(result)
    if edge is not None:
        pair = (result, own(edge[0])) if edge[1] <= 0.5 else (own(edge[0]), result)
        result = at_edge(*pair, edge[1])
    if not diag.identifiable:  # no measurement noise can be told apart: 0 is as likely
        result = replace(result, ci95=(0.0, result.ci95[1]))
    quiet = None if still is None else still.variance
    diag = replace(diag, quiet=quiet_level(diag, result, still, gap))
    diag = with_verdict(
        diag, result.variance, result.core_variance, result.outlier_fraction, quiet, gap
    )
    result.still = still
    if still is not None and (bound := still_caveat(diag, still.n_used)) is not None:
        still.notes.append(bound)  # the still R users take says it too
    result.notes.extend(n for n in diag.notes if n not in result.notes)
    result.diagnostics = diag
    result.assumptions = check_assumptions(spec.assumes, diag)
    return result


def rescale_diagnostics(result: VarianceEstimate, e: int) -> None:
    """Diagnostics made on ``z * 2**e`` back in the record's units, verdict rewritten (in place).

    Parameters
    ----------
    result : VarianceEstimate
        Its variance, core and interval already in the record's units.
    e : int
        The exponent the record was scaled by.
    """
    diag = result.diagnostics
    if diag is None:
        return
    prof = diag.level_profile
    top = np.finfo(float).max

    def back(x: NDArray, power: int) -> NDArray:
        with np.errstate(over="ignore", under="ignore"):
            return np.minimum(np.ldexp(x, -power * e), top)  # a block may not fit: clip

    regimes = tuple(
        replace(
            r,
            variance=float(back(np.asarray(r.variance), 2)),
            lo=float(back(np.asarray(r.lo), 2)),
            hi=float(back(np.asarray(r.hi), 2)),
        )
        for r in prof.regimes
    )
    prof = replace(
        prof,
        variance=back(prof.variance, 2),
        lo=back(prof.lo, 2),
        hi=back(prof.hi, 2),
        regimes=regimes,
    )
    lsb = None if diag.lsb is None else float(back(np.asarray(diag.lsb), 1))
    old = set(diag.notes)
    quiet = (
        None if diag.quiet is None else diag.quiet.mapped(lambda v: float(back(np.asarray(v), 2)))
    )
    diag = replace(diag, level_profile=prof, lsb=lsb, quiet=quiet)
    diag = with_verdict(
        diag,
        result.variance,
        result.core_variance,
        result.outlier_fraction,
        None if result.still is None else result.still.variance,
        still_gap(diag, result.variance, result.still),
    )
    result.notes = [n for n in result.notes if n not in old] + list(diag.notes)
    result.diagnostics = diag
