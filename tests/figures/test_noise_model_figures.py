"""The Allan-deviation figure: band, guides, terms, sum and a simulated overlay."""

from __future__ import annotations

from figure_checks import axis_titles, trace_names

from noisevar.figures.noise_model import allan_figure
from noisevar.noise_model import allan, inertial_noise
from noisevar.noise_model.simulate import simulate_inertial


def test_allan_figure_with_fit_and_simulation() -> None:
    y = simulate_inertial(20_000, 50.0, random_walk=1e-3, rate_random_walk=1e-3, seed=1)
    fit = inertial_noise(y, 50.0, unit="rad/s")
    sim = allan(simulate_inertial(20_000, 50.0, random_walk=1e-3, seed=2), 50.0, data="rate")
    fig = allan_figure(fit.allan, fit=fit, simulated=sim, unit="rad/s")
    names = trace_names(fig)
    assert names.count("slope guides") == 5
    assert "overlapping ADEV" in names and "sum" in names and "simulated from the fit" in names
    assert any(n and n.startswith("N = ") for n in names)
    assert axis_titles(fig) == {"xaxis": "τ (s)", "yaxis": "σ(τ) (rad/s)"}
    assert fig.layout.xaxis.type == fig.layout.yaxis.type == "log"
    assert fig.layout.xaxis.dtick == 1 and fig.layout.xaxis.exponentformat == "power"
    # labelled for what is drawn: the slope guides span decades beyond σ (an ISMN station's
    # axis labelled 0.005-0.05 only, under guides from 1e-4 to 0.3)
    assert fig.layout.yaxis.dtick == 1 and fig.layout.yaxis.exponentformat == "power"


def test_a_short_records_allan_axes_carry_more_than_one_label() -> None:
    """45 samples of an ArduPilot log (pymavlink's test.BIN): τ from 0.02 to 0.3 s read
    only "10⁻¹" (the decades alone), σ(τ) only "1" of a power of ten."""
    res = allan(simulate_inertial(45, 50.0, random_walk=1e-2, seed=3), 50.0, data="rate")
    fig = allan_figure(res)
    for axis in (fig.layout.xaxis, fig.layout.yaxis):
        assert axis.type == "log" and len(axis.tickvals) >= 2


def test_allan_figure_of_data_only() -> None:
    res = allan(simulate_inertial(5000, 1.0, random_walk=1.0, seed=0), data="rate", kind="mdev")
    names = trace_names(allan_figure(res, title=None))
    assert "MDEV" in names and "sum" not in names
