"""A filter's smoothed output's still R is no R to use, on every surface (issue 26,
real_audit16: RTKLIB rover1's still R 2e-9 m², ci95 +-10 %, about 1e-5 of the solver's own
variance, was handed out by ``regimes='still'``, the row and ``fit --regimes still``).

The still stretches of a record whose noise is smoother than a sensor's own low-pass leaves
it hold no sensor noise: their level is measured and said, its interval not handed out.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar
from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import longest_still_stretch, variance_for, why_no_still


def _smoothed_output(seed: int) -> np.ndarray:
    """A still antenna's position as a second-order smoother writes it, a move in between
    (tests/diagnostics/test_not_at_rest.py's record)."""
    rng = np.random.default_rng(seed)
    n = 6000
    z = lfilter([0.05], [1.0, -0.95], lfilter([0.05], [1.0, -0.95], rng.normal(size=n)))
    z[3000:3600] += np.cumsum(rng.normal(size=600)) * 0.05
    return np.round(z, 4)


@pytest.mark.parametrize("seed", [0, 1])
def test_still_r_of_a_smoothed_output_is_refused(seed: int) -> None:
    """Before: ``variance_for(est, 'still')`` 5.97e-7 (ci95 +-20 %), the row's still cells
    filled, ``fit --regimes still`` quoted it as "R to use"."""
    z = _smoothed_output(seed)
    est = noisevar.estimate(z)
    assert est.still is not None  # measured and kept
    gap = why_no_still(est)
    assert gap is not None and "smoothed output" in gap and "raw measurements" in gap
    with pytest.raises(NoisevarError, match="smoothed output"):
        variance_for(est, "still")
    with pytest.raises(NoisevarError, match="smoothed output"):
        longest_still_stretch(z, est=est)
    row = est.to_row()
    assert row["still_variance"] is None and row["still_ci95_low"] is None
    assert "smoothed output" in row["still_note"]
    assert any("does not cover" in n for n in est.still.notes)


def test_white_still_r_is_still_served() -> None:
    """A sensor at rest but for a run of motion keeps its still R everywhere."""
    rng = np.random.default_rng(3)
    z = rng.normal(size=12000)
    z[4000:8000] += 20.0 * np.sin(np.arange(4000) / 3.0)
    est = noisevar.estimate(z)
    assert why_no_still(est) is None
    assert variance_for(est, "still") == est.still.variance
    assert est.to_row()["still_variance"] == est.still.variance
    assert not any("does not cover" in n for n in est.still.notes)


def test_fit_still_refuses_a_smoothed_output_in_one_line(tmp_path, capsys) -> None:
    """Before: ``noisevar fit --regimes still`` printed "R to use 596.7e-9" and "the record
    breaks none of the fit's assumptions the estimate checks"."""
    from noisevar.cli import main

    path = tmp_path / "smoothed.csv"
    np.savetxt(path, _smoothed_output(0))
    assert main(["fit", str(path), "--rate", "1", "--regimes", "still"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "smoothed output" in err and "solver's own variance" in err


def test_untested_still_r_says_what_it_assumes() -> None:
    """Still stretches too short to test (under 400 residuals): before, the still R said
    nothing of what it rests on (RTKLIB's rover2: "untested" in the verdict only)."""
    rng = np.random.default_rng(0)
    z = 0.1 * rng.normal(size=4000)
    z[300:] += 5.0 * rng.normal(size=3700)
    est = noisevar.estimate(z)
    assert est.still is not None and est.diagnostics.still_whiteness is None
    assert any("assumes it white" in n and "untested" in n for n in est.still.notes)


def test_untested_still_level_gives_its_interval_in_the_verdict() -> None:
    """A still level on too few samples to test: the verdict gives the interval those
    samples give (a Permian gamma ray's R to use, 65 samples of 12,041: 95 % 0.0015 to
    0.061, real_audit18); before, the level alone, "untested"."""
    rng = np.random.default_rng(0)
    z = 0.1 * rng.normal(size=4000)
    z[300:] += 5.0 * rng.normal(size=3700)
    est = noisevar.estimate(z)
    v = est.diagnostics.verdict
    assert "too short to test whether their noise is white" in v
    assert "so this level (95 %" in v and "on them) is untested" in v, v
    assert any(f"({est.still.n_used} samples," in n for n in est.still.notes)


def test_the_record_answer_does_not_hand_out_a_smoothed_still_r() -> None:
    """The answer sentence every page and export quotes: before, "Its still regimes
    alone: R = 596.7e-9" on a smoothed output."""
    from noisevar.estimators.answer import record_answer

    est = noisevar.estimate(_smoothed_output(0))
    said = record_answer(est).sentence()
    assert "still regimes alone" not in said and "not an R to use" in said, said
