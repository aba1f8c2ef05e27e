"""Is the R to use (``est.still.variance``) biased low by choosing still stretches? (issue 26)

    python benchmarks/still_bias.py            # synthetic tables and the HA002 record, ~3 min
    python benchmarks/still_bias.py --quick    # 8 seeds per cell

The still stretches are chosen because their level is low, and the R to use is then measured
on those same samples: the lowest of many chi-square draws is below their mean (selection
bias). This script measures it, and decomposes the one real-record failure it was suspected
of (mobgap HA002 accelerometer Y / Z, R to use 0.60x / 0.69x the hand-cut reference).

1. **White-noise rests.** ``K`` rests of ``L`` samples of white noise (sigma = 1) with bursts
   of motion (400 samples, a sine of 5-40 plus the same noise) between. Per cell: the R to
   use over the true variance of the samples it was measured on ('R to use / truth'); the
   noise's own mean square on those samples ('chosen samples' mean square / truth': the
   selection of the samples alone); the same method with the same parameters on the true
   rests ('method on the true rests / truth': the method alone). Mean +- standard error over
   seeded records; records with no R to use (the level not found to vary) are counted.
2. **HA002-like rests.** Three rests of 240, 1750 and 5750 samples (the start, standing and
   sitting stretches of HA002) at one level or at 1, 1.17, 1.37 (its accelerometer Y's
   var(d2)/6 in the three postures), the noise white or AR(1) (low-passed by the sensor).
   'R to use / method on the chosen rests': the R to use over the same method and
   parameters on the true rests it drew its samples from, weighted by the samples it took
   (the selection bias); the share of each rest chosen.
3. **HA002 itself** (mobgap's sdist, fetched as in ``real_records.py``): per still posture
   (hand-cut) and channel, var(d2)/6 with its interval, var(d1)/2 over it, and the R to use's
   own method and parameters on that posture, each over the reference (the sitting stretch's
   var(d2)/6); and the posture's Welch spectrum over the sitting one's at 30-50 Hz, where
   sway has no power left.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy import signal

import noisevar
from noisevar.estimators import pipeline

sys.path.insert(0, str(Path(__file__).resolve().parent))
import real_records as rr  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
#: HA002's still postures, cut by hand (s): the reference is the sitting one.
POSTURES = {"start": (0.1, 2.5), "standing": (39.0, 56.5), "sitting": (82.0, 139.5)}
MOTION = 400


@contextlib.contextmanager
def chosen() -> Iterator[dict]:
    """Record the sample ranges (and the record) the R to use is measured on."""
    seen: dict = {}
    original = pipeline.InMemory.estimate_in

    def spy(self, params, ranges):
        seen["ranges"], seen["record"] = list(ranges), self
        return original(self, params, ranges)

    pipeline.InMemory.estimate_in = spy
    try:
        yield seen
    finally:
        pipeline.InMemory.estimate_in = original


def _noise(rng: np.random.Generator, m: int, var: float, phi: float) -> NDArray:
    w = rng.normal(0.0, 1.0, m + 50)
    if phi:
        w = signal.lfilter([np.sqrt(1 - phi * phi)], [1.0, -phi], w)
    return np.sqrt(var) * w[50:]


def rests_record(seed: int, lens, levels, phi: float = 0.0):
    """Rests of ``lens`` samples at ``levels`` with bursts between; (z, noise, rests)."""
    rng = np.random.default_rng(seed)
    parts, noise, rests, pos = [], [], [], 0
    for i, (m, v) in enumerate(zip(lens, levels, strict=True)):
        if i:
            e = _noise(rng, MOTION, 1.0, phi)
            t = np.arange(MOTION)
            parts.append(e + rng.uniform(5, 40) * np.sin(t / rng.uniform(2, 6)))
            noise.append(e)
            pos += MOTION
        e = _noise(rng, m, v, phi)
        parts.append(e)
        noise.append(e)
        rests.append((pos, pos + m, v))
        pos += m
    return np.concatenate(parts), np.concatenate(noise), rests


def _overlap(ranges, rests) -> NDArray:
    """Samples of each rest inside ``ranges``."""
    return np.array(
        [sum(max(0, min(b, d) - max(a, c)) for c, d in ranges) for a, b, _ in rests], float
    )


def _mean_se(x: list[float]) -> str:
    a = np.asarray(x)
    return f"{a.mean():.3f} ± {a.std(ddof=1) / np.sqrt(a.size):.3f}" if a.size > 1 else "—"


def white_cell(length: int, k: int, seeds: int) -> dict:
    use, sel, method, share, none = [], [], [], [], 0
    for s in range(seeds):
        z, e, rests = rests_record(10_000 * length + 100 * k + s, [length] * k, [1.0] * k)
        with chosen() as seen:
            est = noisevar.estimate(z)
        if est.still is None:
            none += 1
            continue
        ranges = seen["ranges"]
        picked = np.concatenate([e[a:b] for a, b in ranges])
        use.append(est.still.variance)  # the truth is 1 everywhere
        sel.append(float(np.mean(picked**2)))
        true = [(a, b) for a, b, _ in rests]
        method.append(seen["record"].estimate_in(est.still.params, true).variance)
        share.append(_overlap(ranges, rests).sum() / (length * k))
    return {
        "L": length,
        "K": k,
        "records": seeds - none,
        "none": none,
        "use": _mean_se(use),
        "sel": _mean_se(sel),
        "method": _mean_se(method),
        "share": float(np.mean(share)),
    }


def ha002_like_cell(levels, phi: float, seeds: int) -> dict:
    lens = (240, 1750, 5750)
    ratio, shares, none = [], [], 0
    for s in range(seeds):
        z, _, rests = rests_record(777 + s, lens, levels, phi)
        with chosen() as seen:
            est = noisevar.estimate(z)
        if est.still is None:
            none += 1
            continue
        rec, ranges, p = seen["record"], seen["ranges"], est.still.params
        own = [rec.estimate_in(p, [(a, b)]).variance for a, b, _ in rests]
        took = _overlap(ranges, rests)
        ratio.append(est.still.variance / (np.dot(took, own) / took.sum()))
        shares.append(took / np.array(lens))
    return {"levels": levels, "phi": phi, "records": seeds - none, "ratio": _mean_se(ratio),
            "share": np.mean(shares, axis=0).round(2).tolist()}  # fmt: skip


def _band_ratio(x: NDArray, a: tuple[float, float], rate: float) -> float:
    """Welch power at 30-50 Hz of posture ``a`` over the sitting stretch's."""

    def power(span: tuple[float, float]) -> float:
        seg = x[round(span[0] * rate) : round(span[1] * rate)]
        f, p = signal.welch(seg, fs=rate, nperseg=64, detrend="linear")
        return float(np.mean(p[f >= 30.0]))

    return power(a) / power(POSTURES["sitting"])


def ha002_rows() -> list[dict]:
    rec = next(r for r in rr.RECORDS if r.name == "mobgap_ha002")
    rows = []
    for channel, x in rec.load().items():
        with chosen() as seen:
            est = noisevar.estimate(x)
        ref = rr.reference(rec, x).value
        record, p = seen["record"], est.still.params
        where = ", ".join(f"{a / rec.rate:g}-{b / rec.rate:g}" for a, b in seen["ranges"])
        for name, span in POSTURES.items():
            d2 = rr.still_reference(x, rec.rate, [span])
            cut = [(round(span[0] * rec.rate), round(span[1] * rec.rate))]
            rows.append({
                "channel": channel, "posture": name, "d2": d2.value / ref,
                "d2_lo": d2.lo / ref, "d2_hi": d2.hi / ref, "d1d2": d2.check,
                "method": record.estimate_in(p, cut).variance / ref,
                "hf": _band_ratio(x, span, rec.rate),
                "use": est.still.variance / ref,
                "chosen": where if name == "start" else "",
            })  # fmt: skip
    return rows


def report(white: list[dict], like: list[dict], ha: list[dict], seconds: float) -> str:
    out = [
        "### Selection bias of the R to use (`python benchmarks/still_bias.py`)",
        "",
        f"{seconds:.0f} s. Method `auto`; the R to use is `est.still.variance` (the same method "
        "on the still stretches both block grids find). What each column is: the script's "
        "docstring.",
        "",
        "**1. White-noise rests (σ² = 1) with bursts of motion between.**",
        "",
        "| rest length L | rests K | records (no R to use) | R to use / truth | chosen samples' "
        "mean square / truth | method on the true rests / truth | share of the rests' samples "
        "chosen |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in white:
        out.append(f"| {c['L']} | {c['K']} | {c['records']} ({c['none']}) | {c['use']} | "
                   f"{c['sel']} | {c['method']} | {c['share']:.2f} |")  # fmt: skip
    out += [
        "",
        "**2. HA002-like rests** (240, 1750, 5750 samples; AR(1) φ = low-passed by the sensor).",
        "",
        "| levels | φ | records | R to use / method on the chosen rests | share chosen of each "
        "rest |",
        "|---|---|---|---|---|",
    ]
    for c in like:
        out.append(f"| {c['levels']} | {c['phi']} | {c['records']} | {c['ratio']} | "
                   f"{c['share']} |")  # fmt: skip
    out += [
        "",
        "**3. mobgap HA002, per hand-cut still posture** (every figure over the reference, the "
        "sitting stretch's var(d2)/6; 'method' is the R to use's method and parameters on the "
        "posture alone; '30-50 Hz' is the posture's Welch power there over the sitting one's).",
        "",
        "| channel | posture | var(d2)/6 (95 %) | d1 / d2 | method | 30-50 Hz | R to use | "
        "chosen (s) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in ha:
        out.append(f"| {r['channel']} | {r['posture']} | {r['d2']:.3f} ({r['d2_lo']:.3f}-"
                   f"{r['d2_hi']:.3f}) | {r['d1d2']:.2f} | {r['method']:.3f} | {r['hf']:.2f} | "
                   f"{r['use']:.3f} | {r['chosen']} |")  # fmt: skip
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="8 seeds per cell")
    args = ap.parse_args(argv)
    seeds = 8 if args.quick else 30
    t0 = time.perf_counter()
    white = [white_cell(m, k, seeds) for m in (150, 300, 600, 1500) for k in (2, 5, 10)]
    like = [
        ha002_like_cell(levels, phi, seeds)
        for phi in (0.0, 0.5, 0.8)
        for levels in ((1.0, 1.0, 1.0), (1.0, 1.17, 1.37))
    ]
    ha = ha002_rows()
    text = report(white, like, ha, time.perf_counter() - t0)
    print(text)
    if not args.quick:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "still_bias.md").write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
