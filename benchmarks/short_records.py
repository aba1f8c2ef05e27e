"""Short records (issue 26, polish): what ``auto`` answers on 10-99 samples, and how often
the whiteness test calls white noise coloured.

    python benchmarks/short_records.py [--runs 200]

Per length and kind (white noise, a ramp, a GPS-like random walk under white noise; seeded):
R, its interval, the verdict's first words; then, over ``--runs`` seeded white records per
length, the share the whiteness test rejects (5 % asked) and the share whose verdict says
"coloured".
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
    return noise


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
    for n in (10, 20, 32, 47, 64, 99):
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
