"""Row medians: the compiled band selection against ``np.median``, to the last bit."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.numeric import blocks


def _rows(kind: str, shape: tuple[int, int], rng: np.random.Generator) -> np.ndarray:
    v = rng.standard_normal(shape) ** 2
    if kind == "ties":  # a quantised record's squares: few distinct values
        v = np.round(v * 2) / 2
    elif kind == "held":  # most of each row 0 (held values), the median among them
        v[:, : shape[1] * 2 // 3] = 0.0
    elif kind == "sorted":
        v.sort(axis=1)
    elif kind == "reversed":
        v = -np.sort(-v, axis=1)
    elif kind == "inf":
        v[:, ::3] = np.inf
    elif kind == "signed":
        v = rng.standard_t(2, shape) * 1e300
    return v


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("kind", ["chi2", "ties", "held", "sorted", "reversed", "inf", "signed"])
@pytest.mark.parametrize("cols", [1, 2, 7, 64, 65, 256, 5000, 5001])
def test_row_medians_equal_numpy(kind, cols, compiled, monkeypatch):
    monkeypatch.setattr(blocks, "COMPILED_MEDIANS", compiled)
    rng = np.random.default_rng(cols)
    v = _rows(kind, (7, cols), rng)
    before = v.copy()
    assert np.array_equal(blocks.row_medians(v), np.median(v, axis=1))
    assert np.array_equal(v, before)  # the rows are read, not reordered


def test_row_medians_when_the_sample_misses_the_middle():
    # every sampled position (i * 5000 // 64) holds a value far above the median: the band
    # the sample proposes misses the middle ranks and is widened over the same values
    v = np.tile(np.linspace(0.0, 1.0, 5000), (3, 1))
    v[:, np.arange(64) * 5000 // 64] = 1e9
    assert np.array_equal(blocks.row_medians(v), np.median(v, axis=1))
