"""A composite model fitted on a copy of the record scaled by an exact power of two, in
the record's units (as :mod:`noisevar.estimators._scale` does for ``estimate``): the
wavelet variance's squares neither overflow nor underflow at any magnitude (issue 29)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators import scale_back, scale_exponent
from noisevar.noise_model.gmwm.model import FilterBias, ImuModel
from noisevar.noise_model.gmwm.processes import PROCESSES


def scaled(rows: NDArray) -> tuple[NDArray, list[int]]:
    """Each row of ``rows`` (axes x time) times ``2**e``
    (:func:`~noisevar.estimators.scale_exponent`, exact), and each row's ``e``; ``rows``
    itself when every ``e`` is 0 (ordinary magnitudes: bit-identical fits)."""
    exps = [scale_exponent(r) for r in rows]
    if not any(exps):
        return rows, exps
    return np.ldexp(rows, np.array(exps)[:, None]), exps


def bias_in_units(bias: FilterBias, e: int) -> FilterBias:
    """``bias`` of the record scaled by ``2**e`` in the record's units (K_eq and the GMs'
    sigmas in its unit; the horizon and the correlation times do not change)."""
    if e == 0:
        return bias
    k = scale_back(bias.random_walk, -e, "K_eq")
    ks = tuple(scale_back(v, -e, "K_eq") for v in bias.interval)
    sigma = tuple(scale_back(v, -e, "GM sigma") for v in bias.gm_sigma)
    return replace(bias, random_walk=k, interval=ks, gm_sigma=sigma)


def internal_in_units(keys: tuple[str, ...], p: NDArray, e: int) -> NDArray:
    """The internal parameters ``p`` of the record scaled by ``2**e`` in the record's units
    (variances: ``2**-2e``; a GM's correlation time in samples does not change)."""
    variance = np.array([name != "tc" for k in keys for name in PROCESSES[k].params])
    out = np.array(p, dtype=float, copy=True)
    out[variance] = scale_back(out[variance], -2 * e, "model variance")
    return out


def checked(fit: ImuModel) -> ImuModel:
    """``fit``, refused when its processes' wavelet variances (``components`` and their sum,
    shown and exported) leave the floating-point range at its scales.

    Raises
    ------
    NoisevarError
        One sentence, as :func:`~noisevar.estimators.scale_back`'s.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        parts = [*fit.components().values(), fit.model_wv()]
    if not all(np.all(np.isfinite(v)) for v in parts):
        raise NoisevarError(
            "the composite model's wavelet variance of this record is larger than the largest "
            "floating-point number at its longest scales: rescale the record (change its "
            "units) first"
        )
    return fit
