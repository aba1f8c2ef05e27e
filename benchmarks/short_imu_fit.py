"""What the IEEE-952 fit claims on short records (docs/algorithms.md §E4 *Resolution*).

    python benchmarks/short_imu_fit.py              # 100 seeds a cell, ~3 min
    python benchmarks/short_imu_fit.py --seeds 20   # quick

Seeded still records at 100 Hz of 45, 100, 300 and 1,000 samples: white rate noise
(N = 0.01 /√Hz) alone, and with a rate random walk (K = 0.017 /s/√Hz, crossing N near
tau = 1 s, inside the longest record only). Each is fitted by :func:`inertial_noise` (its
default 68.3 % intervals). Per term: the share of records where the fit returns a value
above 0 with an interval whose lower bound is above 0 ("claimed": the fit says the term is
there), the share where the term is said to be unresolved (an upper bound only), and the
share whose interval covers the truth (0 for an absent term). A term the record's taus
cannot resolve must not be claimed.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

from noisevar.noise_model.inertial import TERMS, inertial_noise
from noisevar.noise_model.simulate import simulate_inertial

RESULTS = Path(__file__).resolve().parent / "results"
RATE = 100.0
N_TRUE = 0.01
K_TRUE = 0.017
KINDS = {"white": {"random_walk": N_TRUE}, "white+RRW": {"random_walk": N_TRUE,
                                                         "rate_random_walk": K_TRUE}}
SIZES = (45, 100, 300, 1000)


def unresolved(fit, symbol: str) -> bool:
    """Whether the fit's notes say ``symbol`` is not resolved (an upper bound only)."""
    return any(n.startswith("not resolved") and f"{symbol} (" in n for n in fit.notes)


def cell(kind: str, n: int, seeds: int) -> dict[str, dict[str, float]]:
    truth = {s.symbol: 0.0 for s in TERMS}
    truth.update({s.symbol: KINDS[kind].get(s.name, 0.0) for s in TERMS})
    counts = {s.symbol: {"claimed": 0, "unresolved": 0, "covers": 0} for s in TERMS}
    for seed in range(seeds):
        y = simulate_inertial(n, RATE, seed=10_000 * n + seed, **KINDS[kind])
        fit = inertial_noise(y, RATE)
        for t in fit.terms:
            lo, hi = t.interval
            c = counts[t.symbol]
            c["claimed"] += int(t.value > 0 and lo > 0)
            c["unresolved"] += int(unresolved(fit, t.symbol))
            c["covers"] += int(lo <= truth[t.symbol] <= hi)
    return {k: {m: v / seeds for m, v in c.items()} for k, c in counts.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--out", default="short_imu_fit")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    start = time.perf_counter()
    out: dict[str, dict] = {}
    lines = [
        "## IEEE-952 fit on short records (benchmarks/short_imu_fit.py)",
        "",
        f"{args.seeds} seeds a cell, 100 Hz, N = {N_TRUE}, K = {K_TRUE} (white+RRW); "
        "68.3 % intervals. claimed: value > 0 with a lower bound > 0; unresolved: said to be "
        "an upper bound only; covers: the interval holds the truth (0 when absent).",
        "",
        "| record | n | " + " | ".join(f"{s.symbol} claimed / unres. / covers" for s in TERMS)
        + " |",
        "|---|---|" + "---|" * len(TERMS),
    ]
    for kind in KINDS:
        for n in SIZES:
            res = cell(kind, n, args.seeds)
            out[f"{kind} {n}"] = res
            row = " | ".join(
                f"{r['claimed']:.0%} / {r['unresolved']:.0%} / {r['covers']:.0%}"
                for r in res.values()
            )
            lines.append(f"| {kind} | {n} | {row} |")
    lines += ["", f"{time.perf_counter() - start:.0f} s."]
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{args.out}.md").write_text(text)
    (RESULTS / f"{args.out}.json").write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
