"""regimes="all" | "still" on the noise models and their exports (issue 26, item 5)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import noisevar
from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import (
    choose_variances,
    longest_still_stretch,
    variance_for,
)
from noisevar.noise_model import allan, fit_coloured_noise, fit_kalman, inertial_noise
from noisevar.noise_model.export import filterpy_snippet, from_config, to_config
from noisevar.noise_model.kalibr import kalibr_imu, parse_kalibr

#: the whole motion record's r interval reaches past a float (an infinite upper bound)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")

SIGMA = 0.15
STILL = 2000


def still_then_motion(n: int = 6000, seed: int = 1) -> np.ndarray:
    """White noise of std 0.15, still for the first 2000 samples, then a large oscillation."""
    rng = np.random.default_rng(seed)
    z = SIGMA * rng.standard_normal(n)
    k = np.arange(STILL, n)
    z[STILL:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
    return z


@pytest.fixture(scope="module")
def record() -> np.ndarray:
    return still_then_motion()


@pytest.fixture(scope="module")
def white() -> np.ndarray:
    return SIGMA * np.random.default_rng(2).standard_normal(3000)


def test_the_longest_still_stretch_is_the_still_start(record) -> None:
    s = longest_still_stretch(record)
    assert not s.one_regime and s.start < 50 and STILL - 100 < s.stop <= STILL + 10
    assert s.share == pytest.approx((s.stop - s.start) / record.size)
    assert f"samples {s.start} to {s.stop}" in s.note and "%" in s.note
    assert s.take(record).size == s.stop - s.start


def test_one_regime_is_the_whole_record(white) -> None:
    s = longest_still_stretch(white)
    assert s.one_regime and (s.start, s.stop) == (0, white.size)
    assert "whole record" in s.note


def test_a_stretch_too_short_says_so_and_what_to_do(record) -> None:
    with pytest.raises(NoisevarError, match="too short for the test.*regimes='all'"):
        longest_still_stretch(record, need=10 * record.size, purpose="the test")


@pytest.mark.parametrize(
    "call",
    [
        lambda z, r: fit_kalman(z, model="rw", regimes=r),
        lambda z, r: fit_coloured_noise(z, regimes=r),
        lambda z, r: inertial_noise(z, 100.0, regimes=r),
        lambda z, r: allan(z, 100.0, data="rate", regimes=r),
    ],
    ids=["fit_kalman", "fit_coloured_noise", "inertial_noise", "allan"],
)
def test_a_bad_choice_is_refused(white, call) -> None:
    for bad in ("moving", "", None, 1):
        with pytest.raises(NoisevarError, match="regimes must be one of 'all', 'still'"):
            call(white, bad)


def test_fit_kalman_on_the_still_stretch(record) -> None:
    whole = fit_kalman(record, model="rw", rate=100.0)
    assert whole.regimes == "all" and fit_kalman(record, model="rw", rate=100.0).r == whole.r
    still = fit_kalman(record, model="rw", rate=100.0, regimes="still")
    s = longest_still_stretch(record)
    assert still.regimes == "still" and still.n == s.stop - s.start
    assert still.notes[0] == s.note
    assert still.r == pytest.approx(SIGMA**2, rel=0.15) and whole.r > 10 * SIGMA**2
    assert still.to_dict()["regimes"] == "still"


def test_one_regime_fits_equal_the_whole_record(white) -> None:
    a, b = fit_kalman(white, model="rw"), fit_kalman(white, model="rw", regimes="still")
    assert (a.q, a.r) == (b.q, b.r) and "whole record" in b.notes[0]
    c, d = fit_coloured_noise(white), fit_coloured_noise(white, regimes="still")
    assert (c.model, c.r) == (d.model, d.r) and d.regimes == "still"


def test_fit_coloured_noise_on_the_still_stretch(record) -> None:
    fit = fit_coloured_noise(record, regimes="still")
    assert fit.n == longest_still_stretch(record).stop - longest_still_stretch(record).start
    assert fit.notes[0].startswith("regimes='still'") and fit.to_dict()["regimes"] == "still"
    assert fit.r == pytest.approx(SIGMA**2, rel=0.15)


def test_inertial_noise_per_axis(record) -> None:
    both = np.stack([record, record[::-1]])
    fits = inertial_noise(both, 100.0, regimes="still")
    starts = [int(f.notes[0].split("samples ")[1].split()[0]) for f in fits]
    assert starts[0] < 50 and starts[1] > record.size - STILL - 100  # each axis its own
    for f in fits:
        assert f.regimes == "still" and f.allan.regimes == "still"
        assert f.white_level == pytest.approx(SIGMA / 10.0, rel=0.1)  # sigma / sqrt(fs)
        assert f.to_dict()["regimes"] == "still"
    assert inertial_noise(record, 100.0).white_level > 5 * SIGMA / 10.0


def test_allan_of_phase_data_cuts_the_phase(record) -> None:
    phase = np.concatenate([[0.0], np.cumsum(record)]) / 100.0
    res = allan(phase, 100.0, data="phase", regimes="still")
    s = longest_still_stretch(record)
    assert res.n_samples == s.stop - s.start + 1 and res.notes == (s.note,)
    assert res.to_dict()["regimes"] == "still"
    assert allan(phase, 100.0).notes == () and allan(phase, 100.0).regimes == "all"


def test_the_config_and_the_snippet_carry_the_choice(record) -> None:
    still = fit_kalman(record, model="rw", rate=100.0, regimes="still")
    cfg = json.loads(json.dumps(to_config(still, {"method": "auto"})))
    back = from_config(cfg)
    assert back["regimes"] == "still" and back["notes"] == list(still.notes)
    assert f"# {still.notes[0]}" in filterpy_snippet(still)
    old = {k: v for k, v in cfg["kalman"].items() if k not in ("regimes", "notes")}
    assert from_config({"kalman": old})["regimes"] == "all"  # files written before
    with pytest.raises(NoisevarError, match="kalman.regimes"):
        from_config({"kalman": {**old, "regimes": "moving"}})
    with pytest.raises(NoisevarError, match="kalman.notes"):
        from_config({"kalman": {**old, "notes": "one"}})
    whole = fit_kalman(record[:STILL], model="rw", rate=100.0)
    assert "# regimes='all': fitted on the whole record" in filterpy_snippet(whole)


def test_kalibr_carries_the_choice(record) -> None:
    fits = inertial_noise(np.stack([record, record[::-1]]), 100.0, regimes="still")
    imu = kalibr_imu(fits, fits)
    text = imu.to_yaml()
    assert imu.regimes == "still" and "# regimes: still" in text
    assert sum("regimes='still'" in n for n in imu.notes) == 4  # 2 gyro + 2 accel axes
    back = parse_kalibr(text)
    assert back.regimes == "still" and back.notes == imu.notes
    whole = inertial_noise(record[:STILL], 100.0)
    assert parse_kalibr(kalibr_imu(whole, whole).to_yaml()).regimes == "all"
    with pytest.raises(NoisevarError, match="different regimes"):
        kalibr_imu(fits, whole)


def test_variance_for_and_choose_variances(record, white) -> None:
    est, one = noisevar.estimate(record), noisevar.estimate(white)
    assert variance_for(est) == est.variance and variance_for(est, "still") == est.still.variance
    assert one.still is None and variance_for(one, "still") == one.variance
    rows = [est.to_row(), one.to_row()]
    whole = [r["variance"] for r in rows]
    still = [r["still_variance"] for r in rows]
    np.testing.assert_array_equal(choose_variances(whole, still), whole)
    np.testing.assert_array_equal(
        choose_variances(whole, still, "still"), [est.still.variance, one.variance]
    )
    with pytest.raises(NoisevarError, match="regimes"):
        variance_for(est, "moving")
