"""One record through an estimator: gaps and segments, diagnostics, an honest interval.

:func:`estimate_record` is what :func:`noisevar.estimate` does for each channel: split
the record at gaps (sample times, dropped samples), estimate each uniform segment and
pool them, look at the noise once (:func:`noisevar.diagnostics.diagnose`), widen the
interval of moment estimators for the measured tails and correlation, and write the
verdict (docs/algorithms.md §E1-§E3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import (
    NoiseDiagnostics,
    Segmentation,
    diagnose,
    split_dropped,
    split_times,
    with_verdict,
)
from noisevar.diagnostics.assumptions import check_assumptions
from noisevar.errors import NoisevarError
from noisevar.estimators._input import check_samples, check_times
from noisevar.estimators.results import VarianceEstimate, chi2_interval
from noisevar.estimators.spec import MethodSpec

#: The method's coloured-noise parameters are used below this whiteness p-value (far
#: below the flag's 5 %, so that white noise that fails the test by chance keeps the
#: efficient defaults).
COLOURED_P = 1e-4
#: ``auto`` estimates records at least this long in chunks (:mod:`noisevar.stream`).
CHUNKED_MIN = 1 << 19

Runner = Callable[[MethodSpec, NDArray, list[str], dict], VarianceEstimate]


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


def _pool(parts: list[VarianceEstimate], n_total: int, skipped: int) -> VarianceEstimate:
    """Segments' estimates pooled with weights their samples (the record's mean level)."""
    w = np.array([p.n_used for p in parts], dtype=float)
    w /= w.sum()
    v = np.array([p.variance for p in parts])
    # var = Σ w_s v_s,  ν = var² / Σ w_s² v_s² / ν_s   (Satterthwaite)
    var = float(w @ v)
    dof = float(var**2 / np.sum(w**2 * v**2 / np.array([p.dof for p in parts])))
    cores = [p.core_variance for p in parts]
    core = None if None in cores else float(w @ np.array(cores))
    outliers = float(np.sum([p.outlier_fraction * p.n_total for p in parts]) / n_total)
    notes = list(parts[0].notes)
    notes.append(f"estimated in {len(parts)} uniform segments and pooled")
    if skipped:
        notes.append(f"{skipped} segments too short to estimate were left out")
    return VarianceEstimate(
        parts[0].method, var, chi2_interval(var, dof), int(sum(p.n_used for p in parts)),
        n_total, dof, dict(parts[0].params), notes, core_variance=core,
        outlier_fraction=outliers,
    )  # fmt: skip


def _by_segment(
    spec: MethodSpec, z: NDArray, seg: Segmentation, notes: list[str], params: dict, run: Runner
) -> VarianceEstimate:
    """Estimate each segment (too short ones are skipped) and pool."""
    if len(seg.segments) == 1:
        return run(spec, z, notes, params)
    parts, error = [], None
    for a, b in seg.segments:
        try:
            parts.append(run(spec, check_samples(z[a:b])[0], list(notes), params))
        except NoisevarError as exc:
            error = error or exc
    if not parts:
        raise NoisevarError(f"no uniform segment of the record could be estimated: {error}")
    return _pool(parts, z.size, len(seg.segments) - len(parts))


def _jumps(z: NDArray, seg: Segmentation) -> NDArray | None:
    """Samples around level jumps in each segment (what ``auto`` leaves out as signal)."""
    from noisevar.estimators.auto import jump_mask

    out = np.zeros(z.size, dtype=bool)
    for a, b in seg.segments:
        try:
            m = jump_mask(z[a:b])
        except NoisevarError:  # too short for the jump detector
            continue
        if m is not None:
            out[a:b] = m
    return out if out.any() else None


def _honest_interval(r: VarianceEstimate, diag: NoiseDiagnostics) -> VarianceEstimate:
    """Widen a moment estimator's interval for the noise's kurtosis and correlation.

    ``ν = n / (η c + (κ - 3) / 2)`` with ``η = n / ν₀`` the method's own factor, ``κ``
    the noise kurtosis and ``c`` the excess of the residual's correlation over white
    noise's (1 when the noise passes the whiteness test) (docs/algorithms.md §E1).
    """
    if not (r.dof > 0 and r.n_used > 0):
        return r
    eta = r.n_used / r.dof
    w = diag.whiteness
    c = 1.0
    if not w.white:
        c = max(1.0, (1 + 2 * np.sum(w.acf**2)) / (1 + 2 * np.sum(w.expected**2)))
    excess = max(diag.kurtosis - 3.0, 0.0) / 2.0
    if c == 1.0 and excess == 0.0:
        return r
    dof = float(r.n_used / (eta * c + excess))
    return replace(r, dof=dof, ci95=chi2_interval(r.variance, dof))


def estimate_record(
    spec: MethodSpec, raw: NDArray, t: NDArray | None, drop: bool, params: dict, run: Runner
) -> VarianceEstimate:
    """One channel through ``spec``: segments, pooled estimate, diagnostics and verdict.

    Parameters
    ----------
    spec : MethodSpec
    raw : ndarray, shape (n,)
        Samples as given (non-finite ones allowed with ``drop``).
    t : ndarray, shape (n,), optional
        Sample times.
    drop : bool
        Drop non-finite samples (each run of them is a gap).
    params : dict
        Validated method parameters.
    run : callable
        ``run(spec, z, notes, params)`` for one uniform finite segment.

    Returns
    -------
    VarianceEstimate
    """
    z, seg = _segmentation(raw, t, drop)
    z, notes = check_samples(z)
    dropped = raw.size - z.size
    if dropped:
        notes.insert(0, f"dropped {dropped} non-finite samples")
    if spec.name == "auto" and len(seg.segments) == 1 and z.size >= CHUNKED_MIN:
        return _in_chunks(z, notes, params)
    result = _by_segment(spec, z, seg, notes, params, run)
    return attach_diagnostics(spec, result, z, seg, params, run)


def _in_chunks(z: NDArray, notes: list[str], params: dict) -> VarianceEstimate:
    """``auto`` on a long record in chunks and threads: the same numbers (§F5.7), less memory."""
    from noisevar.stream.chunked import estimate_chunked

    def read(a: int, b: int) -> NDArray:
        return z[max(a, 0) : b]

    result = estimate_chunked(read, z.size, probe=z.__getitem__, note="estimated", **params)
    result.notes[:0] = notes
    return result


def _coloured(
    spec: MethodSpec,
    result: VarianceEstimate,
    z: NDArray,
    seg: Segmentation,
    params: dict,
    run: Runner,
) -> VarianceEstimate:
    """Estimate again with the method's parameters for coloured noise (unless the user chose)."""
    extra = {k: v for k, v in (spec.coloured_params or {}).items() if params.get(k) is None}
    if not extra:
        return result
    again = _by_segment(spec, z, seg, [], {**params, **extra}, run)
    again.notes = [n for n in again.notes if "span chosen" not in n]
    again.notes.append(coloured_note(extra))
    return again


def attach_diagnostics(
    spec: MethodSpec,
    result: VarianceEstimate,
    z: NDArray,
    seg: Segmentation | None = None,
    params: dict | None = None,
    run: Runner | None = None,
) -> VarianceEstimate:
    """``result`` with the diagnostics of the record ``z``, its verdict and honest interval.

    Parameters
    ----------
    spec : MethodSpec
        The method that made ``result``.
    result : VarianceEstimate
    z : ndarray, shape (n,)
        The finite samples it was made from.
    seg : Segmentation, optional
        Their uniform segments (default: one).
    params, run : optional
        The method's parameters and runner, to estimate again with
        ``spec.coloured_params`` when the noise is not white (those the user gave win).

    Returns
    -------
    VarianceEstimate
    """
    seg = seg or Segmentation(((0, z.size),), ())
    try:
        # auto's own jump mask when it made the estimate over the whole record in one piece
        own = result.jumps if result.jumps is not None and result.jumps.size == z.size else None
        jumps = _jumps(z, seg) if own is None else (own if own.any() else None)
        diag = diagnose(z, seg, jumps)
    except NoisevarError as exc:
        result.notes.append(f"no diagnostics: {exc}")
        return result
    if run is not None and diag.whiteness.p_value < COLOURED_P and spec.coloured_params:
        result = _coloured(spec, result, z, seg, params or {}, run)
    record = (lambda a, b: z[a:b]) if len(seg.segments) == 1 else None
    return conclude(spec, result, diag, record)


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
        ``record(a, b)``: samples ``a .. b`` of the (one-segment) record, for the
        method's finishing step (``spec.finish``).

    Returns
    -------
    VarianceEstimate
    """
    if spec.finish is not None:
        result = spec.finish(result, diag, record)
    if spec.moment:
        result = _honest_interval(result, diag)
    if not diag.identifiable:  # no measurement noise can be told apart: 0 is as likely
        result = replace(result, ci95=(0.0, result.ci95[1]))
    diag = with_verdict(diag, result.variance, result.core_variance, result.outlier_fraction)
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

    prof = replace(prof, variance=back(prof.variance, 2), lo=back(prof.lo, 2), hi=back(prof.hi, 2))
    lsb = None if diag.lsb is None else float(back(np.asarray(diag.lsb), 1))
    old = set(diag.notes)
    diag = with_verdict(
        replace(diag, level_profile=prof, lsb=lsb),
        result.variance,
        result.core_variance,
        result.outlier_fraction,
    )
    result.notes = [n for n in result.notes if n not in old] + list(diag.notes)
    result.diagnostics = diag
