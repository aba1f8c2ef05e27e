"""Which power-law noise dominates at each averaging factor (lag-1 autocorrelation).

Names for a measured quantity (allantools' phase data): α = 2 white, 1 flicker, 0 random
walk, -1 flicker walk, -2 random run (docs/algorithms.md §E4).

The identification is Riley and Greenhall's (2004): :func:`noisevar.numeric.noise_id.noise_id`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from noisevar.numeric.noise_id import noise_id

#: Averaging factors probed.
AVERAGING_FACTORS = (1, 4, 16, 64)
#: At most this many samples are used (the identification is costly on long records).
POWER_LAW_MAX = 2**17
#: At least this many averaged samples per factor.
POWER_LAW_MIN = 64

#: α of white noise (the phase-noise convention of :func:`power_law_types`).
WHITE = 2
NAMES = {WHITE: "white", 1: "flicker", 0: "random walk", -1: "flicker walk", -2: "random run"}


def power_law_types(z: NDArray) -> tuple[tuple[int, int], ...]:
    """``(averaging factor, α)`` of the dominant power-law noise at each factor.

    Parameters
    ----------
    z : ndarray
        Uniformly sampled record (the first :data:`POWER_LAW_MAX` samples are used).

    Returns
    -------
    tuple of (int, int)
        Empty when the record is too short.
    """
    x = np.asarray(z[:POWER_LAW_MAX], dtype=float)
    x = (x - x.mean()) / (np.std(x) or 1.0)  # the statistics are scale-free
    out = []
    for af in AVERAGING_FACTORS:
        if x.size // af < POWER_LAW_MIN:
            break
        out.append((af, max(-2, min(2, noise_id(x, af)))))
    return tuple(out)


def without_jumps(x: NDArray, runs: list[tuple[int, int]]) -> NDArray:
    """``x`` with the samples of ``runs`` (left out around level jumps) cut out, the pieces
    joined: each continues the one before, the increments that touch a cut dropped.

    A level jump is signal, not noise; left in, 20 steps in noise of lag-one correlation
    0.5 read "random walk at 1-64 samples" (issue 26).
    """
    keep = np.ones(x.size, dtype=bool)
    for a, b in runs:
        keep[max(a, 0) : min(b, x.size)] = False
    if keep.all() or keep.sum() < 2:
        return x
    step = keep[1:] & keep[:-1]
    first = int(np.argmax(keep))
    return np.r_[x[first], x[first] + np.cumsum(np.diff(x)[step])]


def describe(types: tuple[tuple[int, int], ...]) -> str:
    """Plain words: ``"white at 1 sample, flicker at 4-16 samples"``."""
    parts: list[tuple[int, int, int]] = []  # (alpha, first af, last af)
    for af, alpha in types:
        if parts and parts[-1][0] == alpha:
            parts[-1] = (alpha, parts[-1][1], af)
        else:
            parts.append((alpha, af, af))
    words = []
    for alpha, a, b in parts:
        span = f"{a} sample{'s' if a > 1 else ''}" if a == b else f"{a}-{b} samples"
        words.append(f"{NAMES[alpha]} at {span}")
    return ", ".join(words)
