"""``auto`` and the diagnostics over a record read in chunks (docs/algorithms.md §F5.7).

``auto`` is local: a block's numbers depend on the samples within a few blocks of it.
Each chunk is estimated from a window that adds :data:`OVERLAP` samples either side,
and only the chunk's own blocks are kept (:func:`noisevar.estimators.auto.auto_part`);
their sums give the one-pass estimate. The diagnostics add each chunk's share to sums
laid on a grid fixed before the pass (:mod:`noisevar.diagnostics.sums`). Chunks run
in threads (the compiled filters release the GIL) and are added in record order.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import Segmentation, from_sums
from noisevar.diagnostics.plan import make_plan, probe_of
from noisevar.diagnostics.power_law import POWER_LAW_MAX
from noisevar.diagnostics.sums import DiagPart, DiagSums, diag_part
from noisevar.errors import NoisevarError
from noisevar.estimators._record import COLOURED_P, coloured_note, conclude
from noisevar.estimators._scale import SAFE_RANGE, check_answer, unscale
from noisevar.estimators._trim import AUTO_BLOCK
from noisevar.estimators.auto import AUTO, AUTO_COLOURED_SPAN, AutoPart, auto_part, auto_reduce
from noisevar.estimators.auto import auto_spans as _spans
from noisevar.estimators.params import AUTO_ORDER, AUTO_TRIM
from noisevar.estimators.results import VarianceEstimate
from noisevar.numeric.steps import STEP_MAX_FRACTION

#: Samples added on each side of a chunk: far beyond what one block's numbers depend on
#: (the longest span's reach, the jump detector's windows, neighbouring blocks).
OVERLAP = 8 * AUTO_BLOCK
#: Samples per chunk (a multiple of the block): about 25 MB of work arrays per thread.
CHUNK = 1 << 18
#: Chunks in flight per thread (bounded memory: results are added in order).
AHEAD = 2
#: The interpreter's thread switch interval (s) while chunks run in threads.
SWITCH = 2e-4


@dataclass(frozen=True)
class _Chunk:
    lo: int
    hi: int
    wa: int
    wb: int


def chunks(n: int, size: int = CHUNK) -> list[_Chunk]:
    """The chunks of a record of ``n`` samples on ``auto``'s block grid, with their windows."""
    if size % AUTO_BLOCK or size < 2 * AUTO_BLOCK:
        raise NoisevarError(f"chunk must be a multiple of {AUTO_BLOCK} of at least two blocks")
    last = (n // AUTO_BLOCK - 1) * AUTO_BLOCK  # the last block takes the rest of the record
    out, lo = [], 0
    while lo < n:
        hi = n if lo + size > last else lo + size
        wb = n if hi + OVERLAP > last else hi + OVERLAP
        out.append(_Chunk(lo, hi, max(0, lo - OVERLAP), wb))
        lo = hi
    return out


@dataclass
class _Pass:
    """What one pass over the record returns."""

    parts: list[AutoPart]
    top: float  # largest |z|
    span: float  # max z - min z
    diag: DiagSums | None


def _in_order(work: Callable[[_Chunk], tuple], todo: list[_Chunk], workers: int) -> Iterator[tuple]:
    """``work(c)`` for every chunk, in order, at most ``AHEAD * workers`` in flight."""
    if workers <= 1:
        yield from (work(c) for c in todo)
        return
    # a thread back from a long compiled call waits for the interpreter lock at most this
    # long while the other runs Python: the chunks' short calls then overlap (restored after)
    interval = sys.getswitchinterval()
    sys.setswitchinterval(SWITCH)
    try:
        with ThreadPoolExecutor(workers) as pool:
            queue: list[Future] = []
            for c in todo:
                queue.append(pool.submit(work, c))
                if len(queue) >= AHEAD * workers:
                    yield queue.pop(0).result()
            for f in queue:
                yield f.result()
    finally:
        sys.setswitchinterval(interval)


# long: one pass, its per-chunk work and its in-order reduction kept together
def _pass(
    read: Callable[[int, int], NDArray],
    n: int,
    spans: tuple[int, ...],
    params: dict,
    e: int,
    sums: DiagSums | None,
    step_limit: float,
    size: int,
    workers: int,
) -> _Pass:
    order, trim = params["order"], params["trim"]

    def work(c: _Chunk) -> tuple[AutoPart | None, DiagPart | None, float, float, float]:
        z = read(c.wa, c.wb)
        lo_z, hi_z = float(z.min()), float(z.max())
        top = max(abs(lo_z), abs(hi_z))
        if e == 0 and _exponent(top) != 0 and top > 1.0:  # squares would overflow: rescale
            return None, None, top, lo_z, hi_z
        if e:
            z = np.ldexp(z, e)
        part = auto_part(z, spans, order, trim, (c.lo - c.wa, c.hi - c.wa), step_limit, c.wa)
        dpart = None
        if sums is not None:
            dpart = diag_part(z, c.wa, (c.lo, c.hi), 0, sums.plan, part.jumps)
        part.jumps = np.zeros(0, dtype=bool)  # not kept: a mask the record's size
        return part, dpart, top, lo_z, hi_z

    parts, top, lo_all, hi_all = [], 0.0, math.inf, -math.inf
    for part, dpart, t, lo_z, hi_z in _in_order(work, chunks(n, size), workers):
        if part is not None:
            parts.append(part)
        top, lo_all, hi_all = max(top, t), min(lo_all, lo_z), max(hi_all, hi_z)
        if sums is not None and dpart is not None:
            sums.add(dpart)
    return _Pass(parts, top, hi_all - lo_all, sums)


def _exponent(top: float) -> int:
    """:func:`noisevar.estimators._scale.scale_exponent` from the record's largest |z|."""
    if top == 0.0:
        return 0
    _, k = math.frexp(top)
    return 0 if SAFE_RANGE[0] <= k <= SAFE_RANGE[1] else -k


# long: the steps of estimate() for one record, each a pass or a check, in order
def estimate_chunked(
    read: Callable[[int, int], NDArray],
    n: int,
    *,
    span: int | None = None,
    order: int = AUTO_ORDER,
    trim: float = AUTO_TRIM,
    probe: Callable[[slice], NDArray] | None = None,
    chunk: int = CHUNK,
    workers: int = 2,
    note: str = "streamed",
) -> VarianceEstimate:
    """``noisevar.estimate(z)`` (method ``auto``) for a record read in chunks.

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b`` as finite float64 (a copy).
    n : int
        Samples in the record.
    span, order, trim : see :func:`noisevar.estimators.auto.auto_estimate`.
    probe : callable, optional
        ``probe(slice)`` returns a strided selection (default: through ``read``).
    chunk : int
        Samples per chunk (a multiple of 256).
    workers : int
        Threads.
    note : str
        How the record was read, for the first note ("streamed in chunks of ...").

    Returns
    -------
    VarianceEstimate
        The same numbers as the one-pass estimate, with its diagnostics; ``jumps`` is
        not kept.
    """
    params = AUTO.validate({"span": span, "order": order, "trim": trim})
    params = {"span": params.get("span"), "order": params["order"], "trim": params["trim"]}
    spans = _spans(params["span"], params["order"], params["trim"], n)
    get = probe or (lambda s: np.array([read(i, i + 1)[0] for i in range(*s.indices(n))]))
    grid = probe_of(get, n)
    e = 0
    for _ in range(2):  # a second pass only when the record needs scaling (exact)
        plan = make_plan(n, ((0, n),), np.ldexp(grid, e))
        run = _pass(read, n, spans, params, e, DiagSums(plan), math.inf, chunk, workers)
        if run.span == 0:
            raise NoisevarError("the signal is constant: there is no noise to estimate")
        if _exponent(run.top) == e:
            break
        e = _exponent(run.top)
    if sum(p.found for p in run.parts) > STEP_MAX_FRACTION * n:  # a fast signal, not jumps
        run = _pass(read, n, spans, params, e, DiagSums(plan), -1.0, chunk, workers)
    result = auto_reduce(run.parts, spans, params, [f"{note} in chunks of {chunk} samples"])
    head = read(0, min(n, POWER_LAW_MAX))
    assert run.diag is not None
    diag = from_sums(run.diag, Segmentation(((0, n),), ()), lambda: np.ldexp(head, e))
    if diag.whiteness.p_value < COLOURED_P and params["span"] is None:
        extra = {"span": AUTO_COLOURED_SPAN}
        col = {**params, **extra}
        short = _spans(AUTO_COLOURED_SPAN, params["order"], params["trim"], n)
        again = _pass(read, n, short, col, e, None, math.inf, chunk, workers)
        result = auto_reduce(again.parts, (AUTO_COLOURED_SPAN,), col, result.notes[:1])
        result.notes.append(coloured_note(extra))
    result = conclude(AUTO, result, diag, lambda a, b: np.ldexp(read(a, b), e))
    unscale([result], e)
    check_answer(result)
    if e:
        from noisevar.estimators._record import rescale_diagnostics

        rescale_diagnostics(result, e)
    result.params = {"method": "auto", **result.params}
    return result
