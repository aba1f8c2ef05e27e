"""Window selection (docs/algorithms.md §A5, §A6), envelopes (§A3), the h scan (§A4)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.filters.abg import abg_filter, settling_samples, somd_bias_factor
from noisevar.filters.envelope import RATIO_BAND, envelopes, noise_amplitude, scan_h
from noisevar.filters.selection import WindowSelection, robust_noise_scale, select_windows

M = 40


def _zigzag(m, amp_first, amp_second):
    """Alternating +-a deviations, amplitude a1 in the first half and a2 in the second."""
    sign = np.where(np.arange(m) % 2 == 0, 1.0, -1.0)
    amp = np.where(np.arange(m) < m // 2, amp_first, amp_second)
    return sign * amp


@pytest.fixture
def synthetic_selection():
    """Three windows of hand-made filter outputs with a known verdict each.

    0: smooth output on a straight line with symmetric +-0.1 wiggle, tracking
       output on the same line: passes both tests.
    1: the wiggle is 0.1 in the first half and 0.3 in the second (the smooth
       output is not centred on one line): fails the amplitude test only.
    2: straight line of slope +0.5 for the smooth output while the tracking
       output already turned to slope -0.5 (smooth filter lagging a sharp
       turn): fails the angle test only.
    """
    i = np.arange(1, M + 1, dtype=float)
    smooth = np.concatenate(
        [
            10.0 + 0.5 * i + _zigzag(M, 0.1, 0.1),
            30.0 + 0.5 * i + _zigzag(M, 0.1, 0.3),
            50.0 + 0.5 * i + _zigzag(M, 0.1, 0.1),
        ]
    )
    track = np.concatenate([10.0 + 0.5 * i, 30.0 + 0.5 * i, 50.0 - 0.5 * i])
    rng = np.random.default_rng(0)
    z = smooth + rng.normal(0.0, 1.0, smooth.size)
    return z, smooth, track


# --------------------------------------------------------------------- the two tests
def test_synthetic_windows_verdicts(synthetic_selection):
    z, smooth, track = synthetic_selection
    sel = select_windows(z, smooth, track, window=M, noise_scale=1.0)
    assert isinstance(sel, WindowSelection)
    assert sel.n_windows == 3
    np.testing.assert_array_equal(sel.starts, [0, M, 2 * M])
    np.testing.assert_array_equal(sel.amp_ok, [True, False, True])
    np.testing.assert_array_equal(sel.ang_ok, [True, True, False])
    np.testing.assert_array_equal(sel.kept, [True, False, False])
    # fitted slopes [16]-[17]
    np.testing.assert_allclose(sel.slope_track, [0.5, 0.5, -0.5], rtol=1e-12)
    np.testing.assert_allclose(sel.slope_smooth, 0.5, atol=0.02)
    # the angle of window 2: atan(0.5) - atan(-0.5) = 53.13 degrees
    assert sel.angle_diff_deg[2] == pytest.approx(2 * np.degrees(np.arctan(0.5)), abs=1.5)
    assert sel.angle_diff_deg[0] < 1.0


def test_amplitudes_a1_to_a4(synthetic_selection):
    z, smooth, track = synthetic_selection
    sel = select_windows(z, smooth, track, window=M, noise_scale=1.0)
    a = sel.amplitudes
    assert a.shape == (3, 4)
    # A1, A3 above the line (positive), A2, A4 below (negative) [18]
    assert np.all(a[:, [0, 2]] > 0) and np.all(a[:, [1, 3]] < 0)
    np.testing.assert_allclose(np.abs(a[0]), 0.1, rtol=0.05)
    np.testing.assert_allclose(np.abs(a[1, :2]), 0.1, rtol=0.15)
    np.testing.assert_allclose(np.abs(a[1, 2:]), 0.3, rtol=0.15)


def test_amplitude_threshold_is_strict_open_interval(synthetic_selection):
    z, smooth, track = synthetic_selection
    # window 1: |A2/A3| is about 1/3, so the printed test passes it only once gamma_amp > 2/3
    paper = {"noise_scale": 1.0, "amplitude": "paper"}
    tight = select_windows(z, smooth, track, window=M, gamma_amp=0.6, **paper)
    loose = select_windows(z, smooth, track, window=M, gamma_amp=0.75, **paper)
    assert not tight.amp_ok[1]
    assert loose.amp_ok[1]
    # the symmetric test: max/min about 3 passes once tanh(ln 3) = 0.8 < gamma_amp
    tight = select_windows(z, smooth, track, window=M, gamma_amp=0.75, noise_scale=1.0)
    loose = select_windows(z, smooth, track, window=M, gamma_amp=0.85, noise_scale=1.0)
    assert not tight.amp_ok[1]
    assert loose.amp_ok[1]
    # the angle threshold: window 2's 53 degrees passes at 60, fails at 50
    assert select_windows(z, smooth, track, M, gamma_ang=60.0, noise_scale=1.0).ang_ok[2]
    assert not select_windows(z, smooth, track, M, gamma_ang=50.0, noise_scale=1.0).ang_ok[2]


def test_amplitudes_signs_on_real_filter_outputs():
    g = nv.generate("random-jerk", n=4000, seed=5)
    z = g.measured
    sel = select_windows(z, abg_filter(z, 1.5e-5), abg_filter(z, 4.5e-4), window=M)
    a = sel.amplitudes
    finite = np.isfinite(a)
    assert finite.mean() > 0.95
    assert np.all(a[:, 0][finite[:, 0]] >= 0) and np.all(a[:, 2][finite[:, 2]] >= 0)
    assert np.all(a[:, 1][finite[:, 1]] < 0) and np.all(a[:, 3][finite[:, 3]] < 0)


def _v_shaped(seed=2, n=4000, turn=2020):
    rng = np.random.default_rng(seed)
    k = np.arange(n, dtype=float)
    clean = np.where(k < turn, 0.5 * k, 0.5 * turn - 0.5 * (k - turn))
    return clean + rng.normal(0.0, 1.0, n)


def test_window_on_a_straight_line_passes_and_one_straddling_a_sharp_turn_fails_the_angle_test():
    z = _v_shaped()
    hs, ht = 1.5e-5, 4.5e-4
    skip = settling_samples(ht)
    sel = select_windows(z, abg_filter(z, hs), abg_filter(z, ht), window=M, skip=skip)
    straddling = 2020 // M  # window 50 holds samples 2000..2039, the turn at 2020
    assert not sel.ang_ok[straddling]
    assert sel.angle_diff_deg[straddling] > 10.0
    # every window on the straight stretches, after the transient, passes the angle test
    before = (sel.starts >= skip) & (sel.starts + M < 2020 - 40)
    assert before.sum() > 30
    assert np.all(sel.ang_ok[before])
    assert np.all(sel.angle_diff_deg[before] < 3.0)


def test_kept_is_amp_and_angle_and_in_record():
    z = _v_shaped(seed=3)
    skip = 600
    sel = select_windows(z, abg_filter(z, 1.5e-5), abg_filter(z, 4.5e-4), window=M, skip=skip)
    np.testing.assert_array_equal(sel.kept, sel.amp_ok & sel.ang_ok & sel.in_record)
    np.testing.assert_array_equal(sel.in_record, sel.starts >= skip)
    assert sel.kept.any() and not sel.kept.all()
    assert not sel.kept[sel.starts < skip].any()
    mask = sel.sample_mask(z.size)
    assert mask.sum() == sel.kept.sum() * M
    for s, k in zip(sel.starts, sel.kept, strict=True):
        assert np.all(mask[s : s + M] == k)


def test_rejection_summary_counts():
    z = _v_shaped(seed=4)
    skip = 600
    sel = select_windows(z, abg_filter(z, 1.5e-5), abg_filter(z, 4.5e-4), window=M, skip=skip)
    summary = sel.rejection_summary()
    considered = sel.starts >= skip
    assert summary == {
        "windows": int(considered.sum()),
        "kept": int(sel.kept.sum()),
        "failed_amplitude": int((~sel.amp_ok & considered).sum()),
        "failed_angle": int((~sel.ang_ok & considered).sum()),
    }
    assert summary["failed_angle"] >= 1  # the turn
    assert summary["failed_amplitude"] >= 1
    # a window can fail both, so the failures are at least the rejected ones
    rejected = summary["windows"] - summary["kept"]
    assert summary["failed_amplitude"] + summary["failed_angle"] >= rejected


def test_partial_trailing_window_is_not_a_window():
    z = _v_shaped(n=4015)
    sel = select_windows(z, abg_filter(z, 1.5e-5), abg_filter(z, 4.5e-4), window=M)
    assert sel.n_windows == 4015 // M


def test_unknown_angle_convention_is_refused():
    z = _v_shaped()
    with pytest.raises(NoisevarError, match="angle must be one of"):
        select_windows(z, z, z, window=M, angle="degrees")


# ----------------------------------------------------------------- angle conventions
def test_paper_angle_is_atan_of_raw_slopes_and_scaled_divides_by_noise_scale():
    z = _v_shaped(seed=6) * 3.0
    s, t = abg_filter(z, 1.5e-5), abg_filter(z, 4.5e-4)
    paper = select_windows(z, s, t, window=M, angle="paper")
    scaled = select_windows(z, s, t, window=M, angle="scaled")
    np.testing.assert_allclose(
        paper.angle_diff_deg,
        np.degrees(np.abs(np.arctan(paper.slope_smooth) - np.arctan(paper.slope_track))),
        rtol=1e-12,
    )
    sc = robust_noise_scale(z)
    np.testing.assert_allclose(
        scaled.angle_diff_deg,
        np.degrees(np.abs(np.arctan(paper.slope_smooth / sc) - np.arctan(paper.slope_track / sc))),
        rtol=1e-12,
    )
    np.testing.assert_array_equal(paper.amp_ok, scaled.amp_ok)  # amplitude test is unit-free


@pytest.mark.parametrize(
    ("family", "seed", "method"),
    [("fast-slow", 3, "somd"), ("gps-circle", 1, "somd"), ("random-jerk", 2, "somd-paper")],
)
def test_scaled_angle_makes_the_estimate_scale_free(family, seed, method):
    z = nv.generate(family, n=6000, seed=seed).measured
    base = nv.estimate(z, method=method, angle="scaled")
    big = nv.estimate(z * 1000.0, method=method, angle="scaled")
    small = nv.estimate(z * 1e-3, method=method, angle="scaled")
    assert big.variance == pytest.approx(base.variance * 1e6, rel=1e-9)
    assert small.variance == pytest.approx(base.variance * 1e-6, rel=1e-9)
    np.testing.assert_array_equal(big.details.kept_windows, base.details.kept_windows)


def test_paper_angle_depends_on_the_signal_units():
    """The paper's atan of raw slopes: rescaling the signal changes which windows pass."""
    z = nv.generate("fast-slow", n=6000, seed=3).measured
    base = nv.estimate(z, method="somd", angle="paper")
    big = nv.estimate(z * 1000.0, method="somd", angle="paper")
    assert base.params["angle"] == "paper"
    assert not np.array_equal(base.details.kept_windows, big.details.kept_windows)
    assert big.variance / 1e6 != pytest.approx(base.variance, rel=1e-6)
    # somd-paper defaults to the paper's convention, somd to the scaled one
    assert nv.estimate(z, method="somd-paper").params["angle"] == "paper"
    assert nv.estimate(z, method="somd").params["angle"] == "scaled"


# ---------------------------------------------------------------- robust noise scale
def test_robust_noise_scale_ignores_trends_and_jumps():
    rng = np.random.default_rng(7)
    k = np.arange(20_000, dtype=float)
    w = rng.normal(0.0, 2.0, k.size)
    assert robust_noise_scale(w) == pytest.approx(2.0, rel=0.03)
    trend = 5.0 + 0.3 * k + 1e-4 * k**2 + 50.0 * (k > 7000)
    assert robust_noise_scale(w + trend) == pytest.approx(robust_noise_scale(w), rel=0.01)
    assert robust_noise_scale(7.0 * w) == pytest.approx(7.0 * robust_noise_scale(w), rel=1e-12)
    assert robust_noise_scale(0.3 * k) < 1e-10  # a line has no noise (up to rounding)
    assert robust_noise_scale([1.0, 2.0]) == 0.0


# ---------------------------------------------------------- selection inside estimate
def test_estimate_reports_the_selection_it_used():
    z = nv.generate("fast-slow", n=6000, seed=8).measured
    est = nv.estimate(z, method="somd")
    d = est.details
    sel = d.selection
    assert isinstance(sel, WindowSelection)
    np.testing.assert_array_equal(d.kept_windows, sel.kept)
    assert est.n_used <= int(d.kept_windows.sum()) * M
    assert est.n_used >= int(d.kept_windows.sum()) * M - 1
    assert d.sample_mask.sum() == d.kept_windows.sum() * M
    assert np.all(np.isnan(d.window_variance[~d.kept_windows]))
    assert np.nanmean(d.window_variance) == pytest.approx(est.variance, rel=1e-12)
    assert d.skip == max(settling_samples(1.5e-5), settling_samples(est.params["h_track"]))
    assert d.smooth_output.shape == (1, z.size)
    assert d.bias_factor == (pytest.approx(somd_bias_factor(1.5e-5)),)


def test_several_smoothing_h_keep_a_window_when_any_passes():
    """Spec A6: with several h_S a window counts when any of them passes."""
    z = nv.generate("fast-slow", n=6000, seed=9).measured
    hs = [1e-5, 3e-5, 1e-4]
    ht = 3e-4
    multi = nv.estimate(z, method="somd", h_smooth=hs, h_track=ht)
    singles = [nv.estimate(z, method="somd", h_smooth=h, h_track=ht) for h in hs]
    union = np.logical_or.reduce([s.details.kept_windows for s in singles])
    # the multi-h run waits for its slowest filter to settle before using any window
    starts = np.arange(union.size) * M
    assert multi.details.skip == max(s.details.skip for s in singles)
    union &= starts >= multi.details.skip
    np.testing.assert_array_equal(multi.details.kept_windows, union)
    assert multi.details.kept_windows.sum() > max(s.details.kept_windows.sum() for s in singles)
    assert multi.params["h_smooth"] == hs
    assert multi.details.smooth_output.shape == (3, z.size)


def test_no_window_kept_says_which_test_rejected_how_many_and_what_to_relax():
    z = nv.generate("fast-slow", n=3000, seed=10).measured
    with pytest.raises(NoisevarError) as info:
        nv.estimate(z, method="somd", gamma_amp=0.001)
    msg = str(info.value)
    assert msg.startswith("no window kept")
    assert "failed the amplitude test" in msg and "the angle test" in msg
    assert "gamma_amp=0.001" in msg
    assert re.search(r"of (\d+) windows, \1 failed the amplitude test", msg)
    assert "relax gamma_amp" in msg and "turn selection off" in msg
    # with an impossible angle threshold every window fails the angle test
    with pytest.raises(NoisevarError, match=r"of (\d+) windows, \d+ failed .* and \1 the angle"):
        nv.estimate(z, method="somd", gamma_amp=1.0, gamma_ang=1e-6)


def test_selection_off_uses_every_sample_after_the_transient():
    z = nv.generate("random-jerk", n=5000, seed=11).measured
    est = nv.estimate(z, method="somd", select=False)
    assert est.details.selection is None
    assert est.n_used == z.size - 1 - est.details.skip
    assert est.params["select"] is False


# ------------------------------------------------------------------ envelopes, eq. 13
def test_envelopes_on_a_known_sequence():
    upper, lower = envelopes([0.0, 2.0, 1.0, 3.0, 0.0])
    np.testing.assert_allclose(upper, [0.0, 2.0, 2.5, 3.0, 0.0])
    np.testing.assert_allclose(lower, [0.0, 0.5, 1.0, 0.5, 0.0])
    up, lo = envelopes([1.0, 4.0, 2.0, 5.0, 1.0, 6.0, 0.0])
    np.testing.assert_allclose(up, [1.0, 4.0, 4.5, 5.0, 5.5, 6.0, 0.0])
    np.testing.assert_allclose(lo, [1.0, 1.5, 2.0, 1.5, 1.0, 0.5, 0.0])
    assert np.all(up >= lo)


def test_envelopes_of_short_sequences_are_the_sequence():
    for x in ([], [3.0], [1.0, 2.0]):
        u, lo = envelopes(x)
        np.testing.assert_array_equal(u, x)
        np.testing.assert_array_equal(lo, x)


def test_noise_amplitude_on_white_noise():
    rng = np.random.default_rng(12)
    w = rng.normal(0.0, 1.0, 8000)
    amp = noise_amplitude(w, window=M)
    assert amp.window == M
    assert amp.amplitude.shape == (8000 // M,)
    assert np.all(amp.amplitude > 0)
    assert amp.upper.shape == amp.lower.shape == (8000,)
    assert np.all(amp.upper >= amp.lower)
    # eq. 13 per window
    per_window = (amp.upper - amp.lower).reshape(-1, M).sum(axis=1) / (2 * M)
    np.testing.assert_allclose(amp.amplitude, per_window)
    # scales exactly with sigma (same noise), and about with sigma (fresh noise)
    assert noise_amplitude(3.0 * w, M).mean_amplitude == pytest.approx(
        3.0 * amp.mean_amplitude, rel=1e-12
    )
    other = np.random.default_rng(13).normal(0.0, 3.0, 8000)
    assert noise_amplitude(other, M).mean_amplitude / amp.mean_amplitude == pytest.approx(
        3.0, rel=0.05
    )
    # |V| is a mean half peak-to-peak: of the order of sigma
    assert 0.5 < amp.mean_amplitude < 1.5


def test_noise_amplitude_detrends_each_window():
    rng = np.random.default_rng(14)
    w = rng.normal(0.0, 1.0, 4000)
    k = np.arange(4000, dtype=float)
    assert noise_amplitude(w + 100.0 + 0.7 * k, M).mean_amplitude == pytest.approx(
        noise_amplitude(w, M).mean_amplitude, rel=1e-9
    )


def test_noise_amplitude_bad_input():
    with pytest.raises(NoisevarError, match="at least 4"):
        noise_amplitude(np.arange(100.0), window=3)
    with pytest.raises(NoisevarError, match="fewer samples than one window"):
        noise_amplitude(np.arange(30.0), window=40)


# ---------------------------------------------------------------------- h scan, eq. 14
def test_scan_h_on_white_noise():
    rng = np.random.default_rng(15)
    scan = scan_h(rng.normal(0.0, 1.0, 6000))
    assert scan.h.size == 41
    assert scan.band == RATIO_BAND == (1 / 20, 1 / 10)
    # less smoothing (larger h) lets more noise through: increasing in h
    assert np.all(np.diff(scan.ratio) > 0)
    assert scan.ratio[0] < 0.01 and scan.ratio[-1] > 0.5
    inside = (scan.ratio >= 1 / 20) & (scan.ratio <= 1 / 10)
    assert inside.any()
    assert scan.h_min == scan.h[inside].min() and scan.h_max == scan.h[inside].max()
    assert scan.h_min <= scan.h_chosen <= scan.h_max
    # for white noise the band sits around the paper's smoothing values
    assert 1e-6 < scan.h_min < scan.h_max < 1e-3


def test_scan_h_band_logic_on_a_fast_and_slow_signal():
    z = nv.generate("fast-slow", n=6000, seed=4).measured
    scan = scan_h(z)
    finite = np.isfinite(scan.ratio)
    assert finite.all()
    assert np.mean(np.diff(scan.ratio) > 0) > 0.8  # monotone-ish
    inside = (scan.ratio >= scan.band[0]) & (scan.ratio <= scan.band[1])
    assert np.all((scan.h[inside] >= scan.h_min) & (scan.h[inside] <= scan.h_max))
    centre = np.sqrt(scan.band[0] * scan.band[1])
    best = scan.h[np.argmin(np.abs(np.log(scan.ratio / centre)))]
    assert scan.h_chosen == best
    if inside.any():
        assert scan.h_min <= scan.h_chosen <= scan.h_max
    d = scan.to_dict()
    assert json.loads(json.dumps(d))["h_chosen"] == scan.h_chosen
    assert set(d) == {"h", "ratio", "band", "h_min", "h_max", "h_chosen"}


def test_scan_h_with_a_band_nobody_reaches():
    rng = np.random.default_rng(16)
    scan = scan_h(rng.normal(0.0, 1.0, 3000), h_grid=[1e-6, 1e-5, 1e-4], band=(5.0, 6.0))
    assert np.isnan(scan.h_min) and np.isnan(scan.h_max)
    assert scan.h_chosen == 1e-4  # still the closest to the band


def test_scan_h_bad_input():
    rng = np.random.default_rng(17)
    with pytest.raises(NoisevarError, match="stable range"):
        scan_h(rng.normal(size=2000), h_grid=[1e-5, 0.5])
    with pytest.raises(NoisevarError, match="constant"):
        scan_h(np.ones(2000))


def test_no_window_kept_carries_the_refused_estimate_for_drawing():
    """The error holds every window's tests, equal to running the selection by hand."""
    from noisevar.filters.selection import select_windows

    z = nv.generate("fast-slow", n=3000, seed=10).measured
    with pytest.raises(nv.NoWindowKept) as info:
        nv.estimate(z, method="somd", gamma_amp=0.001, gamma_ang=3.0)
    exc = info.value
    assert isinstance(exc, NoisevarError)
    assert exc.summary["kept"] == 0 and exc.summary["windows"] > 0
    diag = exc.diagnosis
    assert np.isnan(diag.variance) and diag.n_used == 0
    assert diag.params["gamma_amp"] == 0.001 and diag.params["gamma_ang"] == 3.0
    d = diag.details
    ok = nv.estimate(z, method="somd", select=False).details
    np.testing.assert_array_equal(d.smooth_output, ok.smooth_output)
    by_hand = select_windows(z, ok.smooth_output[0], ok.track_output, 40, 0.001, 3.0, skip=d.skip)
    np.testing.assert_array_equal(d.selection.amp_ok, by_hand.amp_ok)
    np.testing.assert_array_equal(d.selection.ang_ok, by_hand.ang_ok)
    assert exc.summary == by_hand.rejection_summary()
    assert not d.kept_windows.any() and np.isnan(d.window_variance).all()


def test_symmetric_amplitude_test_band_and_statistic():
    """Symmetric test: every pair's max/min below sqrt((1+Γ)/(1-Γ)), A4/A1 included."""
    from noisevar.filters.selection import select_windows

    z = nv.generate("fast-slow", n=6000, seed=3).measured
    d = nv.estimate(z, method="somd", select=False).details
    g = 0.3
    sel = select_windows(z, d.smooth_output[0], d.track_output, 40, g, 90.0, skip=d.skip)
    paper = select_windows(
        z, d.smooth_output[0], d.track_output, 40, g, 90.0, skip=d.skip, amplitude="paper"
    )
    a = np.abs(sel.amplitudes)
    pairs = np.stack([a[:, [0, 1, 2, 3]], a[:, [1, 2, 3, 0]]])
    rho = pairs.max(axis=0) / pairs.min(axis=0)
    expected = np.all(rho < np.sqrt((1 + g) / (1 - g)), axis=1)
    np.testing.assert_array_equal(sel.amp_ok, expected)
    np.testing.assert_allclose(sel.amplitude_deviation, np.tanh(np.log(rho)).max(axis=1))
    assert sel.amplitude_ratios().shape[1] == 4 and paper.amplitude_ratios().shape[1] == 3
    r = paper.amplitude_ratios()
    np.testing.assert_array_equal(paper.amp_ok, np.all((r > 1 - g) & (r < 1 + g), axis=1))
    assert 0 < sel.amp_ok.sum() < sel.n_windows and not np.array_equal(sel.amp_ok, paper.amp_ok)
    with pytest.raises(NoisevarError, match="amplitude must be one of"):
        select_windows(z, d.smooth_output[0], d.track_output, 40, g, 90.0, amplitude="x")
