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


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("offset, stride", [(0, 1), (1, 2), (3, 4)])
def test_scaled_square_rows_equal_numpy(offset, stride, compiled, monkeypatch):
    """Peaks, rows over their peaks squared (NaN in a row of zeros) and squares' medians."""
    monkeypatch.setattr(blocks, "COMPILED_MEDIANS", compiled)
    rng = np.random.default_rng(stride)
    rows = rng.standard_t(3, (6, 5000))
    rows[1] = 0.0  # a held stretch
    rows[2] = -np.abs(rows[2])  # the peak on the negative side
    rows[3, ::2] = 0.0
    peak, x2, med = blocks.scaled_square_rows(rows, offset, stride, 0.37)
    top, low = rows.max(axis=1, initial=0.0), -rows.min(axis=1, initial=0.0)
    ref_peak = np.where(low > top, low, top)
    with np.errstate(invalid="ignore", divide="ignore"):
        ref_x2 = (rows / ref_peak[:, None]) ** 2
    values = rows[:, offset::stride] * rows[:, offset::stride] * 0.37
    assert np.array_equal(peak, ref_peak)
    assert np.array_equal(x2, ref_x2, equal_nan=True) and np.isnan(x2[1]).all()
    assert np.array_equal(med, np.median(values, axis=1))
