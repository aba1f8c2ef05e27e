"""The Noise panel's data and figures: shapes, caps, the t overlay, the ACF band."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar import estimate, synth
from noisevar.diagnostics.panel import (
    PANEL_RESIDUALS,
    QQ_POINTS,
    assumption_rows,
    noise_panel_data,
    verdict_severity,
)
from noisevar.errors import NoisevarError
from noisevar.figures.noise import acf_plot, level_profile_plot, qq_plot, residual_histogram

N = 6000


def _record(kind: str, n: int = N, seed: int = 3, **params: float) -> np.ndarray:
    x = np.arange(n)
    return synth.noise(kind, n, rng=seed, **params).values + 5.0 * np.sin(x / 400.0)


@pytest.fixture(scope="module")
def heavy():
    z = _record("student_t", dof=3.0)
    est = estimate(z)
    return z, est, noise_panel_data(z, est.diagnostics)


@pytest.fixture(scope="module")
def gauss():
    z = _record("gauss")
    est = estimate(z)
    return z, est, noise_panel_data(z, est.diagnostics)


def test_shapes_and_unit_scale(gauss):
    _, est, d = gauss
    assert d.bin_edges.size == d.density.size + 1
    assert d.pdf_x.shape == d.normal_pdf.shape == d.t_pdf.shape
    assert d.qq_normal.shape == d.qq_sample.shape == d.qq_t.shape
    assert np.all(np.diff(d.qq_normal) > 0) and np.all(np.diff(d.qq_sample) >= 0)
    # the histogram is a density over every residual
    counted = np.sum(d.density * np.diff(d.bin_edges)) * d.n_residuals + d.outside
    assert counted == pytest.approx(d.n_residuals)
    assert np.mean(d.residuals**2) == pytest.approx(1.0, abs=0.05)
    prof = est.diagnostics.level_profile
    assert d.variance.size == prof.variance.size == d.block_x.size
    assert np.all(d.lo <= d.variance) and np.all(d.variance <= d.hi)
    assert d.quiet_variance == est.diagnostics.quiet_variance
    json.dumps(d.to_dict(), allow_nan=False)


def test_caps_on_a_long_record():
    z = _record("gauss", n=200_000, seed=4)
    est = estimate(z)
    d = noise_panel_data(z, est.diagnostics)
    assert d.n_residuals > PANEL_RESIDUALS
    assert d.residuals.size <= PANEL_RESIDUALS
    assert d.qq_normal.size <= QQ_POINTS
    figs = [residual_histogram(d), qq_plot(d), acf_plot(d), level_profile_plot(d)]
    for fig in figs:
        points = sum(np.size(tr.x) for tr in fig.data if tr.x is not None)
        assert points <= 10_000
        assert len(fig.layout.shapes) <= 2_000
    # the QQ plot keeps the extreme order statistics
    assert d.qq_sample[0] == pytest.approx(np.min(d.qq_sample))
    assert d.qq_sample[-1] == np.max(d.qq_sample)


def test_t_overlay_heavier_on_student_t(heavy, gauss):
    _, _, dh = heavy
    _, _, dg = gauss
    assert dh.t_dof < 8.0
    assert dg.t_dof > 20.0
    # the fitted t puts more density far out than the normal, on the t record
    far = np.abs(dh.pdf_x) > 4.0
    assert np.all(dh.t_pdf[far] > dh.normal_pdf[far])
    # and the sample's extreme quantiles lie beyond the normal's
    assert dh.qq_sample[-1] > 1.5 * dh.qq_normal[-1]


def test_acf_band_matches_whiteness_test(heavy):
    _, est, d = heavy
    w = est.diagnostics.whiteness
    np.testing.assert_array_equal(d.acf, w.acf)
    np.testing.assert_array_equal(d.acf_expected, w.expected)
    np.testing.assert_array_equal(d.acf_band, w.band)
    assert d.white == w.white
    fig = acf_plot(d)
    band = fig.data[0]
    k = d.lags.size
    np.testing.assert_allclose(band.y[:k], w.expected + w.band)
    np.testing.assert_allclose(band.y[k:][::-1], w.expected - w.band)


def test_level_profile_in_times_and_quiet_marked():
    rng = np.random.default_rng(8)
    z = rng.standard_normal(N)
    z[: N // 2] += 20.0 * np.sin(np.arange(N // 2) / 3.0)  # motion in the first half
    t = 100.0 + 0.01 * np.arange(N)
    est = estimate(z, t=t)
    d = noise_panel_data(z, est.diagnostics, t)
    assert d.x_title == "time (s)"
    assert t[0] <= d.block_x.min() and d.block_x.max() <= t[-1]
    assert d.quiet.any() and not d.quiet.all()
    fig = level_profile_plot(d)
    names = [tr.name for tr in fig.data]
    assert "quiet blocks" in names and "other blocks" in names
    line = fig.data[-1]
    assert list(line.y) == [d.quiet_variance] * 2
    assert fig.layout.yaxis.type == "log"


def test_gapped_record_split_at_gaps():
    z = _record("gauss", seed=5)
    z[2000:2300] = np.nan
    est = estimate(z, drop_nonfinite=True)
    zf = z[np.isfinite(z)]
    d = noise_panel_data(zf, est.diagnostics)
    # one residual window less per extra segment
    from noisevar.diagnostics import DIAG_SPAN

    assert d.n_residuals == zf.size - 2 * (DIAG_SPAN - 1)


def test_wrong_record_refused(gauss):
    z, est, _ = gauss
    with pytest.raises(NoisevarError, match="samples"):
        noise_panel_data(z[:-5], est.diagnostics)


def test_histogram_log_axis_and_t_label(heavy):
    _, _, d = heavy
    fig = residual_histogram(d, log_y=True)
    assert fig.layout.yaxis.type == "log"
    assert "Student-t" in fig.data[2].name


def test_severity_and_assumption_rows(heavy, gauss):
    assert verdict_severity(gauss[1].diagnostics) == "ok"
    assert verdict_severity(heavy[1].diagnostics) in {"caution", "warning"}
    ar = estimate(_record("ar1", phi=0.7))
    assert verdict_severity(ar.diagnostics) == "warning"
    rows = assumption_rows([gauss[1], ar])
    assert [r["method"] for r in rows] == [gauss[1].method, ar.method]
    assert rows[0]["fails"] == "-"
    assert "everything it assumes holds" in rows[0]["meaning"]
    assert "white noise" in rows[1]["fails"]
    assert "not a trustworthy R" in rows[1]["meaning"]


def test_histogram_legend_clears_its_axis_title(heavy):
    """The legend sits under the x axis title (issue 28 §8): at the figure's bottom edge in
    pixels, with the x axis keeping its own room above it (the geometry drawn in a browser
    is checked by tests/app/test_browser_pages.py)."""
    fig = residual_histogram(heavy[2])
    legend = fig.layout.legend
    assert (legend.yref, legend.yanchor, legend.y) == ("container", "bottom", 0)
    assert fig.layout.xaxis.automargin is True
