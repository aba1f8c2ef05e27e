"""GPS latency (docs/algorithms.md §C): least-squares delay, segments, random-constant filter."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.experiments.latency import EXPERIMENT
from noisevar.systems.latency import (
    LatencyScenario,
    align_signals,
    estimate_delay,
    random_constant_kalman,
    run_latency,
    segment_delays,
    simulate_latency,
)

NOISE_FREE = {"ahrs_noise_std": 0.0, "gps_noise_std": 0.0, "measurable_jitter_s": 0.0}


@pytest.mark.parametrize("unknown", [0.0, 0.2, 0.5])
def test_integer_delay_is_exact_on_noise_free_records(unknown: float) -> None:
    rec = simulate_latency(LatencyScenario(unknown_delay_s=unknown, **NOISE_FREE), seed=3)
    est = estimate_delay(rec.reference, rec.delayed, rec.sample_period, max_delay=2.0)
    assert est.delay_s == pytest.approx(rec.true_delay[0], abs=1e-9)
    assert est.integer_shift == round(rec.true_delay[0] / rec.sample_period)


@pytest.mark.parametrize("unknown", [0.137, 0.2251, 0.349])
def test_sub_sample_delay_on_noise_free_records(unknown: float) -> None:
    rec = simulate_latency(LatencyScenario(unknown_delay_s=unknown, **NOISE_FREE), seed=1)
    est = estimate_delay(rec.reference, rec.delayed, rec.sample_period, max_delay=2.0)
    # The parabola's error on a smooth signal: far below a millisecond at 10 Hz.
    assert est.delay_s == pytest.approx(rec.true_delay[0], abs=2e-4)


def test_exact_on_a_plain_shifted_signal_in_samples() -> None:
    k = np.arange(3000)
    signal = np.sin(2 * np.pi * k / 217.0) + 0.5 * np.sin(2 * np.pi * k / 61.0 + 1.0)
    for shift in (-7, 0, 4, 11):
        late = np.roll(signal, shift)
        est = estimate_delay(signal, late, max_delay=20)
        assert est.delay_s == pytest.approx(shift, abs=1e-9)


def test_constant_offset_does_not_move_the_delay_when_bias_is_removed() -> None:
    scen = LatencyScenario(ahrs_bias=3.0, measurable_jitter_s=0.0)
    rec = simulate_latency(scen, seed=2)
    robust = estimate_delay(rec.reference, rec.delayed, rec.sample_period, 2.0)
    assert robust.delay_s == pytest.approx(rec.true_delay[0], abs=0.01)


def test_simulation_is_seeded() -> None:
    a = simulate_latency(seed=5)
    b = simulate_latency(seed=5)
    c = simulate_latency(seed=6)
    np.testing.assert_array_equal(a.delayed, b.delayed)
    assert not np.array_equal(a.delayed, c.delayed)
    assert a.time.size == 5500 and a.sample_period == pytest.approx(0.1)
    kn = a.true_speed / 0.514444
    assert kn.min() >= 110 - 1e-9 and kn.max() <= 170 + 1e-9


def test_whole_method_on_the_paper_scenario() -> None:
    result = run_latency(simulate_latency(seed=0))
    assert abs(result.estimated_delay_s - result.true_delay_s) < 0.010
    assert result.residual_none_s > 0.25
    assert result.residual_fixed_s < result.residual_none_s
    settled = result.segment_true_delay_s - result.total_filtered_s
    assert np.sqrt(np.mean(settled[len(settled) // 2 :] ** 2)) < result.residual_fixed_s
    assert result.segments.costs.shape[1] == 41


def test_segment_variances_are_honest() -> None:
    z = []
    for seed in range(10):
        rec = simulate_latency(seed=seed)
        seg = segment_delays(rec.reference, rec.delayed, rec.segment_length, rec.sample_period, 2.0)
        truth = np.add.reduceat(rec.true_delay, seg.start_index) / np.diff(
            np.append(seg.start_index, rec.true_delay.size)
        )
        ok = np.isfinite(seg.variance_s2)
        z.append((seg.delay_s[ok] - truth[ok]) / np.sqrt(seg.variance_s2[ok]))
    z_all = np.concatenate(z)
    assert 0.6 < np.std(z_all) < 1.6


def test_random_constant_filter_is_the_weighted_mean() -> None:
    rng = np.random.default_rng(0)
    z = rng.normal(0.3, 0.02, size=(4, 12))
    r = np.full(12, 0.02**2)
    est, var = random_constant_kalman(z, r, process_variance=0.0, initial_variance=1.0)
    precision = 1.0 + 12 / r[0]
    expected = (z.sum(axis=-1) / r[0]) / precision
    np.testing.assert_allclose(est[:, -1], expected, rtol=1e-12)
    np.testing.assert_allclose(var[:, -1], 1.0 / precision, rtol=1e-12)


def test_infinite_variance_skips_a_segment() -> None:
    z = np.array([0.3, 9.0, 0.3])
    est, _ = random_constant_kalman(z, np.array([1e-4, np.inf, 1e-4]), 0.0)
    assert est[1] == est[0]
    assert est[2] == pytest.approx(0.3, abs=1e-3)


def test_align_signals_removes_the_delay() -> None:
    rec = simulate_latency(LatencyScenario(**NOISE_FREE), seed=4)
    ref, late = align_signals(rec.true_speed, rec.delayed, rec.true_delay[0], rec.sample_period)
    assert ref.size == late.size == rec.time.size - 3
    np.testing.assert_allclose(ref, late, atol=1e-9)


@pytest.mark.parametrize(
    "make",
    [
        lambda: simulate_latency(LatencyScenario(unknown_delay_s=600.0)),
        lambda: simulate_latency(LatencyScenario(unknown_delay_s=-0.1)),
        lambda: estimate_delay(np.zeros(100), np.zeros(100), 1.0, max_delay=500.0),
        lambda: estimate_delay(np.zeros(100), np.zeros(90)),
        lambda: estimate_delay(np.r_[np.nan, np.zeros(99)], np.zeros(100)),
        lambda: estimate_delay(np.zeros(100), np.zeros(100), sample_period=0.0),
    ],
)
def test_bad_parameters_are_refused(make) -> None:
    with pytest.raises(NoisevarError):
        make()


def test_delay_longer_than_the_record_message() -> None:
    with pytest.raises(NoisevarError, match="longer than this record"):
        estimate_delay(np.arange(100.0), np.arange(100.0), 0.1, max_delay=60.0)
    with pytest.raises(NoisevarError, match="too long"):
        simulate_latency(LatencyScenario(duration_s=10.0, unknown_delay_s=5.0))


def test_minimum_at_search_edge_is_reported() -> None:
    k = np.arange(2000.0)
    signal = np.sin(k / 50.0)
    with pytest.raises(NoisevarError, match="edge"):
        estimate_delay(signal, np.roll(signal, 30), max_delay=5)


def test_experiment_reports_the_issue_metrics() -> None:
    result = EXPERIMENT.run(runs=3, seed=0).to_dict()
    for key in (
        "true_delay_s",
        "estimated_delay_s",
        "residual_delay_none_s",
        "residual_delay_fixed_s",
        "residual_delay_filtered_s",
    ):
        assert np.isfinite(result["metrics"][key])
    assert "latency" in EXPERIMENT.format_table(result)
    with pytest.raises(NoisevarError):
        EXPERIMENT.run(runs=3, seed=0, delay=0.05)


def test_a_delay_is_significant_beyond_half_a_sample_and_two_std() -> None:
    from noisevar.systems.latency import DelayEstimate

    def est(delay: float, variance: float) -> DelayEstimate:
        return DelayEstimate(delay, 0, np.arange(1), np.zeros(1), variance, 100, 0.1)

    assert est(0.3, 0.01).is_significant(0.1)  # 3 samples, 3 std
    assert not est(0.04, 1e-6).is_significant(0.1)  # under half a sample
    assert not est(0.3, 0.04).is_significant(0.1)  # 1.5 std
