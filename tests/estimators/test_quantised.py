"""Quantised records at low noise: auto's correction for the missed rounding error (§E3)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar import synth
from noisevar.diagnostics.panel import verdict_severity
from noisevar.estimators.auto import _quantised
from noisevar.estimators.auto._quantised import (
    PIECES,
    QUANT_MAX_SIGMA,
    SMOOTH_STEPS,
    Offsets,
    quantisation_correction,
    record_offsets,
    rounding_model,
    solve_sigma,
)

LSB = 25.0
N = 6000


def _off(monkeypatch) -> None:
    """Switch the correction off (the estimate as it was before it)."""
    monkeypatch.setattr(_quantised, "correct", lambda result, *args: result)


def _records(clean: np.ndarray, std: float, runs: int, seed: int) -> tuple[np.ndarray, float]:
    d = synth.noise("gauss", clean.size, seed, runs=runs, std=std)
    return synth.quantise(clean + d.values, LSB, d.variance, clean=clean)


def _bias(z: np.ndarray, truth: float) -> float:
    return float(np.mean([e.variance / truth - 1 for e in noisevar.estimate(z)]))


@pytest.mark.parametrize(
    "clean",
    [
        np.linspace(0.0, 40 * LSB, N) + 3.0,  # a slow ramp: offsets nearly uniform
        noisevar.generate("noise-step", n=N).clean,  # lingers near grid points at its turns
    ],
    ids=["ramp", "noise-step"],
)
def test_slow_signal_at_a_fifth_of_a_step(clean, monkeypatch) -> None:
    z, truth = _records(clean, 0.2 * LSB, 60, 5)
    after = _bias(z, truth)
    _off(monkeypatch)
    before = _bias(z, truth)
    assert before < -0.05  # what the residual misses
    assert abs(after) < 0.015


def test_the_record_own_offsets_not_uniform_ones() -> None:
    # noise-step's error variance is well below σ² + 1/12: the model, fed the clean
    # signal, finds the exact value of synth (not the uniform-offset one)
    clean = noisevar.generate("noise-step", n=N).clean
    exact = synth.quantised_error_variance(clean, LSB, (0.2 * LSB) ** 2) / LSB**2
    off = Offsets([clean / LSB], [clean / LSB], [(40, N - 40)])  # truth over all N
    truth = rounding_model(off, 0.2, 81, 3)[1]
    assert truth == pytest.approx(exact, rel=1e-4)
    assert truth < 0.95 * (0.04 + 1 / 12)


def test_fast_ramp_is_not_over_corrected(monkeypatch) -> None:
    # over a step per sample: nothing is missed; b(c) is periodic at 0.37 cycles per
    # sample and the residual sees it with its gain there (a little above 1)
    clean = 1.37 * LSB * np.arange(N)
    z, truth = _records(clean, 0.2 * LSB, 40, 6)
    after = _bias(z, truth)
    _off(monkeypatch)
    before = _bias(z, truth)
    assert abs(after) < 0.015 and abs(after) < abs(before)


def test_not_applied_without_a_grid_or_with_large_noise(monkeypatch) -> None:
    rng = np.random.default_rng(3)
    clean = noisevar.generate("noise-step", n=N).clean
    continuous = clean + 5.0 * rng.standard_normal(N)
    large, _ = synth.quantise(clean + 0.6 * LSB * rng.standard_normal(N), LSB, 1.0)
    on = [noisevar.estimate(z) for z in (continuous, large)]
    _off(monkeypatch)
    off = [noisevar.estimate(z) for z in (continuous, large)]
    assert on[1].diagnostics.lsb == LSB
    for a, b in zip(on, off, strict=True):
        assert a.variance == b.variance and a.ci95 == b.ci95 and a.notes == b.notes


def test_the_note_reaches_the_json_and_scales_everything(monkeypatch) -> None:
    clean = np.linspace(0.0, 40 * LSB, N)
    z, _ = _records(clean, 0.2 * LSB, 1, 9)
    got = noisevar.estimate(z)
    _off(monkeypatch)
    raw = noisevar.estimate(z)
    k = got.variance / raw.variance
    assert k > 1.05
    np.testing.assert_allclose(got.core_variance, k * raw.core_variance, rtol=1e-12)
    d = got.to_dict()
    assert any("of a step" in n and "multiplied by" in n for n in d["notes"])
    assert d["ci95_low"] < d["variance"] < d["ci95_high"]


def test_a_still_signal_is_not_corrected() -> None:
    # the signal crosses under two steps: the offsets are not uniform, no factor is applied
    clean = np.linspace(0.0, 1.5 * LSB, N)
    z, _ = _records(clean, 0.2 * LSB, 1, 4)
    got = noisevar.estimate(z)
    assert any("crosses only" in n for n in got.notes)
    assert not any("multiplied by" in n for n in got.notes)


def test_solve_sigma_inverts_the_model() -> None:
    c = np.linspace(0.0, 30.0, 4000) + 0.1 * np.sin(np.arange(4000) / 50)
    off = Offsets([c], [c], [(40, 4000 - 40)])
    for s in (0.05, 0.2, 0.4):
        seen, truth = rounding_model(off, s, 81, 3)
        assert seen < truth or s > 0.3  # the slow part of b is missed
        assert solve_sigma(off, seen, 81, 3) == pytest.approx(s, rel=1e-6)
    assert (
        quantisation_correction(lambda a, b: None, 10**6, 1.0, QUANT_MAX_SIGMA**2 + 0.1, 81, 3)
        is None
    )


@pytest.mark.parametrize(("n", "jump"), [(40_000, 0.0), (150_000, 0.0), (150_000, 20.0)])
def test_chunked_equals_in_memory_on_a_quantised_record(n: int, jump: float) -> None:
    from noisevar.stream import estimate_chunked

    rng = np.random.default_rng(21)
    clean = 30 * LSB * np.sin(np.arange(n) / 3000) + jump * LSB * (np.arange(n) >= n // 3)
    z, _ = synth.quantise(clean + 0.2 * LSB * rng.standard_normal(n), LSB, 1.0)
    one = noisevar.estimate(z)
    many = estimate_chunked(
        lambda a, b: z[max(a, 0) : b].copy(), n, probe=z.__getitem__, chunk=4096
    )
    assert any("multiplied by" in s for s in one.notes)
    np.testing.assert_allclose(many.variance, one.variance, rtol=1e-9)
    np.testing.assert_allclose(many.ci95, one.ci95, rtol=1e-9)
    np.testing.assert_allclose(many.core_variance, one.core_variance, rtol=1e-9)
    assert many.notes[1:] == one.notes


def test_offsets_are_a_pure_function_of_the_pieces_read() -> None:
    z = np.round(
        np.arange(200_000) * 0.01 + np.random.default_rng(1).standard_normal(200_000) * 0.2
    )
    seen = []
    off = record_offsets(lambda a, b: seen.append((a, b)) or z[a:b], z.size, 1.0, 81)
    final = seen[-PIECES:]  # the first fit's pieces, then the chosen fit's
    assert len(seen) == 2 * PIECES and final[0][0] == 0 and final[-1][1] == z.size
    assert all(b - a <= 2048 + 2 * (40 + 4 * (off.fit // 2)) for a, b in final)
    assert off.travel(z.size) == pytest.approx(0.01 * z.size, rel=0.02)
    # the fit spans about SMOOTH_STEPS steps of the signal
    assert off.fit == pytest.approx(SMOOTH_STEPS / 0.01, rel=0.05)


def test_a_long_slow_record_gets_a_longer_fit() -> None:
    # noise-step stretched to 60,000 samples: a fit of a fixed 601 samples would see the
    # signal linger within it, and the rounding error's mean with it
    n = 60_000
    clean = noisevar.generate("noise-step", n=n).clean
    z, truth = _records(clean, 0.2 * LSB, 6, 14)
    off = record_offsets(lambda a, b: z[0, a:b], n, LSB, 81)
    assert off.fit > 3000  # 513 on the 6,000-sample record
    assert abs(_bias(z, truth)) < 0.01


def test_the_verdict_calls_the_varying_level_quantisation() -> None:
    clean = noisevar.generate("noise-step", n=N).clean
    z, _ = _records(clean, 0.2 * LSB, 1, 11)
    est = noisevar.estimate(z)
    got = est.diagnostics
    assert got.level_varies  # the error's level follows the offset within a step
    assert "quantisation, not a changing sensor" in got.verdict
    assert f"grid of step {LSB:g}" in got.verdict
    assert verdict_severity(got, est.variance) == "ok"  # information, not a warning
    assert verdict_severity(got) == "warning"  # without the variance: the level varies
    # a level that really changes, off any grid, keeps its verdict
    rng = np.random.default_rng(12)
    level = np.where(np.arange(N) < N // 2, 1.0, 4.0)
    other_est = noisevar.estimate(clean + level * rng.standard_normal(N))
    other = other_est.diagnostics
    assert other.lsb is None and other.level_varies
    assert other.verdict.startswith("the noise level changes along the record")
    assert verdict_severity(other, other_est.variance) == "warning"


def test_a_level_jump_is_cut_out_not_modelled_as_noise() -> None:
    # a 20-step level jump: its leak through the residual is signal, not rounding error
    clean = noisevar.generate("noise-step", n=N).clean + 20 * LSB * (np.arange(N) >= N // 2)
    z, truth = _records(clean, 0.2 * LSB, 30, 5)
    off = record_offsets(lambda a, b: z[0, a:b], N, LSB, 81)
    assert off.cuts is not None and np.abs(off.cuts[0] - N // 2).min() <= 3
    assert abs(_bias(z, truth)) < 0.02


def test_a_grid_offset_from_zero_gives_the_same_estimate() -> None:
    clean = noisevar.generate("noise-step", n=N).clean
    z, _ = _records(clean, 0.2 * LSB, 1, 13)
    on_zero, offset = noisevar.estimate(z), noisevar.estimate(z + 0.37 * LSB + 1e6 * LSB)
    assert any("multiplied by" in n for n in on_zero.notes)
    assert offset.variance == pytest.approx(on_zero.variance, rel=1e-6)


@pytest.mark.parametrize("fit", [101, 513, 2049])
def test_smooth_is_scipys_savitzky_golay_fit(fit):
    from scipy import signal

    from noisevar.estimators.auto._quantised import SMOOTH_ORDER, _smooth

    x = np.cumsum(np.random.default_rng(fit).standard_normal(3 * fit))
    expected = signal.savgol_filter(x, fit, SMOOTH_ORDER, mode="interp")
    np.testing.assert_allclose(_smooth(x, fit), expected, rtol=0, atol=1e-9 * np.ptp(x))


def test_a_gapped_record_says_it_was_not_corrected() -> None:
    clean = noisevar.generate("noise-step", n=N).clean
    z, _ = _records(clean, 0.2 * LSB, 1, 7)
    gapped = synth.remove_blocks(z, 3, t=np.arange(N, dtype=float))
    est = noisevar.estimate(gapped.values, t=gapped.t)
    assert len(est.diagnostics.gaps) > 0
    assert any("has gaps" in note and "§E3" in note for note in est.notes)
    whole = noisevar.estimate(z)
    assert not any("has gaps" in note for note in whole.notes)
