"""Does the IEEE-952 misfit check (docs/algorithms.md §E4) flag records that are not a still
sensor's noise, and only those? (issue 26)

    python benchmarks/inertial_misfit.py           # 274 still + 60 motion records, ~1 min
    python benchmarks/inertial_misfit.py --quick   # 40 + 15

1. **False alarms.** Model-true records from ``simulate_inertial``: N always (1e-4 to 1e-2
   per √Hz), Q, B, K, R each drawn in with a seeded chance and a seeded size relative to N,
   1,000-50,000 samples at 50-200 Hz; and the two records the first attempt (a chi-square
   over every tau) false-alarmed on; and 12 still records E4.1 does not describe (white
   noise and a Gauss-Markov bias, 50,000-2,000,000 samples at 100 Hz). Share of records
   noted (target <= 1-2 %), and the largest misfit (standard errors) at the judged taus.
2. **Detection.** White rate noise (sigma 1e-3 to 1e-1 per sample, 50 Hz, 20,000 samples)
   plus a sine (0.03-3 Hz), a triangle (back-and-forth motion, period 3-100 s) or 2-7
   level steps, each of 1-10x sigma. Share noted per kind.
Both run :func:`allan` and :func:`fit_terms` (the fit ``inertial_noise`` makes, without
its bootstrap) and :func:`misfit_note` on the edf ``inertial_noise`` uses.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model.allan import allan
from noisevar.noise_model.inertial import TERMS, _model_edf, fit_terms
from noisevar.noise_model.inertial_misfit import APPROXIMATE, MISFIT, misfit_note, misfit_z
from noisevar.noise_model.simulate import simulate_inertial

RESULTS = Path(__file__).resolve().parent / "results"


def judge(y: np.ndarray, fs: float) -> tuple[list[str], float]:
    """The misfit notes of the fit of ``y`` (their start), and its largest judged misfit."""
    res = allan(y, rate=fs, data="rate", kind="oadev", taus="octave")
    m = np.maximum(np.round(res.taus * fs), 1).astype(np.int64)
    coef, _ = fit_terms(res.taus, res.variance, res.edf, rate=fs, n_phase=y.size + 1)
    a = np.column_stack([s.coefficient(res.taus) for s in TERMS])
    edf = _model_edf(a, coef, m, y.size + 1)
    z = misfit_z(res.variance, a @ coef, edf)
    worst = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 0.0
    return [n.split(":")[0] for n in misfit_note(res.taus, res.variance, a @ coef, edf)], worst


def true_records(count: int):
    rng = np.random.default_rng(456)
    for s in range(count):
        n = int(rng.choice([1000, 2000, 5000, 20000, 50000]))
        fs = float(rng.choice([50, 100, 200]))
        big_n = 10 ** rng.uniform(-4, -2)
        kw = {"random_walk": big_n}
        if rng.random() < 0.5:
            kw["quantization"] = big_n / np.sqrt(fs) * 10 ** rng.uniform(-1, 0.5)
        if rng.random() < 0.6:
            kw["bias_instability"] = big_n * np.sqrt(fs) * 10 ** rng.uniform(-2, -0.5)
        if rng.random() < 0.6:
            kw["rate_random_walk"] = big_n * 10 ** rng.uniform(-3, -1)
        if rng.random() < 0.3:
            kw["rate_ramp"] = big_n * 10 ** rng.uniform(-4, -2)
        yield "+".join(sorted(kw)), simulate_inertial(n, fs, seed=5000 + s, **kw), fs
    yield (
        "first attempt a",
        simulate_inertial(50000, 50, random_walk=1e-3, rate_random_walk=1e-4, seed=0),
        50.0,
    )
    yield (
        "first attempt b",
        simulate_inertial(
            50000,
            50,
            quantization=1e-4,
            random_walk=1e-3,
            bias_instability=1e-3,
            rate_random_walk=1e-4,
            rate_ramp=1e-6,
            seed=1,
        ),
        50.0,
    )


def gauss_markov_records(count: int):
    """A still sensor's noise E4.1 lacks: white rate noise and a Gauss-Markov bias."""
    rng = np.random.default_rng(11)
    for s in range(count):
        n = int((50_000, 400_000, 2_000_000)[s % 3])
        gm = (1e-3 * 10 ** rng.uniform(-0.5, 0.5), 10 ** rng.uniform(0.5, 2))
        yield (
            "gauss-markov",
            simulate_inertial(n, 100.0, random_walk=1e-3, gauss_markov=(gm,), seed=9000 + s),
            100.0,
        )


def motion_records(count: int):
    rng = np.random.default_rng(7)
    n, fs = 20000, 50.0
    t = np.arange(n) / fs
    for s in range(count):
        sd = 10 ** rng.uniform(-3, -1)
        noise = simulate_inertial(n, fs, random_walk=sd / np.sqrt(fs), seed=1000 + s)
        kind = ("sine", "triangle", "steps")[s % 3]
        amp = sd * 10 ** rng.uniform(0, 1)
        if kind == "sine":
            sig = amp * np.sin(2 * np.pi * 10 ** rng.uniform(-1.5, 0.5) * t + rng.uniform(0, 6))
        elif kind == "triangle":
            period = 10 ** rng.uniform(0.5, 2)
            sig = amp * 2 * np.abs((t / period) % 1 - 0.5)
        else:
            sig = np.zeros(n)
            for c in np.sort(rng.integers(0, n, rng.integers(2, 8))):
                sig[c:] += amp * rng.choice([-1, 1])
        yield kind, sig + noise, fs


def table(rows: list[tuple[str, list[str], float]], title: str, kinds: list[str]) -> list[str]:
    out = [
        f"### {title}",
        "",
        "| records | n | misfit (files warn) | share | approximate (note only) | "
        "largest misfit (SE) |",
        "|---|---|---|---|---|---|",
    ]
    for kind in kinds:
        sel = [r for r in rows if kind in ("all", r[0])]
        hit = sum(MISFIT in r[1] for r in sel)
        soft = sum(APPROXIMATE in r[1] for r in sel)
        worst = max(r[2] for r in sel)
        out.append(f"| {kind} | {len(sel)} | {hit} | {hit / len(sel):.1%} | {soft} | {worst:.2f} |")
    return [*out, ""]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    start = time.perf_counter()
    truth = [(k, *judge(y, fs)) for k, y, fs in true_records(40 if args.quick else 260)]
    truth += [(k, *judge(y, fs)) for k, y, fs in gauss_markov_records(3 if args.quick else 12)]
    motion = [(k, *judge(y, fs)) for k, y, fs in motion_records(15 if args.quick else 60)]
    lines = ["## IEEE-952 misfit check (benchmarks/inertial_misfit.py)", ""]
    lines += table(truth, "False alarms (still records)", ["all", "gauss-markov"])
    lines += table(motion, "Detection", ["sine", "triangle", "steps"])
    lines.append(f"{time.perf_counter() - start:.0f} s.")
    text = "\n".join(lines) + "\n"
    print(text)
    name = "inertial_misfit_quick" if args.quick else "inertial_misfit"
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.md").write_text(text)
    (RESULTS / f"{name}.json").write_text(
        json.dumps({"false_alarms": truth, "detection": motion}, indent=1)
    )


if __name__ == "__main__":
    main()
