"""What estimators assume of the noise, and how to read each off the diagnostics."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics

#: Assumption key -> (plain words, test on the diagnostics).
ASSUMPTIONS: dict[str, tuple[str, Callable[[NoiseDiagnostics], bool]]] = {
    "white": ("white noise", lambda d: d.white),
    "gaussian": ("Gaussian tails", lambda d: not d.heavy_tailed),
    "identifiable": (
        "measurement noise that can be told apart from the signal",
        lambda d: d.identifiable,
    ),
    # docs/algorithms.md §E2 *Smoothed outputs*: past a first-order low-pass, the residual
    # sees an unknown share of the noise: no R of the sensor's is measured
    "unsmoothed": (
        "noise no smoother than a sensor's own low-pass leaves it (not a filter's output)",
        lambda d: d.smoothed is None,
    ),
}


def check_assumptions(assumes: tuple[str, ...], diag: NoiseDiagnostics) -> dict[str, bool]:
    """Plain description of each assumption in ``assumes`` -> whether the record satisfies it.

    Parameters
    ----------
    assumes : tuple of str
        Keys of :data:`ASSUMPTIONS`.
    diag : NoiseDiagnostics

    Returns
    -------
    dict of str to bool
    """
    return {ASSUMPTIONS[a][0]: bool(ASSUMPTIONS[a][1](diag)) for a in assumes}
