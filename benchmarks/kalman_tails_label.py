"""What fit_kalman calls the innovations' tails, per noise family (docs/algorithms.md §E6
*Light-tailed innovations*).

    python benchmarks/kalman_tails_label.py              # 50 seeds a family, ~1 min
    python benchmarks/kalman_tails_label.py --seeds 10

A constant-velocity track (2,000 samples, the tests' ``_track``) plus noise of each
family, fitted by :func:`noisevar.noise_model.fit_kalman` (cv). Per family: the median
innovation kurtosis and the share of records labelled Gaussian, light- and heavy-tailed.
Gaussian and Student-t(5) noise are the controls; uniform noise, a quantised track
(step 2: rounding error uniform, kurtosis 1.8), a sine (period 7.3 samples, kurtosis 1.5)
and a square wave (period 11.1) are not Gaussian.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model import fit_kalman

RESULTS = Path(__file__).resolve().parent / "results"
N = 2000


def record(family: str, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    track = np.cumsum(np.cumsum(rng.normal(0, 0.3, N))) * 0.1
    k = np.arange(N)
    noise = {
        "gaussian": lambda: rng.normal(0, 1, N),
        "student-t 5": lambda: rng.standard_t(5, N),
        "uniform": lambda: rng.uniform(-1.7, 1.7, N),
        "quantised track (step 2)": lambda: np.round(track / 2) * 2 - track,
        "sine (P 7.3)": lambda: 1.4 * np.sin(2 * np.pi * k / 7.3 + rng.uniform(0, 6)),
        "square (P 11.1)": lambda: np.sign(np.sin(2 * np.pi * k / 11.1 + rng.uniform(0, 6))),
    }[family]()
    return track + noise


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--out", default="kalman_tails_label")
    args = ap.parse_args()
    start = time.perf_counter()
    families = [
        "gaussian",
        "student-t 5",
        "uniform",
        "quantised track (step 2)",
        "sine (P 7.3)",
        "square (P 11.1)",
    ]
    lines = [
        "## Kalman fit: the innovations' tails (benchmarks/kalman_tails_label.py)",
        "",
        f"cv track, {N} samples, {args.seeds} seeds a family.",
        "",
        "| noise | median kurtosis | Gaussian | light | heavy |",
        "|---|---|---|---|---|",
    ]
    out = {}
    for fam in families:
        fits = [fit_kalman(record(fam, s)) for s in range(args.seeds)]
        kurt = float(np.median([f.innovations_kurtosis for f in fits]))
        shape = [getattr(f, "innovations_tails", None) for f in fits]
        gauss = sum(f.innovations_gaussian for f in fits) / len(fits)
        light = sum(s == "light" for s in shape) / len(fits)
        heavy = sum(s == "heavy" or (s is None and not f.innovations_gaussian)
                    for s, f in zip(shape, fits, strict=True)) / len(fits)  # fmt: skip
        out[fam] = {"kurtosis": kurt, "gaussian": gauss, "light": light, "heavy": heavy}
        lines.append(f"| {fam} | {kurt:.2f} | {gauss:.0%} | {light:.0%} | {heavy:.0%} |")
    lines += ["", f"{time.perf_counter() - start:.0f} s."]
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{args.out}.md").write_text(text)
    (RESULTS / f"{args.out}.json").write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
