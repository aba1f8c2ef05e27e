"""Short records (issue 26, polish): what ``auto`` answers on 10-99 samples, and how often
the whiteness test calls white noise coloured.

    python benchmarks/short_records.py [--runs 200]

Per length and kind (white noise, a ramp, a GPS-like random walk under white noise; seeded):
R, its interval, the verdict's first words; then, over ``--runs`` seeded records of 8-21
samples (white noise, a ramp, a slow sine; noise variance 1), the bias of R and how often
its ci95 covers 1 (95 % asked); then, over ``--runs`` seeded white records per length, the
share the whiteness test rejects (5 % asked) and the share whose verdict says "coloured".
"""

from __future__ import annotations

import argparse

import numpy as np

import noisevar


def _record(kind: str, n: int, rng: np.random.Generator) -> np.ndarray:
    noise = rng.normal(0.0, 1.0, n)
    if kind == "ramp":
        return 0.5 * np.arange(n) + noise
    if kind == "gps":
        return np.cumsum(rng.normal(0.0, 0.3, n)) + noise
    if kind == "sine":  # slow: 50 samples per period, amplitude 5 noise std
        return 5.0 * np.sin(2 * np.pi * np.arange(n) / 50 + rng.uniform(0, 2 * np.pi)) + noise
    return noise


def _coverage(runs: int) -> None:
    """Bias and ci95 coverage of ``auto`` on the shortest records (noise variance 1)."""
    print(f"\n| n | record | mean R - 1 | ci95 covers 1 | median ci95 | ({runs} runs) |")
    print("|---|---|---|---|---|")
    for n in (8, 10, 12, 16, 21):
        for kind in ("white", "ramp", "sine"):
            rng = np.random.default_rng(100 * n + len(kind))
            try:
                ests = [
                    noisevar.estimate(_record(kind, n, rng), method="auto") for _ in range(runs)
                ]
            except noisevar.NoisevarError as exc:
                print(f"| {n} | {kind} | refused: {exc} | | |")
                continue
            r = np.array([e.variance for e in ests])
            lo, hi = np.array([e.ci95 for e in ests]).T
            cover = np.mean((lo <= 1.0) & (1.0 <= hi))
            ci = f"{np.median(lo):.3g}-{np.median(hi):.3g}"
            print(f"| {n} | {kind} | {np.mean(r) - 1:+.3f} | {cover:.1%} | {ci} |")


def _verdict(e: noisevar.VarianceEstimate) -> str:
    """The estimate's verdict (an older checkout: its diagnostics' only)."""
    said = getattr(e, "verdict", None)
    if said is None:
        said = e.diagnostics.verdict if e.diagnostics is not None else "(no verdict)"
    return said or "(no verdict)"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    runs = ap.parse_args().runs
    print("| n | record | R | ci95 | verdict (first words) |")
    print("|---|---|---|---|---|")
    for n in (9, 10, 12, 16, 20, 32, 47, 64, 99):
        for kind in ("white", "ramp", "gps"):
            z = _record(kind, n, np.random.default_rng(n))
            try:
                e = noisevar.estimate(z, method="auto")
            except noisevar.NoisevarError as exc:
                print(f"| {n} | {kind} | - | - | refused: {exc} |")
                continue
            words = " ".join(_verdict(e).split()[:14])
            ci = f"{e.ci95[0]:.3g}-{e.ci95[1]:.3g}"
            print(f"| {n} | {kind} | {e.variance:.3g} | {ci} | {words} |")
    _coverage(runs)
    print(f"\n| n | white noise: whiteness test rejects | verdict says coloured | ({runs} runs) |")
    print("|---|---|---|---|")
    for n in (48, 64, 100, 200, 400):
        rng = np.random.default_rng(1000 + n)
        ests = [noisevar.estimate(rng.normal(size=n)) for _ in range(runs)]
        rejected = np.mean([not e.diagnostics.white for e in ests])
        coloured = np.mean(["coloured" in _verdict(e) for e in ests])
        print(f"| {n} | {rejected:.1%} | {coloured:.1%} | |")


if __name__ == "__main__":
    main()
