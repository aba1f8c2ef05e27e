"""Real noise: heavy tails, coloured noise, quantisation, gaps, real records and an IMU (issue 13).

    python benchmarks/real_noise.py                # 400 runs per family, about 5 minutes
    python benchmarks/real_noise.py --quick        # 40 runs, no state-space MLE
    python benchmarks/real_noise.py --runs 200
    python benchmarks/real_noise.py --families quantised   # only families whose name has it

Synthetic families (n = 6000): a smooth signal (the ``noise-step`` family's clean signal,
amplitude about 200) plus noise of standard deviation 5 drawn by :mod:`noisevar.synth`; the
Gaussian families are ``benchmarks/accuracy.py``'s, with its seeds, so that their runs are
paired with the ``auto`` runs of ``results/accuracy.json`` (the "before" column). For each
family: bias and RMSE of ``.variance`` relative to the variance it should match (the
``synth`` docstring says which), ci95 coverage of that variance, the rate of
``diagnostics.white``, of ``diagnostics.lsb`` equal to the grid step, ``core_variance`` and
``outlier_fraction``, each against the issue's target with PASS/FAIL.

Real records nobody here wrote (``_refdata``: allantools' sdist, the scikit-kinematics
wheel): the references are computed here, not copied: ADEV(τ0)/√3 with ``allantools.adev``
(white phase noise of variance σ² gives σ_y(τ0) = √3 σ / τ0) and the maximum-likelihood
local-level model (random walk plus white noise) of ``statsmodels``' ``UnobservedComponents``.

IMU: the NGIMU ``sensors.csv`` (6 channels: gyroscope in deg/s, accelerometer in g,
about 50 Hz; the Xsens record has no still stretch of 1 s). The issue's reference is the
variance "measured on hand-picked still stretches": :data:`HAND_PICKED`, picked by eye on
a plot of all six channels (motion in the first 3.5 s; then the board lies still but for
a tap near 6.1 s and a wobble at 6.6-7.1 s, up to 6σ on gyroscope X and seen at the same
moment on gyroscope Y and accelerometer Z). The variance of each channel is pooled about a
straight line fitted in each stretch (a line removes slow drift and tilt, which are not
sensor noise), shown with its own 95 % interval, with quiet_variance over each stretch
alone and over the stretches a rule finds (:func:`still_stretches`: the gyroscope norm
under 1.5 deg/s over a centred 0.5 s window, for at least 1 s; it lets the wobble in).
``--parts imu`` prints only this table.

The "before" column reads ``results/accuracy.json``: run this benchmark before regenerating
that file, or the comparison is of the new code with itself.

Speed: ``auto`` (with its diagnostics) per 1e6 samples against one third-order ``lfilter``
pass, timed beside each other as in ``benchmarks/speed.py``.

Written against the issue-13 interface with ``getattr`` so that it also runs on the code
before it (then the diagnostic columns read "—" and their targets FAIL).
"""

from __future__ import annotations

import argparse
import io
import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy import signal

import noisevar
from noisevar import synth
from noisevar.errors import NoisevarError

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _refdata  # noqa: E402
from accuracy import FAMILIES as GAUSSIAN_FAMILIES  # noqa: E402
from speed import _best_time_beside  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
N = 6000
STD = 5.0
CLEAN = noisevar.generate("noise-step", n=N).clean
#: Seeds of benchmarks/accuracy.py: family ``i`` at n uses ``1 + 100000 i + n``, run j adds j.
ACCURACY_SEED = 1
#: Words that show a note, or verdict, about a subject (searched lower-case).
WORDS = {
    "interval": ("interval", "unreliable"),
    "colour": ("colour", "color", "correlat", "not white", "flicker", "walk"),
    "glitch": ("glitch", "outlier", "spike", "first sample", "sample 0"),
}


# ---------------------------------------------------------------- one estimate
def _attr(obj, name: str):
    return None if obj is None else getattr(obj, name, None)


def record(est) -> dict:
    """What the benchmark reads from one estimate (None where the interface lacks it)."""
    diag = _attr(est, "diagnostics")
    flags = _attr(diag, "flags") or {}
    return {
        "diag": diag is not None,
        "variance": float(est.variance),
        "ci95": (float(est.ci95[0]), float(est.ci95[1])),
        "core": _attr(est, "core_variance"),
        "outliers": _attr(est, "outlier_fraction"),
        "white": _attr(diag, "white"),
        "lsb": _attr(diag, "lsb"),
        "quiet": _attr(diag, "quiet_variance"),
        "identifiable": flags.get("identifiable"),
        "verdict": _attr(diag, "verdict") or "",
        "notes": [*est.notes, *(_attr(diag, "notes") or ())],
    }


def run_estimates(z: NDArray, t: NDArray | None, kw: dict) -> list[dict]:
    """``auto`` on every row of ``z``; rows with their own times (2-D ``t``) one at a time."""
    try:
        if t is not None and t.ndim == 2:
            return [record(noisevar.estimate(zi, t=ti, **kw)) for zi, ti in zip(z, t, strict=True)]
        return [record(e) for e in noisevar.estimate(z, t=t, **kw)]
    except NoisevarError as exc:
        return [{"error": str(exc)}] * len(z)


def mentions(rec: dict, subject: str) -> bool:
    """Does a note or the verdict speak of ``subject`` (a key of ``WORDS``)?"""
    text = " ".join([rec.get("verdict", ""), *rec.get("notes", [])]).lower()
    return any(w in text for w in WORDS[subject])


# ---------------------------------------------------------------- families
@dataclass
class Batch:
    """Records of one family and what each estimate is compared with."""

    z: NDArray
    truth: NDArray
    t: NDArray | None = None
    core: float | None = None
    lsb: float | None = None
    kw: dict = field(default_factory=dict)
    before: NDArray | None = None


@dataclass
class Family:
    """A synthetic family: its records and its targets."""

    name: str
    group: str
    make: Callable[[int, int], Batch]
    checks: tuple


def _synth(kind: str, **params) -> Callable[[int, int], Batch]:
    def make(runs: int, seed: int) -> Batch:
        kw = params if kind == "flicker" else {"std": STD, **params}
        d = synth.noise(kind, N, seed, runs=runs, **kw)
        return Batch(CLEAN + d.values, np.full(runs, d.variance), core=d.core_variance)

    return make


def _gaussian(family: str, index: int) -> Callable[[int, int], Batch]:
    def make(runs: int, seed: int) -> Batch:
        base = ACCURACY_SEED + 100_000 * index + N
        gs = [noisevar.generate(family, n=N, seed=base + i) for i in range(runs)]
        return Batch(
            np.stack([g.measured for g in gs]),
            np.array([g.true_variance for g in gs]),
            before=_accuracy_errors(family, runs),
        )

    return make


def _accuracy_errors(family: str, runs: int) -> NDArray | None:
    """``auto``'s relative errors on the same runs, from ``results/accuracy.json``."""
    import json

    path = RESULTS / "accuracy.json"
    if not path.exists():
        return None
    for c in json.loads(path.read_text())["cells"]:
        if (c["method"], c["family"], c["n"]) == ("auto", family, N) and len(c["errors"]) >= runs:
            return np.asarray(c["errors"][:runs], dtype=float)
    return None


def _quantised(q: float) -> Callable[[int, int], Batch]:
    def make(runs: int, seed: int) -> Batch:
        d = synth.noise("gauss", N, seed, runs=runs, std=STD)
        lsb = STD / q
        zq, var = synth.quantise(CLEAN + d.values, lsb, d.variance, clean=CLEAN)
        return Batch(zq, np.full(runs, var), lsb=lsb)

    return make


def _gapped(form: str) -> Callable[[int, int], Batch]:
    def make(runs: int, seed: int) -> Batch:
        rng = np.random.default_rng(seed)
        d = synth.noise("gauss", N, rng, runs=runs, std=STD)
        gaps = [synth.remove_blocks(CLEAN + row, rng, fraction=0.05, blocks=10) for row in d.values]
        truth = np.full(runs, d.variance)
        if form == "times":
            return Batch(np.stack([g.values for g in gaps]), truth, np.stack([g.t for g in gaps]))
        if form == "nan":
            z = np.where(np.stack([g.keep for g in gaps]), CLEAN + d.values, np.nan)
            return Batch(z, truth, np.arange(N, dtype=float), kw={"drop_nonfinite": True})
        return Batch(np.stack([g.values for g in gaps]), truth)

    return make


# ---------------------------------------------------------------- checks
def _fmt(x: float | None, digits: int = 1) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{100 * x:+.{digits}f} %"


def abs_within(key: str, label: str, limit: float):
    """Check ``|s[key]| <= limit``."""

    def check(s: dict) -> tuple[str, bool]:
        return f"{label} ≤ {100 * limit:g} %", s[key] is not None and abs(s[key]) <= limit

    return check


def rate_between(key: str, label: str, lo: float, hi: float = 1.0):
    """Check ``lo <= s[key] <= hi``."""

    def check(s: dict) -> tuple[str, bool]:
        text = f"{label} {100 * lo:g}-{100 * hi:g} %" if hi < 1 else f"{label} ≥ {100 * lo:g} %"
        return text, s[key] is not None and lo <= s[key] <= hi

    return check


def no_worse_than_before(s: dict) -> tuple[str, bool]:
    """Paired with accuracy.json's runs: |bias| up at most 0.1 point, RMSE at most 2 %."""
    text = "bias, RMSE no worse than before (paired runs)"
    if s["before_rmse"] is None or s["bias"] is None:
        return text + " (none in accuracy.json)", False
    ok = abs(s["bias"]) <= abs(s["before_bias"]) + 0.001 and s["rmse"] <= 1.02 * s["before_rmse"]
    return text, bool(ok)


def bias_within(limit: float):
    return abs_within("bias", "|bias|", limit)


HEAVY = (bias_within(0.02), rate_between("coverage", "coverage", 0.90, 0.98))
COLOURED = (
    rate_between("not_white", "white False", 0.95),
    rate_between("colour", "verdict names the colour", 0.95),
)
QUANTISED = (rate_between("lsb_exact", "lsb exact", 0.95), bias_within(0.01))
GAPS = (bias_within(0.01), rate_between("coverage", "coverage", 0.90))


def families() -> list[Family]:
    """Every synthetic family with its targets (issue 13's, and two of ours marked so)."""
    out = [
        Family("student-t 5 dof", "heavy tails", _synth("student_t", dof=5.0), HEAVY),
        Family("laplace", "heavy tails", _synth("laplace"), HEAVY),
        Family(
            "1 % at 10x std",
            "heavy tails",
            _synth("contaminated", fraction=0.01, factor=10.0),
            (
                *HEAVY,
                abs_within("core_bias", "core |bias| (ours)", 0.05),
                rate_between("outliers", "outlier_fraction (ours)", 0.005, 0.02),
            ),
        ),
        Family(
            "student-t 3 dof",
            "heavy tails",
            _synth("student_t", dof=3.0),
            (bias_within(0.05), rate_between("interval", "note on the interval", 0.95)),
        ),
    ]
    white = (no_worse_than_before, rate_between("white", "white", 0.93, 0.97))
    out += [Family(f, "gaussian", _gaussian(f, i), white) for i, f in enumerate(GAUSSIAN_FAMILIES)]
    out += [
        Family("AR(1) φ 0.3", "coloured", _synth("ar1", phi=0.3), COLOURED),
        Family("AR(1) φ 0.7", "coloured", _synth("ar1", phi=0.7), COLOURED),
        Family("flicker", "coloured", _synth("flicker", qd=STD**2), COLOURED),
        Family("white + flicker", "coloured", _synth("white+flicker", ratio=1.0), COLOURED),
        Family("white + RW", "coloured", _synth("white+rw", ratio=1.0), COLOURED),
    ]
    out += [
        Family(f"quantised σ {q:g} LSB", "quantised", _quantised(q), QUANTISED)
        for q in (0.2, 0.5, 1.0, 3.0)
    ]
    out += [
        Family("5 % gaps, times given", "gaps", _gapped("times"), GAPS),
        Family("5 % gaps as NaN, drop_nonfinite", "gaps", _gapped("nan"), GAPS),
        Family("5 % gaps spliced, no times", "gaps", _gapped("spliced"), ()),
    ]
    # last, so that the families before it keep their seeds
    out.append(Family("quantised σ 0.3 LSB", "quantised", _quantised(0.3), QUANTISED))
    return out


def _lsb_exact(rec: dict, lsb: float) -> bool | None:
    """Did the diagnostics find the grid step ``lsb`` (None: no diagnostics)?"""
    return (
        None if not rec["diag"] else rec["lsb"] is not None and abs(rec["lsb"] - lsb) <= 1e-6 * lsb
    )


def summarise(recs: list[dict], b: Batch) -> dict:
    """Bias, RMSE, coverage and the diagnostic rates of one family."""
    ok = [i for i, r in enumerate(recs) if "error" not in r]
    s: dict = {"runs": len(recs), "refused": len(recs) - len(ok), "records": recs}
    s["error"] = next((r["error"] for r in recs if "error" in r), None)
    v = np.array([recs[i]["variance"] for i in ok])
    truth = b.truth[ok]
    err = v / truth - 1.0 if ok else np.array([])
    s["bias"] = float(np.mean(err)) if ok else None
    s["rmse"] = float(np.sqrt(np.mean(err**2))) if ok else None
    lo_hi = np.array([recs[i]["ci95"] for i in ok]).reshape(-1, 2)
    s["coverage"] = float(np.mean((lo_hi[:, 0] <= truth) & (truth <= lo_hi[:, 1]))) if ok else None

    def rate(f) -> float | None:
        vals = [f(recs[i]) for i in ok]
        vals = [x for x in vals if x is not None]
        return float(np.mean(vals)) if vals and len(vals) == len(ok) else None

    s["white"] = rate(lambda r: r["white"])
    s["not_white"] = None if s["white"] is None else 1.0 - s["white"]
    s["lsb_exact"] = None if b.lsb is None else rate(lambda r: _lsb_exact(r, b.lsb))
    s["interval"] = float(np.mean([mentions(recs[i], "interval") for i in ok])) if ok else None
    s["colour"] = float(np.mean([mentions(recs[i], "colour") for i in ok])) if ok else None
    core = [recs[i]["core"] for i in ok if recs[i]["core"] is not None]
    s["core_bias"] = float(np.mean(core) / b.core - 1.0) if core and b.core else None
    out = [recs[i]["outliers"] for i in ok if recs[i]["outliers"] is not None]
    s["outliers"] = float(np.mean(out)) if out else None
    s["before_bias"] = None if b.before is None else float(np.mean(b.before))
    s["before_rmse"] = None if b.before is None else float(np.sqrt(np.mean(b.before**2)))
    return s


def run_family(fam: Family, runs: int, seed: int) -> dict:
    """Draw, estimate and summarise one family; the checks' verdicts included."""
    b = fam.make(runs, seed)
    t0 = time.perf_counter()
    s = summarise(run_estimates(b.z, b.t, b.kw), b)
    s["seconds"] = time.perf_counter() - t0
    s["checks"] = [c(s) for c in fam.checks]
    return s


# ---------------------------------------------------------------- real records
def mle_local_level(x: NDArray) -> float:
    """σ of the white part of the maximum-likelihood local-level model (statsmodels)."""
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    scale = float(np.std(x))
    fit = UnobservedComponents((x - np.mean(x)) / scale, level="llevel").fit(disp=False)
    return float(np.sqrt(fit.params[0]) * scale)


def adev_sigma(x: NDArray) -> float:
    """ADEV(τ0)/√3 of a phase record, in its units (white phase noise: σ_y(τ0) = √3 σ/τ0)."""
    import allantools

    _, ad, _, _ = allantools.adev(x, rate=1.0, data_type="phase", taus=[1.0])
    return float(ad[0] / np.sqrt(3.0))


def real_record(name: str, with_mle: bool) -> dict:
    """``auto`` on one allantools record with its computed references and target."""
    x = _refdata.allantools_record(name)
    clean = x[1:] if name == "cs5071a" else x  # the Cs record's first sample is a glitch
    # as issue 13 states them: ADEV on the whole record, the MLE without the glitch
    rec = record(noisevar.estimate(x))
    row = {"name": name, "n": x.size, "rec": rec, "sigma": float(np.sqrt(rec["variance"]))}
    row["adev"] = adev_sigma(x)
    row["mle"] = mle_local_level(clean) if with_mle else None
    s, a, m = row["sigma"], row["adev"], row["mle"]
    if name in ("keysight_tic", "gps_1pps"):
        row["target"], row["ok"] = "σ within 3 % of ADEV(τ0)/√3", abs(s / a - 1.0) <= 0.03
    if name == "gps_1pps":
        says = rec["white"] is False and "flicker" in rec["verdict"].lower()
        row["target"] += "; white False, verdict says flicker"
        row["ok"] = row["ok"] and says
    if name == "cs5071a":
        refs = [a] if m is None else [a, m]
        inside = 0.98 * min(refs) <= s <= 1.02 * max(refs)
        found = mentions(rec, "glitch") or bool(rec["outliers"])
        row["target"] = "σ between MLE and ADEV(τ0)/√3 within 2 %; the glitch reported"
        row["ok"] = inside and found
    if name == "phase_dat":
        row["target"] = "flagged: noise not identifiable (flags['identifiable'] False)"
        row["ok"] = rec["identifiable"] is False
    return row


#: Still stretches of the NGIMU record picked by eye, in seconds (module docstring); the
#: second starts once the wobble after the tap has died out (7.2 to 7.5 s move every ratio
#: by under 0.03).
HAND_PICKED = ((3.85, 5.87), (7.30, 9.98))


def still_stretches(gyro_norm: NDArray, rate: float) -> list[tuple[int, int]]:
    """Runs of >= 1 s where the gyroscope norm stays under 1.5 deg/s over a centred 0.5 s."""
    half = int(round(0.25 * rate))
    padded = np.pad(gyro_norm, half, mode="edge")
    local_max = np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1).max(axis=1)
    still = np.concatenate([[False], local_max < 1.5, [False]])
    edges = np.flatnonzero(np.diff(still.astype(int)))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True) if b - a >= rate]


def _stretch_residuals(x: NDArray, stretches: list[tuple[int, int]]) -> list[NDArray]:
    """Each stretch's residual about a straight line fitted in it."""
    out = []
    for a, b in stretches:
        k = np.arange(b - a)
        out.append(x[a:b] - np.polyval(np.polyfit(k, x[a:b], 1), k))
    return out


def stretch_variance(x: NDArray, stretches: list[tuple[int, int]]) -> float:
    """Pooled variance about a straight line fitted in each stretch."""
    resid = _stretch_residuals(x, stretches)
    return sum(float(r @ r) for r in resid) / sum(r.size - 2 for r in resid)


def stretch_interval(x: NDArray, stretches: list[tuple[int, int]]) -> tuple[float, float]:
    """95 % interval of :func:`stretch_variance` as a χ² on ``ν = 2 dof / (κ - 1)`` dof.

    ``κ`` is the residuals' kurtosis (3 for Gaussian noise: ``ν = dof``); a variance of
    ``ν`` dof has relative variance ``2 / ν = (κ - 1) / dof``.
    """
    from scipy import stats

    resid = np.concatenate(_stretch_residuals(x, stretches))
    dof = resid.size - 2 * len(stretches)
    nu = 2.0 * dof / (float(stats.kurtosis(resid, fisher=False)) - 1.0)
    v = stretch_variance(x, stretches)
    return v * nu / float(stats.chi2.ppf(0.975, nu)), v * nu / float(stats.chi2.ppf(0.025, nu))


def imu_rows() -> tuple[list[dict], list[tuple[int, int]], list[tuple[int, int]], NDArray]:
    """Per channel of the NGIMU record: quiet_variance and .variance against still stretches.

    Returns the rows, the hand-picked and the rule's stretches (sample ranges) and the times.
    """
    import pandas as pd

    df = pd.read_csv(io.BytesIO(_refdata.skinematics_file("tests/data/data_ngimu/sensors.csv")))
    rate = 1.0 / float(np.median(np.diff(df.iloc[:, 0])))
    channels = [c for c in df.columns if c.startswith(("Gyroscope", "Accelerometer"))]
    gyro = df[[c for c in channels if c.startswith("Gyroscope")]].to_numpy()
    t = df.iloc[:, 0].to_numpy(dtype=float)
    stretches = [
        (int(np.searchsorted(t, a)), int(np.searchsorted(t, b, side="right")))
        for a, b in HAND_PICKED
    ]
    rule = still_stretches(np.sqrt((gyro**2).sum(axis=1)), rate)
    rows = []
    for c in channels:
        x = df[c].to_numpy(dtype=float)
        rec = record(noisevar.estimate(x))
        ref = stretch_variance(x, stretches)
        each = [stretch_variance(x, [s]) for s in stretches]
        q = rec["quiet"]
        ok = q is not None and abs(q / ref - 1.0) <= 0.25
        rows.append(
            {"channel": c, "ref": ref, "ci": stretch_interval(x, stretches), "each": each,
             "rule": stretch_variance(x, rule), "rec": rec, "ok": ok}
        )  # fmt: skip
    return rows, stretches, rule, t


def speed(n: int = 1_000_000, repeats: int = 5) -> tuple[float, float, float, float]:
    """Seconds of ``auto`` per 1e6 samples and its ratio to one lfilter pass beside it.

    ``noisevar.estimate`` runs a record this long in chunks on two threads (§F5.7); the
    last two values are the same on one thread (``estimate_chunked(workers=1)``).
    """
    from noisevar.stream import estimate_chunked

    z = noisevar.generate("gps-circle", n=n, seed=3).measured
    b, a = signal.butter(3, 0.05)
    noisevar.estimate(z)  # warm caches
    t, t_ref, *_ = _best_time_beside(
        lambda: noisevar.estimate(z), lambda: signal.lfilter(b, a, z), repeats
    )
    one, one_ref, *_ = _best_time_beside(
        lambda: estimate_chunked(lambda i, j: z[max(i, 0) : j], n, probe=z.__getitem__,
                                 workers=1),
        lambda: signal.lfilter(b, a, z), repeats,
    )  # fmt: skip
    return t * 1e6 / n, t / t_ref, one * 1e6 / n, one / one_ref


# ---------------------------------------------------------------- report
def _rate(x: float | None) -> str:
    return "—" if x is None else f"{100 * x:.1f} %"


def _mark(ok: bool) -> str:
    return "PASS" if ok else "FAIL"


def family_table(fams: list[Family], stats: list[dict]) -> list[str]:
    """One row per synthetic family."""
    lines = [
        "| family | group | bias | RMSE | before: bias / RMSE | ci95 coverage | white | "
        "lsb exact | core bias | outlier fraction | targets | result |",
        "|---" * 12 + "|",
    ]
    for fam, s in zip(fams, stats, strict=True):
        before = (
            "—"
            if s["before_rmse"] is None
            else f"{_fmt(s['before_bias'], digits=2)} / {100 * s['before_rmse']:.2f} %"
        )
        rmse = "—" if s["rmse"] is None else f"{100 * s['rmse']:.2f} %"
        targets = "; ".join(f"{t} {'✓' if ok else '✗'}" for t, ok in s["checks"]) or "none (shown)"
        result = "—" if not s["checks"] else _mark(all(ok for _, ok in s["checks"]))
        if s["refused"]:
            rmse += f" ({s['refused']} refused)"
        lines.append(
            f"| {fam.name} | {fam.group} | {_fmt(s['bias'], digits=2)} | {rmse} | {before} | "
            f"{_rate(s['coverage'])} | {_rate(s['white'])} | {_rate(s['lsb_exact'])} | "
            f"{_fmt(s['core_bias'])} | {_rate(s['outliers'])} | {targets} | {result} |"
        )
    return lines


def _said(rec: dict) -> str:
    """The verdict, or the notes when there is none; one line for a table."""
    if "error" in rec:
        return "refused: " + rec["error"]
    text = rec["verdict"] or ("notes: " + "; ".join(rec["notes"]) if rec["notes"] else "(nothing)")
    return text.replace("|", "/").replace("\n", " ")


def verdict_table(fams: list[Family], stats: list[dict]) -> list[str]:
    """What the first run of each family told the user."""
    lines = ["| family | verdict (or notes) of run 0 |", "|---|---|"]
    for fam, s in zip(fams, stats, strict=True):
        lines.append(f"| {fam.name} | {_said(s['records'][0])} |")
    return lines


def _phase(x: float | None, name: str) -> str:
    """A phase in ps (the allantools records are in seconds; PHASE.DAT has no unit)."""
    if x is None:
        return "skipped (--quick)"
    return f"{x:.4g}" if name == "phase_dat" else f"{x * 1e12:.4g} ps"


def real_table(rows: list[dict]) -> list[str]:
    """The allantools records against their computed references."""
    lines = [
        "| record | n | σ (auto) | ADEV(τ0)/√3 | local-level MLE | σ / ADEV ref | white | "
        "verdict (or notes) | target | result |",
        "|---" * 10 + "|",
    ]
    for r in rows:
        white = {None: "—", True: "yes", False: "no"}[r["rec"]["white"]]
        lines.append(
            f"| {r['name']} | {r['n']} | {_phase(r['sigma'], r['name'])} | "
            f"{_phase(r['adev'], r['name'])} | {_phase(r['mle'], r['name'])} | "
            f"{r['sigma'] / r['adev']:.3f} | {white} | {_said(r['rec'])} | {r['target']} | "
            f"{_mark(r['ok'])} |"
        )
    return lines


def imu_table(
    rows: list[dict], stretches: list[tuple[int, int]], rule: list[tuple[int, int]], t: NDArray
) -> list[str]:
    """Per IMU channel: quiet_variance and .variance over the still stretches' variance."""

    def spans(ss: list[tuple[int, int]]) -> list[str]:
        return [f"{t[a]:.2f}-{t[b - 1]:.2f} s" for a, b in ss]

    hand = spans(stretches)
    lines = [
        f"Hand-picked still stretches: {', '.join(hand)}; the rule's: {', '.join(spans(rule))} "
        f"(samples at {1.0 / float(np.median(np.diff(t))):.1f} Hz). The still-stretch interval "
        "is the reference's own 95 % interval (a χ² on 2 dof / (κ - 1) dof, κ the residuals' "
        "kurtosis); quiet_variance is also shown over each stretch's variance alone and over "
        "the rule's stretches.",
        "",
        "| channel | still-stretch variance (95 % interval) | quiet_variance / still | "
        + " | ".join(f"quiet / {s}" for s in hand)
        + " | quiet / rule's stretches | .variance / still | target | result |",
        "|---" * (7 + len(hand)) + "|",
    ]
    for r in rows:
        q = r["rec"]["quiet"]
        ratio = "—" if q is None else f"{q / r['ref']:.3g}"
        each = " | ".join("—" if q is None else f"{q / v:.3g}" for v in r["each"])
        by_rule = "—" if q is None else f"{q / r['rule']:.3g}"
        lo, hi = r["ci"]
        lines.append(
            f"| {r['channel']} | {r['ref']:.3g} ({lo:.3g}-{hi:.3g}) | {ratio} | {each} | "
            f"{by_rule} | {r['rec']['variance'] / r['ref']:.3g} | quiet_variance within 25 % | "
            f"{_mark(r['ok'])} |"
        )
    return lines


def report(args, fams, stats, real, imu, spd, seconds: float) -> str:
    """The whole result as Markdown."""
    flags = (" --quick" if args.quick else "") + (f" --runs {args.runs}" if args.given_runs else "")
    per_m, ratio, per_one, ratio_one = spd
    passed = sum(all(ok for _, ok in s["checks"]) for s in stats if s["checks"])
    lines = [
        f"### Real noise (`python benchmarks/real_noise.py{flags}`)",
        "",
        f"{args.runs} runs per family, n = {N}, noise std {STD:g} on a smooth signal; "
        f"{platform.machine()}, {os.cpu_count()} cores, {seconds:.0f} s. Bias and RMSE of "
        "`.variance` relative to the variance each family should match; coverage of the "
        'same by `ci95`; rates over the runs. "before" is `auto` on the same runs in '
        "`results/accuracy.json`. Targets are issue 13's except those marked (ours). "
        f"Synthetic families passing: {passed} of {sum(1 for s in stats if s['checks'])}.",
        "",
        *family_table(fams, stats),
        "",
        "**What each family's first run said**",
        "",
        *verdict_table(fams, stats),
        "",
        "**Real records** (allantools' test data; references computed here: ADEV(τ0)/√3 on "
        "the whole record, the local-level MLE without the Cs 5071A's first sample, a glitch; "
        "`auto` sees the whole record)",
        "",
        *real_table(real),
        "",
        "**IMU** (NGIMU `sensors.csv` of the scikit-kinematics wheel; still stretches picked by "
        "eye on all six channels, leaving out a tap near 6.1 s and the wobble after it, "
        "6.6-7.1 s)",
        "",
        *imu_table(*imu),
        "",
        f"**Speed**: `auto` with diagnostics, {per_m:.3f} s per 1e6 samples, {ratio:.1f}x one "
        f"third-order lfilter pass beside it (target < 10x): {_mark(ratio < 10)}. "
        "`noisevar.estimate` runs a record of 2^19 samples or more in chunks on two threads "
        f"(docs/algorithms.md §F5.7); on one thread: {per_one:.3f} s, {ratio_one:.1f}x.",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print Markdown and write ``results/real_noise.md``."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=None, help="runs per family (default 400)")
    ap.add_argument("--quick", action="store_true", help="40 runs, no state-space MLE")
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument(
        "--families",
        default=None,
        help="only the families whose name contains this text (their usual seeds); prints "
        "their table and writes nothing",
    )
    args = ap.parse_args(argv)
    args.given_runs = args.runs is not None
    args.runs = args.runs or (40 if args.quick else 400)
    t0 = time.perf_counter()
    fams = families()
    stats = []
    if args.families is not None:
        chosen = [(i, f) for i, f in enumerate(fams) if args.families.lower() in f.name.lower()]
        if not chosen:
            ap.error(f"no family name contains {args.families!r}")
        fams = [f for _, f in chosen]
        stats = [run_family(f, args.runs, args.seed + 1000 * i) for i, f in chosen]
        print("\n".join(family_table(fams, stats)))
        return 0
    for i, fam in enumerate(fams):
        stats.append(run_family(fam, args.runs, args.seed + 1000 * i))
        print(f"{fam.name}: {stats[-1]['seconds']:.1f} s", file=sys.stderr)
    real = [real_record(name, not args.quick) for name in _refdata.ALLANTOOLS_RECORDS]
    imu = imu_rows()
    spd = speed(repeats=3 if args.quick else 15)  # best of 15: one run of 5 ranged 7.6-10.4x
    text = report(args, fams, stats, real, imu, spd, time.perf_counter() - t0)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "real_noise.md").write_text(text + "\n")
    print(text)
    return 0


def parts_main(argv: list[str]) -> int:
    """``--parts imu``: only the IMU table, printed (nothing written)."""
    ap = argparse.ArgumentParser(description="one part of " + __doc__.splitlines()[0])
    ap.add_argument("--parts", choices=["imu"], required=True)
    ap.parse_args(argv)
    print("\n".join(imu_table(*imu_rows())))
    return 0


if __name__ == "__main__":
    sys.exit(parts_main(sys.argv[1:]) if "--parts" in sys.argv else main())
