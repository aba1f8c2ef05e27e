"""fit_coloured_noise does not depend on units; an unconverged fit is never chosen silently.

Issue 26, class 6: a fractional frequency (about 1e-11) gave ``white`` with two fits
unconverged, and the same data x1e11 gave ``white+ar1``. The fit standardises its input,
so the model, phi and the variances / scale² are the same at every scale.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal

from noisevar.noise_model import fit_coloured_noise
from noisevar.noise_model.coloured import ModelFit, convergence_notes

N = 3000
SCALES = (1e-11, 1.0, 1e6)


def _records() -> dict[str, tuple[np.ndarray, str]]:
    """Seeded records, each with the model BIC should choose at scale 1."""
    rng = np.random.default_rng(26)
    white = rng.normal(0.0, 1.0, N)
    ar = scipy.signal.lfilter([1.0], [1.0, -0.9], rng.normal(0.0, np.sqrt(1 - 0.81), N))
    rw = np.cumsum(rng.normal(0.0, 0.1, N))
    return {
        "white": (white, "white"),
        "white+ar1": (np.sqrt(0.5) * white + ar, "white+ar1"),
        "white+rw": (white + rw, "white+rw"),
        # a counter's fractional frequency: differenced white noise (the record of class 6)
        "differenced": (np.diff(rng.normal(0.0, 1.0, N + 1)), None),
    }


RECORDS = _records()


@pytest.fixture(scope="module", params=list(RECORDS))
def fits_by_scale(request):
    z, expected = RECORDS[request.param]
    return expected, {s: fit_coloured_noise(s * z) for s in SCALES}


def test_same_model_and_parameters_at_every_scale(fits_by_scale) -> None:
    expected, fits = fits_by_scale
    ref = fits[1.0]
    if expected is not None:
        assert ref.model == expected
    for s, f in fits.items():
        assert f.model == ref.model, f"scale {s:g}: {f.model} against {ref.model}"
        assert all(m.converged for m in f.fits), f"scale {s:g}: {f.notes}"
        np.testing.assert_allclose(f.phi, ref.phi, rtol=1e-6)
        assert f.r / s**2 == pytest.approx(ref.r, rel=1e-6)
        np.testing.assert_allclose(np.array(f.q) / s**2, ref.q, rtol=1e-6)
        for m, m_ref in zip(f.fits, ref.fits, strict=True):
            assert m.r / s**2 == pytest.approx(m_ref.r, rel=1e-6)
            # the log-likelihood of data in other units shifts by -n ln(scale)
            assert m.loglik == pytest.approx(m_ref.loglik - N * np.log(s), abs=1e-6 * N)
            assert m.bic - f.fits[0].bic == pytest.approx(m_ref.bic - ref.fits[0].bic, abs=1e-3)


def _fit(name: str, bic: float, converged: bool) -> ModelFit:
    return ModelFit(name, 1.0, None, None, None, -bic / 2, bic, bic, 1, converged)


def test_convergence_notes_say_whether_the_choice_could_change() -> None:
    ok = [_fit("white", 10.0, True), _fit("white+ar1", 12.0, True)]
    assert convergence_notes(ok, ok[0]) == []
    # a loser that did not converge could fit better: the choice could change
    loser = [_fit("white", 10.0, True), _fit("white+ar1", 12.0, False)]
    (note,) = convergence_notes(loser, loser[0])
    assert "white+ar1" in note and "could change" in note
    # the winner did not converge: its parameters are not the maximum, the choice stands
    winner = [_fit("white", 12.0, True), _fit("white+ar1", 10.0, False)]
    (note,) = convergence_notes(winner, winner[1])
    assert "chosen model" in note and "white+ar1" in note and "would not change" in note


def test_an_unconverged_fit_is_reported_on_the_result(monkeypatch) -> None:
    import dataclasses

    from noisevar.noise_model import coloured

    real = coloured._fit_one

    def stuck(y, name):
        fit = real(y, name)
        return dataclasses.replace(fit, converged=False) if name == "white+rw" else fit

    monkeypatch.setattr(coloured, "_fit_one", stuck)
    f = fit_coloured_noise(RECORDS["white+ar1"][0])
    assert f.model == "white+ar1"
    assert f.converged == {"white": True, "white+ar1": True, "white+rw": False}
    assert f.to_dict()["converged"] == f.converged
    assert any("white+rw" in n and "could change" in n for n in f.notes)
