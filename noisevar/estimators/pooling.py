"""Segments' estimates pooled into the record's: a record split at its gaps is one answer.

A record with gaps (or the still stretches of one) is estimated per uniform piece; the
pooled estimate carries what each piece found in record indices (its outlying samples,
their note) and the noise kurtosis its interval is widened for, as the record in one
piece does (docs/algorithms.md §E1, "Gaps").
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate, chi2_interval

_OUTLIER_NOTE = re.compile(
    r"^(\d+) outlying samples? \([^;]*; the first at sample (\d+)\): noise, so in the "
    r"variance; left out of core_variance$"
)


def outlier_note(k: int, n: int, first: int) -> str:
    """The note of ``k`` outlying samples counted in R, of ``n``, the first at ``first``."""
    return (
        f"{k} outlying sample{'s' if k > 1 else ''} ({k / n:.2%}; the first at sample "
        f"{first}): noise, so in the variance; left out of core_variance"
    )


def _outliers_said(notes: list[str]) -> tuple[list[str], tuple[int, int] | None]:
    """``notes`` without the :func:`outlier_note`, and its ``(k, first)`` (None: no such note)."""
    rest, said = [], None
    for note in notes:
        m = _OUTLIER_NOTE.match(note)
        if m is None:
            rest.append(note)
        else:
            said = (int(m.group(1)), int(m.group(2)))
    return rest, said


def _pooled_notes(parts: list[VarianceEstimate], n_total: int, starts: Sequence[int]) -> list[str]:
    """The first piece's notes, its outlier note replaced by the record's (record indices)."""
    notes, _ = _outliers_said(list(parts[0].notes))
    counts, firsts = 0, []
    for part, start in zip(parts, starts, strict=True):
        said = _outliers_said(list(part.notes))[1]
        if said is not None:
            counts += said[0]
            firsts.append(start + said[1])
    if firsts:
        notes.append(outlier_note(counts, n_total, min(firsts)))
    return notes


def _pooled_kurtosis(
    parts: list[VarianceEstimate], w: np.ndarray, v: np.ndarray, cores: list
) -> float | None:
    """The parts' noise kurtosis as the record's own: their moment sums added.

    Each part reads ``κ_s`` on squares scaled by its blocks' trimmed level (about its
    core variance ``c_s``), so its sums are ``Σe²/L = n_s r_s`` and ``Σe⁴/L² = n_s κ_s r_s²``
    with ``r_s = v_s / c_s``: ``κ = Σ w_s κ_s r_s² / (Σ w_s r_s)²`` (a glitch in one part
    weighs as in the record; a level that differs between parts is not a tail).
    """
    kurts = [p.kurtosis for p in parts]
    if None in kurts:
        return None
    if None in cores or not all(c > 0 for c in cores):
        return float(w @ np.array(kurts))
    r = v / np.array(cores)
    return float(w @ (np.array(kurts) * r**2) / (w @ r) ** 2)


def pool_segments(
    parts: list[VarianceEstimate],
    n_total: int,
    skipped: int,
    starts: Sequence[int] | None = None,
) -> VarianceEstimate:
    """Segments' estimates pooled with weights their samples (the record's mean level).

    Parameters
    ----------
    parts : list of VarianceEstimate
        One per estimated segment.
    n_total : int
        Samples of the record.
    skipped : int
        Segments too short to estimate.
    starts : sequence of int, optional
        Each part's first sample in the record: the parts' outlying samples and their
        note are then given in record indices (else the note is the first part's and
        there are no ``outliers``).

    Returns
    -------
    VarianceEstimate
    """
    w = np.array([p.n_used for p in parts], dtype=float)
    w /= w.sum()
    v = np.array([p.variance for p in parts])
    # var = Σ w_s v_s,  ν = var² / Σ w_s² v_s² / ν_s   (Satterthwaite)
    var = float(w @ v)
    dofs = np.array([p.dof for p in parts])
    spread = float(np.sum(w**2 * v**2 / dofs))
    # every part at 0 (held values): the parts' dof, not 0/0; the answer's check refuses it
    dof = float(var**2 / spread) if spread > 0 else float(np.sum(dofs))
    cores = [p.core_variance for p in parts]
    core = None if None in cores else float(w @ np.array(cores))
    outliers = float(np.sum([p.outlier_fraction * p.n_total for p in parts]) / n_total)
    kurt = _pooled_kurtosis(parts, w, v, cores)
    found = None
    if starts is not None and all(p.outliers is not None for p in parts):
        found = np.concatenate([p.outliers + s for p, s in zip(parts, starts, strict=True)])
    jumps = None if starts is None else _pooled_jumps(parts, n_total, starts)
    notes = list(parts[0].notes) if starts is None else _pooled_notes(parts, n_total, starts)
    k = len(parts)
    notes.append(f"estimated in {k} uniform segments and pooled" if k > 1 else
                 "estimated on 1 uniform segment")  # fmt: skip
    if skipped:
        notes.append(f"{skipped} segment{'s' * (skipped > 1)} too short to estimate left out")
    return VarianceEstimate(
        parts[0].method, var, chi2_interval(var, dof), int(sum(p.n_used for p in parts)),
        n_total, dof, dict(parts[0].params), notes, core_variance=core,
        outlier_fraction=outliers, kurtosis=kurt, outliers=found, jumps=jumps,
    )  # fmt: skip


def _pooled_jumps(
    parts: list[VarianceEstimate], n_total: int, starts: Sequence[int]
) -> NDArray | None:
    """The parts' samples left out around level jumps, in record indices (None: none)."""
    out = np.zeros(n_total, dtype=bool)
    for p, s in zip(parts, starts, strict=True):
        if p.jumps is not None:
            out[s : s + p.jumps.size] = p.jumps
    return out if out.any() else None


def none_estimated(error: Exception | None, n: int, segments: int, longest: int) -> NoisevarError:
    """The error when no uniform segment of a record split at its gaps could be estimated:
    ``error`` (the longest segment's) after how the record was split, so that its sample
    count reads as the segment's, not the record's.

    Parameters
    ----------
    error : Exception or None
        Why the longest segment could not be estimated.
    n, segments, longest : int
        The record's finite samples, its uniform segments and the longest one's samples.

    Returns
    -------
    NoisevarError

    Notes
    -----
    radvel's EPIC 203771098 (32 radial velocities, unevenly timed) read "the signal has only
    3 samples" of a record of 32 (benchmarks/real_audit21.py).
    """
    return NoisevarError(
        f"no uniform segment of the record could be estimated: its {n} samples split at "
        f"their gaps into {segments} uniform segments, the longest {longest} samples ({error}); "
        "to take it as one uniform record, set its times aside (a file without its time "
        "column; Python: estimate(z) without t; dashboard: another sample period)"
    )
