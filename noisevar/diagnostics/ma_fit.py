"""Whether short-memory (MA(q)) noise fits the lags it was fitted on: a derivative filter's
noise does, an oscillation's correlation does not (docs/algorithms.md §E2 *An oscillation
read as differenced*)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_sf

if TYPE_CHECKING:
    from noisevar.diagnostics.whiteness import WhitenessTest

#: Significance at which MA(q) noise is rejected by its own fitted lags: strong evidence
#: only (a derivative filter's noise is the reading kept when in doubt).
MA_FIT_ALPHA = 1e-3


def ma_misfit(w: WhitenessTest, r: NDArray) -> tuple[float, int]:
    """The χ² misfit of MA(q) noise of correlations ``r`` over the lags it is fitted on
    (``1..q+2``, at most those tested), and its degrees of freedom (lags less ``q``).

    Parameters
    ----------
    w : WhitenessTest
        The residual's autocorrelation test the fit was made on.
    r : ndarray, shape (q,)
        The fitted correlations (``w.short_memory``).

    Returns
    -------
    chi2 : float
        ``Σ_k ((acf_k - model_k) / σ_k)²`` over the fitted lags, ``σ_k`` the null's
        standard error (``band / 1.96``).
    dof : int
    """
    lags = min(r.size + 2, w.acf.size)
    sigma = np.where(w.band > 0, w.band / 1.96, np.inf)
    white = float(np.sum(((w.acf - w.expected) / sigma)[:lags] ** 2))
    return w.ma_left(r, lags) * white, lags - r.size


def ma_fits(w: WhitenessTest, r: NDArray) -> bool:
    """Whether MA(q) noise of correlations ``r`` fits the lags it was fitted on.

    Notes
    -----
    A derivative filter's noise (``np.gradient``, a 5-point derivative) is MA(q): ``q``
    correlations fit ``q + 2`` lags to their sampling error (χ² at most 9.6 on 2 degrees
    of freedom over 30 seeded records). An oscillation near a few samples per period (a
    red giant's in Kepler's long cadence: +0.46, -0.18, -0.33, -0.07 at lags 1-4) has
    correlation at every lag that no MA(q) noise reaches: χ² 535 on the Kepler record.
    Rejected at :data:`MA_FIT_ALPHA`.
    """
    chi2, dof = ma_misfit(w, r)
    return dof < 1 or chi2_sf(chi2, dof) >= MA_FIT_ALPHA
