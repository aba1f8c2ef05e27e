"""C/N0 sweeps and slip-rate statistics over many paired runs (docs/algorithms.md §B1)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from noisevar.errors import NoisevarError
from noisevar.systems.carrier.run import CarrierResult, compare, comparison_variants
from noisevar.systems.carrier.scenario import METHODS, CarrierScenario


@dataclass(frozen=True)
class CarrierSweep:
    """Filters over a range of C/N0 (same signals for all of them at each C/N0).

    Attributes
    ----------
    cn0_dbhz : ndarray, shape (c,)
    rms_phase_error_rad : dict of str to ndarray, shape (c,)
        Per filter (the names of the variants).
    loss_of_lock : dict of str to ndarray, shape (c,)
        Fraction of runs that slipped, per filter.
    q_rules : dict of str to str
        Per filter, :attr:`CarrierResult.method` and ``q_rule`` as
        ``"ekf/none"``, ``"aekf/paper"``, ... (for labels).
    """

    cn0_dbhz: NDArray[np.float64]
    rms_phase_error_rad: dict[str, NDArray[np.float64]]
    loss_of_lock: dict[str, NDArray[np.float64]]
    q_rules: dict[str, str] = field(default_factory=dict)


def cn0_sweep(
    cn0_dbhz: tuple[float, ...] = (25.0, 30.0, 35.0, 40.0, 45.0),
    runs: int = 100,
    seed: int = 0,
    scenario: CarrierScenario | None = None,
    variants: Mapping[str, Mapping[str, object]] | None = None,
    **kwargs: object,
) -> CarrierSweep:
    """RMS phase error and loss-of-lock of several filters over a C/N0 sweep.

    Parameters
    ----------
    cn0_dbhz : tuple of float
        C/N0 values (dB-Hz).
    runs, seed : int
        Monte Carlo runs per point and seed.
    scenario : CarrierScenario, optional
        Other parameters (its ``cn0_dbhz`` is replaced).
    variants : mapping of str to mapping, optional
        Filters to compare (see :func:`compare`; default the EKF and the
        AEKF with the matched design; :func:`comparison_variants` for the
        nominal-design comparison).
    **kwargs
        Passed to :func:`run_carrier` (``window``, ``jerk_psd``, ...).

    Returns
    -------
    CarrierSweep
    """
    base = scenario or CarrierScenario()
    values = np.asarray(cn0_dbhz, dtype=float)
    names = list(variants or METHODS)
    rms = {m: np.empty(values.size) for m in names}
    lol = {m: np.empty(values.size) for m in names}
    rules: dict[str, str] = {}
    for i, c in enumerate(values):
        scen = CarrierScenario(**{**base.__dict__, "cn0_dbhz": float(c)})
        for m, res in compare(scen, variants, seed=seed, runs=runs, **kwargs).items():
            rms[m][i] = res.rms_phase_error
            lol[m][i] = res.loss_of_lock
            rules[m] = f"{res.label}"
    return CarrierSweep(cn0_dbhz=values, rms_phase_error_rad=rms, loss_of_lock=lol, q_rules=rules)


def wilson_interval(slipped: int, runs: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (here: runs that slipped).

    Unlike the normal (Wald) interval it stays inside ``[0, 1]`` and is not
    empty at 0 slips: with 0 of ``n`` the upper end is about ``3.8 / n``
    at 95 %.

    Parameters
    ----------
    slipped : int
        Runs that slipped.
    runs : int
        Runs in all.
    level : float
        Confidence level.

    Returns
    -------
    tuple of float
        Lower and upper end.
    """
    if runs < 1 or not 0 <= slipped <= runs:
        raise NoisevarError(
            f"{slipped} slips of {runs} runs: need 0 <= slipped <= runs, runs >= 1."
        )
    z = float(stats.norm.ppf(0.5 + level / 2.0))
    p = slipped / runs
    z2n = z * z / runs
    centre = (p + z2n / 2.0) / (1.0 + z2n)
    half = z * np.sqrt(p * (1.0 - p) / runs + z2n / (4.0 * runs)) / (1.0 + z2n)
    lo = 0.0 if slipped == 0 else max(centre - half, 0.0)
    hi = 1.0 if slipped == runs else min(centre + half, 1.0)
    return float(lo), float(hi)


@dataclass(frozen=True)
class SlipRates:
    """Slip counts of several filters on the same runs, over a C/N0 list.

    Attributes
    ----------
    cn0_dbhz : ndarray, shape (c,)
    runs : int
        Runs per C/N0 (the same signals for every filter).
    seed : int
    slipped : dict of str to ndarray of int, shape (c,)
        Runs that slipped, per filter.
    ci95 : dict of str to ndarray, shape (c, 2)
        Wilson 95 % interval of the slipped fraction.
    before_manoeuvre : dict of str to ndarray of int, shape (c,)
        Slipped runs whose first slip came before the first manoeuvre
        starts: the loop had not finished pulling in by ``settle_s``.
    returned : dict of str to ndarray of int, shape (c,)
        Slipped runs whose cycle count at the end is back at its value at
        ``settle_s`` (an excursion past ±π that came back; the rest are
        net slips).
    discordant : dict of str to ndarray of int, shape (c, 2)
        Against the first filter: ``[first slipped and this one not, this
        one slipped and the first not]`` (paired runs).
    p_value : dict of str to ndarray, shape (c,)
        Exact two-sided McNemar test of equal slip rates against the first
        filter (binomial test on the discordant pairs; 1 without any).
    unlocked_at_end : dict of str to ndarray of int, shape (c,)
        Runs whose cycle count still changes in the last second: lock lost
        for good (not re-acquired), or a loop still slipping on noise.
    rms_phase_error_rad : dict of str to ndarray, shape (c,)
        RMS phase error over all runs and steps after ``settle_s``
        (as :attr:`CarrierResult.rms_phase_error`, pooled over chunks).
    """

    cn0_dbhz: NDArray[np.float64]
    runs: int
    seed: int
    slipped: dict[str, NDArray[np.int64]]
    ci95: dict[str, NDArray[np.float64]]
    before_manoeuvre: dict[str, NDArray[np.int64]]
    returned: dict[str, NDArray[np.int64]]
    discordant: dict[str, NDArray[np.int64]]
    p_value: dict[str, NDArray[np.float64]]
    unlocked_at_end: dict[str, NDArray[np.int64]]
    rms_phase_error_rad: dict[str, NDArray[np.float64]]


def slip_rates(
    cn0_dbhz: tuple[float, ...] = (25.0, 30.0, 35.0),
    runs: int = 1000,
    seed: int = 0,
    variants: Mapping[str, Mapping[str, object]] | None = None,
    scenario: CarrierScenario | None = None,
    chunk: int = 1000,
    **kwargs: object,
) -> SlipRates:
    """Slip rates with their uncertainty: many runs, paired across filters.

    A fraction of 100 runs cannot tell 0 slips from 1 %; this counts the
    slipped runs of every filter on the same ``runs`` signals per C/N0
    (simulated ``chunk`` runs at a time, seeds ``seed, seed + 1, ...`` per
    chunk, to bound the memory), with Wilson intervals, and compares each
    filter with the first on the same runs (McNemar).

    Parameters
    ----------
    cn0_dbhz : tuple of float
    runs : int
        Runs per C/N0.
    seed : int
        Seed of the first chunk.
    variants : mapping of str to mapping, optional
        Filters (default: ``ekf`` and ``aekf`` of :func:`comparison_variants`,
        the nominal 45 dB-Hz design); the first is the reference of the
        paired test.
    scenario : CarrierScenario, optional
        Other parameters (its ``cn0_dbhz`` is replaced).
    chunk : int
        Runs simulated at once.
    **kwargs
        Passed to :func:`run_carrier`.

    Returns
    -------
    SlipRates
    """
    if int(runs) != runs or runs < 1 or int(chunk) != chunk or chunk < 1:
        raise NoisevarError(f"runs={runs}, chunk={chunk}: give positive integers.")
    if variants is None:
        both = comparison_variants()
        variants = {"ekf": both["ekf"], "aekf": both["aekf"]}
    names = list(variants)
    base = scenario or CarrierScenario()
    values = np.asarray(cn0_dbhz, dtype=float)
    c = values.size
    slipped = {m: np.zeros(c, dtype=np.int64) for m in names}
    early = {m: np.zeros(c, dtype=np.int64) for m in names}
    back = {m: np.zeros(c, dtype=np.int64) for m in names}
    disc = {m: np.zeros((c, 2), dtype=np.int64) for m in names}
    unlocked = {m: np.zeros(c, dtype=np.int64) for m in names}
    sq = {m: np.zeros((c, 2)) for m in names}  # sum of squared errors, count
    for i, cn0 in enumerate(values):
        scen = CarrierScenario(**{**base.__dict__, "cn0_dbhz": float(cn0)})
        first_manoeuvre = min(scen.manoeuvres_s)
        done, j = 0, 0
        while done < runs:
            b = min(int(chunk), runs - done)
            res = compare(scen, variants, seed=seed + j, runs=b, **kwargs)
            ref = res[names[0]].slipped
            for m in names:
                counts = _slip_counts(res[m], ref, first_manoeuvre, scen.integration_s)
                slipped[m][i] += counts[0]
                early[m][i] += counts[1]
                back[m][i] += counts[2]
                disc[m][i] += counts[3]
                unlocked[m][i] += counts[4]
                sq[m][i] += counts[5]
            done += b
            j += 1
    ci = {m: np.array([wilson_interval(int(k), runs) for k in slipped[m]]) for m in names}
    p = {
        m: np.array(
            [
                stats.binomtest(int(d[1]), int(d.sum()), 0.5).pvalue if d.sum() else 1.0
                for d in disc[m]
            ]
        )
        for m in names
    }
    return SlipRates(
        cn0_dbhz=values,
        runs=int(runs),
        seed=int(seed),
        slipped=slipped,
        ci95=ci,
        before_manoeuvre=early,
        returned=back,
        discordant=disc,
        p_value=p,
        unlocked_at_end=unlocked,
        rms_phase_error_rad={m: np.sqrt(sq[m][:, 0] / sq[m][:, 1]) for m in names},
    )


def _slip_counts(
    r: CarrierResult, ref: NDArray[np.bool_], first_manoeuvre: float, integration_s: float
) -> tuple[int, int, int, list[int], int, list[float]]:
    """One chunk's counts for :func:`slip_rates` (slipped, early, returned, discordant,
    unlocked at the end, [sum of squared errors, count])."""
    s = r.settle_steps
    changed = r.cycles[:, s:] != r.cycles[:, s : s + 1]
    first = np.argmax(changed, axis=1)
    t_first = r.time[np.minimum(s + first, r.time.size - 1)]
    early = int(np.sum(r.slipped & changed.any(axis=1) & (t_first < first_manoeuvre)))
    back = int(np.sum(r.slipped & (r.cycles[:, -1] == r.cycles[:, s])))
    disc = [int(np.sum(ref & ~r.slipped)), int(np.sum(r.slipped & ~ref))]
    last = r.cycles[:, -max(int(round(1.0 / integration_s)), 2) :]
    unlocked = int(np.sum(np.any(last != last[:, :1], axis=1)))
    e = r.phase_error[:, s:]
    sq = [float(np.nansum(e * e)), float(np.sum(np.isfinite(e)))]
    return int(r.slipped.sum()), early, back, disc, unlocked, sq
