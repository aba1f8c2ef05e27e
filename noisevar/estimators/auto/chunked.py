"""``auto`` over a record read in chunks: its engine for the pipeline (docs/algorithms.md §F5.7).

``auto`` is local: a block's numbers depend on the samples within a few blocks of it.
Each chunk is estimated from a window that adds :data:`OVERLAP` samples either side,
and only the chunk's own blocks are kept (:func:`~noisevar.estimators.auto.core.auto_part`);
their sums give the one-pass estimate. The diagnostics add each chunk's share to sums
laid on a grid fixed before the pass (:mod:`noisevar.diagnostics.sums`). Chunks run in
threads (the compiled filters release the GIL) and are added in record order.
:class:`ChunkedAuto` is ``auto``'s ``spec.chunked``: the pipeline
(:func:`~noisevar.estimators.pipeline.run_record`) takes it through the steps of a
record in memory.
"""

from __future__ import annotations

import math
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import (
    LevelProfile,
    NoiseDiagnostics,
    Segmentation,
    from_sums,
    on_both_grids,
    profile_from_sums,
)
from noisevar.diagnostics.plan import make_plan, probe_of
from noisevar.diagnostics.power_law import POWER_LAW_MAX
from noisevar.diagnostics.sums import DiagPart, DiagSums, diag_part
from noisevar.errors import NoisevarError
from noisevar.estimators._scale import exponent_of, unscale
from noisevar.estimators.auto._trim import AUTO_BLOCK
from noisevar.estimators.auto.core import AutoPart, auto_part, auto_reduce, auto_spans
from noisevar.estimators.params import AUTO_ORDER, AUTO_TRIM
from noisevar.estimators.pipeline import cut_out
from noisevar.estimators.pooling import pool_segments
from noisevar.estimators.results import VarianceEstimate
from noisevar.numeric.blocks import runs_of

#: Samples added on each side of a chunk: far beyond what one block's numbers depend on
#: (the longest span's reach, the jump detector's windows, neighbouring blocks).
OVERLAP = 8 * AUTO_BLOCK
#: Samples per chunk (a multiple of the block): about 25 MB of work arrays per thread.
CHUNK = 1 << 18
#: Chunks in flight per thread (bounded memory: results are added in order).
AHEAD = 2
#: The interpreter's thread switch interval (s) while chunks run in threads.
SWITCH = 2e-4


class _Switch:
    """The interpreter's switch interval at :data:`SWITCH` while any user is inside.

    Counted, so that estimates in several threads at once (a dashboard's, nested passes)
    restore the interval the first one found, whatever order they leave in.
    """

    def __init__(self) -> None:
        self.lock, self.users, self.saved = threading.Lock(), 0, sys.getswitchinterval()

    def __enter__(self) -> None:
        with self.lock:
            if self.users == 0:
                self.saved = sys.getswitchinterval()
                sys.setswitchinterval(SWITCH)
            self.users += 1

    def __exit__(self, *exc: object) -> None:
        with self.lock:
            self.users -= 1
            if self.users == 0:
                sys.setswitchinterval(self.saved)


_FAST_SWITCH = _Switch()


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
    jump_runs: list[tuple[int, int]]  # samples left out around jumps, as ranges


def _in_order(work: Callable[[_Chunk], tuple], todo: list[_Chunk], workers: int) -> Iterator[tuple]:
    """``work(c)`` for every chunk, in order, at most ``AHEAD * workers`` in flight."""
    if workers <= 1:
        yield from (work(c) for c in todo)
        return
    # a thread back from a long compiled call waits for the interpreter lock at most this
    # long while the other runs Python: the chunks' short calls then overlap (restored after)
    with _FAST_SWITCH, ThreadPoolExecutor(workers) as pool:
        queue: list[Future] = []
        for c in todo:
            queue.append(pool.submit(work, c))
            if len(queue) >= AHEAD * workers:
                yield queue.pop(0).result()
        for f in queue:
            yield f.result()


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
    """One pass over the record: every chunk's block sums (and diagnostics), in order."""
    order, trim = params["order"], params["trim"]

    def work(c: _Chunk) -> tuple[AutoPart | None, DiagPart | None, float, float, float, list]:
        z = read(c.wa, c.wb)
        lo_z, hi_z = float(z.min()), float(z.max())
        top = max(abs(lo_z), abs(hi_z))
        if e == 0 and exponent_of(top) != 0 and top > 1.0:  # squares would overflow: rescale
            return None, None, top, lo_z, hi_z, []
        if e:
            z = np.ldexp(z, e)
        stretch = (c.lo - c.wa, c.hi - c.wa)
        part = auto_part(z, spans, order, trim, stretch, step_limit, c.wa, n - c.wb)
        dpart = None
        if sums is not None:
            back = sums.back is not None
            dpart = diag_part(z, c.wa, (c.lo, c.hi), 0, sums.plan, part.jumps, back=back)
        own = part.jumps[c.lo - c.wa : c.hi - c.wa]
        runs = runs_of(own, c.lo) if own.any() else []
        part.jumps = np.zeros(0, dtype=bool)  # not kept: a mask the record's size
        return part, dpart, top, lo_z, hi_z, runs

    parts, top, lo_all, hi_all, runs = [], 0.0, math.inf, -math.inf, []
    todo = chunks(n, size)  # one chunk: no thread to hand it to and wait for
    for part, dpart, t, lo_z, hi_z, more in _in_order(work, todo, min(workers, len(todo))):
        if part is not None:
            parts.append(part)
        runs = _join(runs, more)
        top, lo_all, hi_all = max(top, t), min(lo_all, lo_z), max(hi_all, hi_z)
        if sums is not None and dpart is not None:
            sums.add(dpart)
    return _Pass(parts, top, hi_all - lo_all, sums, runs)


def _spawn(f: Callable[[], Any]) -> Callable[[], Any]:
    """``f`` started in a thread of its own; what is returned waits for its result."""
    pool = ThreadPoolExecutor(1)
    future = pool.submit(f)
    pool.shutdown(wait=False)  # the thread ends with ``f``
    return future.result


def _join(runs: list[tuple[int, int]], more: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Runs of consecutive chunks, a run that crosses a chunk's end made one."""
    if runs and more and runs[-1][1] == more[0][0]:
        return [*runs[:-1], (runs[-1][0], more[0][1]), *more[1:]]
    return runs + more


def _config(params: dict) -> dict:
    """``auto``'s parameters in the config form: ``span`` None when chosen per block."""
    return {
        "span": params.get("span"),
        "order": params.get("order", AUTO_ORDER),
        "trim": params.get("trim", AUTO_TRIM),
    }


class ChunkedAuto:
    """``auto`` on a record read in chunks, as a :class:`~noisevar.estimators.pipeline.Record`.

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b`` as finite float64 (a copy).
    n : int
        Samples in the record.
    probe : callable, optional
        ``probe(slice)`` returns a strided selection (default: through ``read``).
    chunk : int, optional
        Samples per chunk (a multiple of 256; default :data:`CHUNK`).
    workers : int
        Threads.
    note : str
        How the record was read, for the first note ("streamed in chunks of ...").
    notes : sequence of str
        Remarks carried in front of it.
    diagnostics : bool
        Sum the diagnostics in the first pass (False: the estimate alone, for a part of
        a record whose diagnostics are the record's; :meth:`diagnose` then refuses).

    Notes
    -----
    The first :meth:`estimate` is one pass that also sums the diagnostics, and finds the
    power of two the record is scaled by (:attr:`exponent`; a second pass when it is not
    0); which jumps are believed is decided in each window (§F5.3), never for the whole
    record. Later estimates (coloured noise) are one pass each. ``jumps`` is not kept.
    """

    def __init__(
        self,
        read: Callable[[int, int], NDArray],
        n: int,
        *,
        probe: Callable[[slice], NDArray] | None = None,
        chunk: int | None = None,
        workers: int = 2,
        note: str = "streamed",
        notes: Sequence[str] = (),
        diagnostics: bool = True,
    ) -> None:
        self.read, self.n, self.workers = read, n, workers
        self.diagnostics, self.scaled = diagnostics, False
        self.probe = probe or (
            lambda s: np.array([read(i, i + 1)[0] for i in range(*s.indices(n))])
        )
        self.chunk = CHUNK if chunk is None else chunk
        self.notes = [*notes, f"{note} in chunks of {self.chunk} samples"]
        self.exponent = 0
        self.sums: DiagSums | None = None
        self.jump_runs: list[tuple[int, int]] = []

    def estimate(self, params: dict) -> VarianceEstimate:
        """``auto``'s estimate of the record with ``params`` (validated, None left out)."""
        p = _config(params)
        spans = auto_spans(p["span"], p["order"], p["trim"], self.n)
        if not self.scaled:
            run = self._first(spans, p)
        else:
            run = self._run(spans, p, None, math.inf)
        return auto_reduce(run.parts, spans, p, list(self.notes))

    def branches(self, *work: Callable[[], Any]) -> list[Any]:
        """``[w() for w in work]``, run at once on the record's threads (results in order).

        The pipeline's steps after the diagnostics are independent of each other (the
        coloured-noise pass, the still regimes'). The threads are shared: ``k`` branches
        at once, each reading in chunks with ``workers // k`` threads (never more than
        :attr:`workers` in all; one thread: one after the other).
        """
        k = min(len(work), self.workers)
        if k <= 1:
            return [w() for w in work]
        workers = self.workers
        self.workers = max(1, workers // k)
        try:  # Python-heavy steps (PELT) let the others' compiled calls run
            with _FAST_SWITCH, ThreadPoolExecutor(k - 1) as pool:
                rest = [pool.submit(w) for w in work[1:]]
                first = work[0]()
                return [first, *(f.result() for f in rest)]
        finally:
            self.workers = workers

    def estimate_in(self, params: dict, ranges: list[tuple[int, int]]) -> VarianceEstimate:
        """``auto`` on the sample ranges ``ranges`` only, each read in chunks, pooled.

        The same numbers as the record in memory (each range is a record of its own, at
        this record's scale; docs/algorithms.md §F5.7).
        """
        parts, starts, error = [], [], None
        ranges = cut_out(ranges, self.jump_runs)
        for a, b in ranges:
            sub = ChunkedAuto(
                lambda i, j, a=a: self.read(a + i, a + j), b - a, chunk=self.chunk,
                workers=self.workers, notes=self.notes[:-1], diagnostics=False,
            )  # fmt: skip
            try:
                part = sub.estimate(params)
            except NoisevarError as exc:
                error = error or exc
                continue
            unscale([part], sub.exponent - self.exponent)
            parts.append(part)
            starts.append(a)
        if not parts:
            raise NoisevarError(f"no range of the record could be estimated: {error}")
        if len(ranges) == 1:
            return parts[0]
        return pool_segments(parts, self.n, len(ranges) - len(parts), starts)

    def _run(self, spans: tuple[int, ...], p: dict, sums: DiagSums | None, limit: float) -> _Pass:
        e = self.exponent
        return _pass(self.read, self.n, spans, p, e, sums, limit, self.chunk, self.workers)

    def _first(self, spans: tuple[int, ...], p: dict) -> _Pass:
        """The first pass: estimate, diagnostic sums (when asked) and the record's scale."""
        grid = probe_of(self.probe, self.n) if self.diagnostics else None
        for _ in range(2):  # a second pass only when the record needs scaling (exact)
            sums = None
            if grid is not None:
                plan = make_plan(self.n, ((0, self.n),), np.ldexp(grid, self.exponent))
                sums = DiagSums(plan, back=True)  # the reversed grid's profile too
            run = self._run(spans, p, sums, math.inf)
            if run.span == 0:
                raise NoisevarError(
                    "the signal is constant: there is no noise to estimate: give a channel "
                    "that varies"
                )
            if exponent_of(run.top) == self.exponent:
                break
            self.exponent = exponent_of(run.top)
        self.sums, self.jump_runs, self.scaled = run.diag, run.jump_runs, True
        return run

    def diagnose(self, result: VarianceEstimate) -> NoiseDiagnostics:
        """The diagnostics summed by the first pass (``result``: its glitches, see from_sums)."""
        if not self.diagnostics:
            raise NoisevarError("this part of a record is estimated without diagnostics")
        if self.sums is None:
            raise NoisevarError("the record has not been estimated yet")
        head, e = self.read(0, min(self.n, POWER_LAW_MAX)), self.exponent
        seg = Segmentation(((0, self.n),), ())
        spawn = _spawn if self.workers > 1 else None  # the power law beside the profile
        calm = result.outliers  # the glitches, left out of the correlations
        scaled = lambda: np.ldexp(head, e) if e else head  # noqa: E731
        return from_sums(self.sums, seg, scaled, spawn, calm, self.reader(), self.jump_runs)

    def back_profile(self, diag: NoiseDiagnostics) -> LevelProfile:
        """As :meth:`~noisevar.estimators.pipeline.InMemory.back_profile`: the reversed
        record's level profile, its blocks summed by the first pass (the same residuals
        read backwards, :func:`~noisevar.diagnostics.sums.diag_part`'s ``back``): no pass."""
        if self.sums is None or self.sums.back is None:
            raise NoisevarError("the record has not been estimated yet")
        return profile_from_sums(self.sums.back, diag.lsb)

    def still_ranges(self, diag: NoiseDiagnostics) -> list[tuple[int, int]]:
        """As :meth:`~noisevar.estimators.pipeline.InMemory.still_ranges`."""
        rev = self.back_profile(diag)
        return on_both_grids(diag.level_profile.still_stretches, rev.still_stretches, self.n)

    def reader(self) -> Callable[[int, int], NDArray]:
        """``read`` at the record's scale, for the finishing step."""
        e = self.exponent
        return lambda a, b: np.ldexp(self.read(a, b), e)
