"""Figures of a tuned filter: NIS with its band, innovation ACF, model comparison."""

from __future__ import annotations

import numpy as np
import scipy.signal

from noisevar.figures.kalman_tuning import (
    innovation_acf_figure,
    model_comparison_figure,
    nis_figure,
    tuned_run_figure,
)
from noisevar.kalman.divergence import nis_band
from noisevar.noise_model import fit_coloured_noise, fit_kalman, run_tuned


def test_tuning_figures(make_track):
    z = make_track("cv", 3000, 10.0, 1.0, 1.0, seed=9)
    t = fit_kalman(z, "cv", rate=10.0)
    run = run_tuned(t, z)
    fig = nis_figure(run, dt=t.dt, window=50)
    band = fig.layout.shapes[0]
    assert (band.y0, band.y1) == nis_band(1, 50)
    assert np.isnan(fig.data[0].y[: t.start]).all() and len(fig.data) == 2
    assert fig.layout.yaxis.exponentformat == "power"  # labelled as figures.budget.log_axis
    rec = tuned_run_figure(run, z, dt=t.dt)
    assert np.allclose(rec.data[1].y[t.start :], run.states[:, 0])
    acf = innovation_acf_figure(run, lags=30)
    assert len(acf.data[0].y) == 30 and abs(acf.layout.shapes[0].y1 - 1.96 / np.sqrt(2998)) < 1e-3


def test_model_comparison_figure():
    rng = np.random.default_rng(0)
    z = scipy.signal.lfilter([1], [1, -0.8], rng.normal(size=3000)) + rng.normal(size=3000)
    f = fit_coloured_noise(z)
    fig = model_comparison_figure(f)
    bic = dict(zip(fig.data[0].x, fig.data[0].y, strict=True))
    assert bic[f.model] == 0.0 and min(bic.values()) == 0.0 and len(bic) == 3


def test_tuning_table_gain_and_p_use_one_formatter(make_track):
    """q, r, h at the same digits; every gain named; one spelling of a tiny p (issue 28 §8)."""
    from noisevar.figures.kalman_tuning import tuning_rows
    from noisevar.format import eng, pvalue
    from noisevar.noise_model.export import gain_text

    z = make_track("cv", 3000, 10.0, 1.0, 1.0, seed=9)
    t = fit_kalman(z, "cv", rate=10.0)
    row = tuning_rows({"cv": t})[0]
    assert (row["q"], row["r"], row["h"]) == (eng(t.q), eng(t.r), eng(t.h))
    text = gain_text(t)
    assert text.startswith("level ") and ", rate " in text and len(np.ravel(t.gain)) == 2
    assert pvalue(2.04e-299) == "p < 0.0001" and pvalue(0.03123) == "p = 0.0312"
