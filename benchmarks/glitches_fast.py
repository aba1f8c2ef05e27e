"""Glitches on a fast signal (issue 26 class 8): bias and coverage over 200 seeded records.

    python benchmarks/glitches_fast.py

The family of ``tests/estimators/test_glitches_fast.py`` (four sinusoids of 15-80 samples per
period, 1 % of samples at 10x std), on 200 records instead of 40. Coverage is counted twice:
of the realised noise's variance (what the record holds) and of the process variance (1.99,
what a filter should be told); the number of glitches in 6000 samples is random, so the two
differ.
"""

from __future__ import annotations

import numpy as np

import noisevar
from noisevar import synth

N_RECORDS = 200


def _fast(n: int, rng: np.random.Generator) -> np.ndarray:
    t = np.arange(n)
    return sum(
        rng.uniform(5, 30) * np.sin(2 * np.pi * t / rng.uniform(15, 80) + rng.uniform(0, 6))
        for _ in range(4)
    )


def main() -> None:
    rel, realised, process = [], 0, 0
    for r in range(N_RECORDS):
        rng = np.random.default_rng(100 + r)
        noise = synth.noise("contaminated", 6000, rng=1000 + r)
        est = noisevar.estimate(_fast(6000, rng) + noise.values)
        v = float(np.var(noise.values))
        rel.append(est.variance / v - 1.0)
        realised += est.ci95[0] <= v <= est.ci95[1]
        process += est.ci95[0] <= noise.variance <= est.ci95[1]
    print(
        f"{N_RECORDS} records: bias {100 * np.mean(rel):+.2f} % (sd {100 * np.std(rel):.1f} %); "
        f"ci95 covers the realised variance in {realised} ({100 * realised / N_RECORDS:.1f} %), "
        f"the process variance in {process} ({100 * process / N_RECORDS:.1f} %)"
    )


if __name__ == "__main__":
    main()
