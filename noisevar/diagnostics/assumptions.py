"""What estimators assume of the noise, how to read each off the diagnostics, and what a
short record is too short to check."""

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


#: Fewest samples for every check of the verdict: two blocks of the level profile to
#: compare, and a kurtosis that means something (white Gaussian noise read heavy-tailed
#: in 9 % of 64-sample records, 3.5 % of 100-sample ones). Fewer:
#: :func:`~noisevar.diagnostics.verdict.short_verdict`.
SHORT_RECORD = 100
#: Two of the checks :func:`unchecked` names, which assumptions wait for.
WHITENESS, TAILS = "whether the noise is white", "its tails and glitches"
#: The check each assumption waits for (the others are read on any record).
NEEDS = {"white": WHITENESS, "unsmoothed": WHITENESS, "gaussian": TAILS}


def unchecked(n: int, diag: NoiseDiagnostics | None) -> tuple[str, ...]:
    """What a record of ``n`` samples is too short to check (empty: every check was made).

    The one rule of short records: the whiteness test needs
    :data:`~noisevar.diagnostics.whiteness.WHITE_MIN` residuals (``whiteness.tested``);
    level changes, heavy tails and glitches :data:`SHORT_RECORD` samples. ``diag`` None:
    the record was too short to diagnose at all.
    """
    out = []
    if diag is None or not diag.whiteness.tested:
        out.append(WHITENESS)
    if diag is None or n < SHORT_RECORD:
        out += ["whether its level changes (motion, steps)", TAILS]
    return tuple(out)


def check_assumptions(assumes: tuple[str, ...], diag: NoiseDiagnostics) -> dict[str, bool]:
    """Plain description of each assumption in ``assumes`` the record could be checked for
    -> whether the record satisfies it.

    Parameters
    ----------
    assumes : tuple of str
        Keys of :data:`ASSUMPTIONS`.
    diag : NoiseDiagnostics

    Returns
    -------
    dict of str to bool
        An assumption a record is too short to check (:func:`unchecked`) is left out: a
        45-sample record's table read "everything it assumes holds" beside a verdict saying
        it was too short to check whether the noise is white.
    """
    gaps = unchecked(diag.n, diag)
    return {
        ASSUMPTIONS[a][0]: bool(ASSUMPTIONS[a][1](diag))
        for a in assumes
        if NEEDS.get(a) not in gaps
    }
