"""noisevar.synth: each kind has the shape, the variance and the character it claims."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from noisevar import synth
from noisevar.errors import NoisevarError

RUNS, N = 200, 2000


@pytest.mark.parametrize("kind", ["gauss", "student_t", "laplace", "contaminated", "ar1"])
def test_stationary_kinds_have_their_stated_variance(kind: str) -> None:
    d = synth.noise(kind, N, rng=1, runs=RUNS, std=1.5)
    assert d.values.shape == (RUNS, N)
    assert d.kind == kind
    # the mean square over 400 000 samples is within a few standard errors of the claim
    assert np.mean(d.values**2) == pytest.approx(d.variance, rel=0.03)


def test_default_variances_are_the_documented_ones() -> None:
    assert synth.noise("gauss", 100, rng=0, std=2.0).variance == 4.0
    assert synth.noise("student_t", 100, rng=0).variance == 1.0
    d = synth.noise("contaminated", 100, rng=0, fraction=0.01, factor=10.0)
    assert d.variance == pytest.approx(1.99)
    assert d.core_variance == 1.0
    assert synth.noise("ar1", 100, rng=0).core_variance is None


def test_heavy_tails_have_their_kurtosis() -> None:
    laplace = synth.noise("laplace", 200_000, rng=2).values
    t5 = synth.noise("student_t", 200_000, rng=3, dof=5).values
    gauss = synth.noise("gauss", 200_000, rng=4).values
    assert stats.kurtosis(laplace) == pytest.approx(3.0, abs=0.3)  # excess kurtosis 3
    assert stats.kurtosis(t5) > 3.0  # excess kurtosis 6 (its estimate converges slowly)
    assert abs(stats.kurtosis(gauss)) < 0.1


def test_contaminated_has_the_stated_outlier_share() -> None:
    d = synth.noise("contaminated", 100_000, rng=5, fraction=0.02, factor=10.0)
    share = np.mean(np.abs(d.values) > 5.0)  # a 5-sigma sample of the bulk is ~6e-7 likely
    assert share == pytest.approx(0.02 * 0.62, rel=0.15)  # P(|N(0, 10)| > 5) = 0.617


def test_ar1_has_its_lag_one_correlation() -> None:
    x = synth.noise("ar1", 100_000, rng=6, phi=0.7).values
    assert np.corrcoef(x[:-1], x[1:])[0, 1] == pytest.approx(0.7, abs=0.02)


def test_flicker_variance_matches_its_formula_and_grows() -> None:
    d = synth.noise("flicker", 1000, rng=7, runs=800)
    assert d.variance == synth.flicker_variance(1000)
    assert np.mean(d.values**2) == pytest.approx(d.variance, rel=0.06)
    assert synth.flicker_variance(10_000) > synth.flicker_variance(1000)
    early, late = np.var(d.values[:, 10]), np.var(d.values[:, 900])
    assert late > 1.3 * early  # expected 1.5: sum h_j² grows like ln(k) / π


def test_flicker_is_seeded_and_leaves_numpys_global_generator_alone() -> None:
    np.random.seed(123)  # noqa: NPY002 - the global state allantools touches
    before = np.random.get_state()[1].copy()  # noqa: NPY002
    a = synth.noise("white+flicker", 500, rng=8).values
    b = synth.noise("white+flicker", 500, rng=8).values
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(np.random.get_state()[1], before)  # noqa: NPY002


def test_mixtures_compare_with_the_white_part() -> None:
    wf = synth.noise("white+flicker", 3000, rng=9, std=2.0)
    rw = synth.noise("white+rw", 3000, rng=10, std=2.0, ratio=1.0)
    assert wf.variance == rw.variance == 4.0
    # the walk dominates: the record's spread dwarfs the white part
    assert np.var(rw.values) > 50 * rw.variance


def test_same_seed_same_draw_other_seed_other_draw() -> None:
    a = synth.noise("laplace", 50, rng=11).values
    np.testing.assert_array_equal(a, synth.noise("laplace", 50, rng=11).values)
    assert not np.array_equal(a, synth.noise("laplace", 50, rng=12).values)


def test_quantise_rounds_to_the_grid_and_adds_lsb_squared_over_12() -> None:
    rng = np.random.default_rng(13)
    clean = np.linspace(0.0, 500.0, 200_000)
    x = clean + rng.standard_normal(clean.size) * 0.5
    xq, var = synth.quantise(x, 0.25, 0.25)
    np.testing.assert_allclose(xq / 0.25, np.round(xq / 0.25), atol=1e-9)
    assert var == pytest.approx(0.25 + 0.25**2 / 12)
    assert np.mean((xq - clean) ** 2) == pytest.approx(var, rel=0.02)


def test_quantise_with_the_clean_signal_gives_the_exact_error_variance() -> None:
    # a slow signal sweeping few steps, noise 0.2 step: lsb²/12 is off, the exact value is not
    clean = 3.0 * np.sin(np.linspace(0.0, 3.0, 3000))
    x = clean + np.random.default_rng(15).standard_normal((300, clean.size)) * 0.2
    xq, exact = synth.quantise(x, 1.0, 0.04, clean=clean)
    _, nominal = synth.quantise(x, 1.0, 0.04)
    measured = np.mean((xq - clean) ** 2)
    assert measured == pytest.approx(exact, rel=0.01)
    assert abs(measured / nominal - 1.0) > 0.03


def test_remove_blocks_leaves_gaps_in_t() -> None:
    z = np.arange(12_000, dtype=float).reshape(2, 6000)
    g = synth.remove_blocks(z, rng=14, fraction=0.05, blocks=10)
    assert g.values.shape == (2, 5700) and g.t.shape == (5700,)
    assert np.sum(~g.keep) == 300
    steps = np.diff(g.t)
    assert np.sum(steps > 1) == 10  # ten separate blocks
    assert set(np.unique(steps[steps > 1])) == {31.0}
    np.testing.assert_array_equal(g.values[0], g.t)  # samples keep their own times


@pytest.mark.parametrize(
    ("kind", "params"),
    [
        ("nope", {}),
        ("student_t", {"dof": 2.0}),
        ("ar1", {"phi": 1.0}),
        ("contaminated", {"fraction": 1.0}),
        ("gauss", {"sigma": 1.0}),
    ],
)
def test_bad_input_says_what_to_do(kind: str, params: dict) -> None:
    with pytest.raises(NoisevarError):
        synth.noise(kind, 100, rng=0, **params)


def test_bad_quantise_and_gaps_are_refused() -> None:
    with pytest.raises(NoisevarError, match="lsb"):
        synth.quantise([1.0, 2.0], 0.0, 1.0)
    with pytest.raises(NoisevarError, match="blocks"):
        synth.remove_blocks(np.zeros(100), rng=0, fraction=0.05, blocks=50)


def test_to_dict_is_json_safe() -> None:
    d = synth.noise("contaminated", 10, rng=0).to_dict()
    assert d == {
        "kind": "contaminated",
        "shape": [10],
        "variance": pytest.approx(1.99),
        "core_variance": 1.0,
        "params": {},
    }
