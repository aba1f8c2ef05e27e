"""``auto``'s steps after the diagnostics run at once on the record's threads: the same numbers.

The coloured-noise pass and the still regimes' levels are independent branches
(:meth:`~noisevar.estimators.auto.ChunkedAuto.branches`), and the power-law
identification runs beside the level profile (``from_sums``'s ``spawn``). One thread
(one after the other) and two (at once) give every field to the last bit.
"""

from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

from noisevar import synth
from noisevar.estimators import estimate_chunked
from noisevar.estimators.auto import ChunkedAuto


def _flat(o):
    if dataclasses.is_dataclass(o):
        return {f.name: _flat(getattr(o, f.name)) for f in dataclasses.fields(o)}
    if isinstance(o, dict):
        return {k: _flat(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return type(o)(_flat(v) for v in o)
    if isinstance(o, np.ndarray):
        return (o.dtype.str, o.shape, o.tobytes())
    return o


def _motion(n: int, seed: int) -> np.ndarray:
    """White noise with bursts of a fast sinusoid (:func:`noisevar.synth.sine_bursts`)."""
    return synth.sine_bursts(n, rng=seed)


@pytest.mark.parametrize(("seed", "scale"), [(1, 1.0), (2, 3e-9)])
def test_branches_at_once_give_the_numbers_of_one_after_the_other(seed, scale):
    z = _motion(60_000, seed) * scale

    def read(a: int, b: int) -> np.ndarray:
        return z[max(a, 0) : b].copy()

    one, two = (
        estimate_chunked(read, z.size, probe=z.__getitem__, chunk=1 << 13, workers=w)
        for w in (1, 2)
    )
    # the case the branches are for: coloured-noise pass, still stretches, power law
    assert any("the noise is not white: estimated with span" in n for n in two.notes)
    assert two.still is not None and two.diagnostics.power_law
    assert _flat(one) == _flat(two)


def test_branches_keep_order_and_restore_the_threads():
    rec = ChunkedAuto(lambda a, b: np.zeros(b - a), 100, workers=2)
    interval = sys.getswitchinterval()
    seen = []

    def work(i):
        def f():
            seen.append(rec.workers)
            return i

        return f

    assert rec.branches(work(0), work(1)) == [0, 1]
    assert seen == [1, 1]  # two branches share the two threads
    assert rec.workers == 2 and sys.getswitchinterval() == interval
    rec.workers = 1
    assert rec.branches(work(2), work(3)) == [2, 3]  # one thread: one after the other
    with pytest.raises(ZeroDivisionError):
        rec.workers = 2
        rec.branches(work(4), lambda: 1 / 0)
    assert rec.workers == 2 and sys.getswitchinterval() == interval


def test_the_switch_interval_comes_back_whatever_order_the_users_leave_in():
    from noisevar.estimators.auto import chunked

    interval = sys.getswitchinterval()
    switch = chunked._FAST_SWITCH
    switch.__enter__()  # one estimate's pass starts ...
    assert sys.getswitchinterval() == pytest.approx(chunked.SWITCH)
    switch.__enter__()  # ... another's, in another thread
    switch.__exit__()  # the first leaves: the second still runs at the short interval
    assert sys.getswitchinterval() == pytest.approx(chunked.SWITCH)
    switch.__exit__()
    assert sys.getswitchinterval() == interval


def test_still_levels_are_measured_again_when_the_coloured_result_carries_other_params(
    monkeypatch,
):
    from noisevar.estimators import pipeline

    z = _motion(60_000, 3)
    coloured = pipeline._coloured
    seen = []

    def other(spec, record, result, params):
        again = coloured(spec, record, result, params)
        again.params = {**again.params, "trim": float(again.params["trim"]) + 0.5}
        return again

    def read(a: int, b: int) -> np.ndarray:
        return z[max(a, 0) : b].copy()

    still = pipeline._still

    def counted(spec, record, params, diag, *rest):
        seen.append(params["trim"])
        return still(spec, record, params, diag, *rest)

    monkeypatch.setattr(pipeline, "_coloured", other)
    monkeypatch.setattr(pipeline, "_still", counted)
    one, two = (
        estimate_chunked(read, z.size, probe=z.__getitem__, chunk=1 << 13, workers=w)
        for w in (1, 2)
    )
    trim = one.params["trim"]  # the carried one
    # each run: the still levels with the expected parameters, then again with the carried
    assert seen == [trim - 0.5, trim, trim - 0.5, trim]
    assert _flat(one) == _flat(two)
