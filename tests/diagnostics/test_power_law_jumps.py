"""The power-law identification does not read level jumps as a random walk (issue 26).

Its samples were the record's head as it is: 20 steps in AR(1) noise of lag-one correlation
0.5 read "random walk at 1-64 samples" (without them "flicker at 1 sample, white at 4-64"),
and white noise with 20 steps of 30 σ "coloured: flicker at 1 sample, random walk at 4-64".
The runs left out around jumps are now cut out of it (``power_law.without_jumps``)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv
from noisevar.diagnostics.power_law import without_jumps
from noisevar.estimators import estimate_chunked

N = 20_000


def _record(a: float, size: float) -> np.ndarray:
    rng = np.random.default_rng(1)
    x = lfilter([1.0], [1.0, -a], rng.normal(size=N)) * np.sqrt(1.0 - a * a)
    for i in np.sort(rng.choice(np.arange(200, N - 200), 20, replace=False)):
        x[i:] += size
    return x


@pytest.mark.parametrize("a", [0.5, 0.8])
def test_steps_leave_the_identified_colour_as_it_was(a):
    plain = nv.estimate(_record(a, 0.0)).diagnostics
    stepped = nv.estimate(_record(a, 50.0)).diagnostics
    assert stepped.power_law == plain.power_law
    assert all(alpha != 0 for _, alpha in stepped.power_law[1:])  # no random walk


def test_white_noise_with_steps_reads_white():
    e = nv.estimate(_record(0.0, 30.0))
    assert e.diagnostics.verdict.startswith("white Gaussian noise"), e.diagnostics.verdict


def test_streamed_reads_the_same_colour():
    z = _record(0.5, 50.0)
    one = nv.estimate(z)
    many = estimate_chunked(lambda a, b: z[max(a, 0) : b].copy(), z.size, chunk=4096)
    assert many.diagnostics.power_law == one.diagnostics.power_law


def test_the_pieces_join_without_their_jumps():
    x = np.r_[np.arange(5.0), 100.0 + np.arange(5.0, 10.0)]
    got = without_jumps(x, [(4, 6)])
    np.testing.assert_array_equal(got, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0])  # 4 and 5 cut
    assert without_jumps(x, []) is x
