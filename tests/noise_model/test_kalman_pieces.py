"""The Kalman fit between the level jumps the record's R leaves out (docs/algorithms.md §E6
*Between the jumps*)."""

import numpy as np
import pytest

import noisevar
from noisevar.noise_model import fit_kalman
from noisevar.noise_model._steady import filter_pass
from noisevar.noise_model.kalman_fit import kinematic_model
from noisevar.noise_model.kalman_pieces import between_jumps, pieces_pass, whole

#: per-sample random-walk variance and white-noise variance of the stepped record
Q_TRUE, R_TRUE = 0.02**2, 0.5**2


@pytest.fixture(scope="module")
def stepped():
    """A random walk plus white noise with three level steps of 50-120 sigma."""
    rng = np.random.default_rng(7)
    n = 4000
    z = np.cumsum(rng.normal(0, Q_TRUE**0.5, n)) + rng.normal(0, R_TRUE**0.5, n)
    z[1000:] += 40
    z[2500:] -= 60
    z[3300:] += 25
    return z, noisevar.estimate(z)


@pytest.mark.parametrize("model", ["rw", "cv"])
def test_fit_leaves_out_the_jumps_r_leaves_out(stepped, model):
    z, est = stepped
    assert est.jumps is not None and est.jumps.any()
    fit = fit_kalman(z, model=model, record=est)
    assert fit.left_out == int(est.jumps.sum())
    assert fit.n == z.size - fit.left_out
    assert any("fitted between the level jumps" in s for s in fit.notes)
    # on the whole record the steps made r 3.8x R (cv) and q 3700x its truth (rw)
    assert est.ci95[0] <= fit.r <= est.ci95[1]
    assert fit.record is not None and fit.record.agrees
    assert not any("level jumps" in b for b in fit.record.broken)
    assert fit.to_dict()["left_out"] == fit.left_out


def test_random_walk_q_between_the_jumps(stepped):
    z, est = stepped
    fit = fit_kalman(z, model="rw", record=est)
    lo, hi = fit.q_interval
    assert lo <= Q_TRUE <= hi


def test_no_jumps_fits_the_whole_record():
    rng = np.random.default_rng(3)
    z = np.cumsum(rng.normal(0, 0.05, 1500)) + rng.normal(0, 0.5, 1500)
    est = noisevar.estimate(z)
    assert est.jumps is None or not est.jumps.any()
    fit = fit_kalman(z, model="rw", record=est)
    assert fit.left_out == 0 and fit.n == z.size
    assert not any("between the level jumps" in s for s in fit.notes)


class _Est:
    """The one attribute :func:`between_jumps` reads."""

    def __init__(self, jumps):
        self.jumps = np.asarray(jumps, bool)


def test_between_jumps_spans():
    jumps = np.zeros(200, bool)
    jumps[50:55] = True  # a piece of 50 before, 20 then, and 125 after
    jumps[75:80] = True
    p = between_jumps(200, _Est(jumps), 40)
    assert p.spans == ((0, 50), (80, 200))
    assert p.left_out == 30 and "2 piece(s)" in p.note
    assert between_jumps(200, _Est(np.zeros(200, bool)), 40) == whole(200)
    assert between_jumps(200, "no estimate", 40) == whole(200)


def test_between_jumps_too_short_takes_the_whole_record():
    jumps = np.zeros(100, bool)
    jumps[30:35] = jumps[65:70] = True
    p = between_jumps(100, _Est(jumps), 40)
    assert p.spans == ((0, 100),) and p.left_out == 0
    assert "no piece has the 40 samples" in p.note


def test_one_piece_is_the_plain_filter():
    rng = np.random.default_rng(1)
    z = rng.normal(size=300).cumsum()
    F, h, Q1 = kinematic_model("cv", 1.0)
    a = filter_pass(z, F, h, Q1 * 0.1, 1.0)
    b = pieces_pass((z,), F, h, Q1 * 0.1, 1.0, states=True)
    np.testing.assert_array_equal(a.innovations, b.innovations)
    np.testing.assert_array_equal(a.s, b.s)


def test_pieces_are_each_from_a_diffuse_start():
    rng = np.random.default_rng(2)
    z1, z2 = rng.normal(size=120), rng.normal(size=90) + 1e3
    F, h, Q1 = kinematic_model("rw", 1.0)
    joined = pieces_pass((z1, z2), F, h, Q1 * 0.01, 1.0, states=False)
    parts = [filter_pass(p, F, h, Q1 * 0.01, 1.0, states=False) for p in (z1, z2)]
    np.testing.assert_allclose(
        joined.innovations, np.concatenate([p.innovations for p in parts]), rtol=0, atol=1e-9
    )


def test_a_timed_record_in_segments_carries_its_jumps_to_the_fit():
    """The CLI's record is estimated on the file's times: split at a gap, the segments'
    jumps are pooled in record indices, so the fit leaves them out as without times."""
    rng = np.random.default_rng(5)
    n = 3000
    z = np.cumsum(rng.normal(0, 0.05, n)) + rng.normal(0, 1, n)
    z[1500:] += 60
    t = np.arange(n, dtype=float)
    t[1000:] += 50  # a gap: two uniform segments
    timed = noisevar.estimate(z, t=t)
    assert timed.jumps is not None and timed.jumps.size == n
    assert timed.jumps[1490:1510].any() and not timed.jumps[:1000].any()
    fit = fit_kalman(z, model="cv", record=timed)
    assert fit.left_out > 0
    assert timed.ci95[0] <= fit.r <= timed.ci95[1]
