"""A record split at a gap is one answer: the pieces' outliers, note and kurtosis in record terms.

A real log with a gap is estimated per uniform piece and pooled. The pooled estimate kept
only its first piece's notes (an outlier note with the piece's own index and share: PX4's
local position read "1 outlying sample (1.47%; the first at sample 15)") and dropped the
pieces' outlying samples and kurtosis, so the verdict of the same record with a gap called
one glitch "heavy-tailed noise" where the record in one piece names it.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


def _record(seed: int = 1, n: int = 2000, at: int = 1500) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    z = rng.normal(size=n)
    z[at] += 40.0
    t = np.arange(n) * 0.01
    t[1000:] += 5.0  # a 5 s gap after sample 999
    return z, t


@pytest.mark.parametrize("at", [300, 1500])
def test_gap_keeps_the_glitch_in_record_terms(at: int) -> None:
    z, t = _record(at=at)
    whole, split = noisevar.estimate(z), noisevar.estimate(z, t=t)
    assert split.outliers is not None
    assert list(split.outliers) == list(whole.outliers) == [at]
    note = f"1 outlying sample (0.05%; the first at sample {at})"
    assert any(n.startswith(note) for n in split.notes)
    assert sum("outlying sample" in n for n in split.notes) == 1
    # the verdict names the glitch on both, as one level of white noise
    for e in (whole, split):
        assert e.diagnostics.verdict.startswith("white noise with 1 outlying sample")
    assert split.kurtosis == pytest.approx(whole.kurtosis, rel=0.25)


def test_outliers_in_both_pieces_are_counted_once_each() -> None:
    z, t = _record()
    z[200] -= 40.0
    split = noisevar.estimate(z, t=t)
    assert list(split.outliers) == [200, 1500]
    said = [n for n in split.notes if "outlying sample" in n]
    assert said == [
        "2 outlying samples (0.10%; the first at sample 200): noise, so in the variance; "
        "left out of core_variance"
    ]


def test_held_segments_are_refused_with_one_error_and_no_warning() -> None:
    """Every gap-split segment of held values (a 0.1-degree temperature staircase, audit 11's
    GENEActiv) is refused as the record without times is, with no 0/0 warning on the way."""
    import warnings

    z = np.round(np.repeat(31.6 - 0.1 * np.arange(11), 800)[:8400], 1)
    t = np.arange(8400) * 0.02
    t[4200:] += 0.5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(noisevar.NoisevarError, match="noise variance of 0") as with_t:
            noisevar.estimate(z, t=t)
        with pytest.raises(noisevar.NoisevarError) as without:
            noisevar.estimate(z)
    assert str(with_t.value) == str(without.value)
