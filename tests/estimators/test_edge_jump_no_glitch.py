"""A jump or fast motion at a record's edge is no glitch there: its samples count as they
are, with no glitch's credit (traffic's A320 pitch, two samples dropped: R x1.26, issue 26)."""

from __future__ import annotations

import numpy as np

from noisevar.estimators.auto._edges import edge_glitches

#: The pitch's take-off rotation (grid steps), as the record reads with two samples dropped.
_ROTATION = np.array([41.0, 41, 42, 46, 48, 48, 46, 45, 44, 44, 45, 47, 47, 48, 47, 47, 47, 47])


def _quiet(seed: int, n: int = 400) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.round(47.2 + 0.08 * rng.normal(size=n))


def test_a_rotation_at_the_start_is_not_credited_as_a_glitch() -> None:
    for seed in (0, 1, 2):
        z = _quiet(seed)
        z[: _ROTATION.size] = _ROTATION
        peaks, first, _ = edge_glitches(z, np.array([0, 1, 2]), (5, 5), 5, 3)
        # was: 50.5 steps² added, 25x the square the one-sided rows give sample 0
        assert first == 0.0
        assert peaks.tolist() == [0, 1, 2]
        # the reversed record: the same at its end
        back = np.array([z.size - 3, z.size - 2, z.size - 1])
        _, _, last = edge_glitches(z[::-1].copy(), back, (5, 5), 5, 3)
        assert last == 0.0


def test_a_lone_glitch_at_the_start_keeps_its_credit() -> None:
    for seed in (0, 1, 2):
        z = _quiet(seed)
        z[0] += 6.0
        peaks, first, _ = edge_glitches(z, np.array([0, 1, 2]), (5, 5), 5, 3)
        assert peaks.tolist() == [0]
        assert first > 0.9 * 36.0 * 0.9  # (1 - w_0) 6², w_0 about 4 %
