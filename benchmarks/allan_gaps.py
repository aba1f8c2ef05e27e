"""The IEEE-952 terms of rate data whose logger drops samples (noise_model/allan_gaps.py).

Two parts, written to ``results/allan_gaps.md``:

- synthetic: white (N) + random-walk (K) rate noise at 400 Hz for 300 s, 30-45 % of the
  samples dropped at random (seeded), stamps with 2 % jitter. ``inertial_noise`` with the
  times (samples placed on their base period) against the same samples taken as uniform
  at the median rate (the path before) and the full record: N and K bias, the 95 %
  interval's coverage, CPU seconds per fit;
- PX4: the committed log's ``vehicle_angular_velocity`` (1,812 samples, 848 of 2,660
  slots empty): N, B, K per axis, placed and taken as uniform (``noisevar imu``'s two
  paths).

Usage: ``python benchmarks/allan_gaps.py [--seeds 40]``.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model import inertial_noise
from noisevar.noise_model.allan_gaps import stamp_grid

RESULTS = Path(__file__).resolve().parent / "results"
OUT = RESULTS / "allan_gaps.md"
LOG = Path(__file__).resolve().parents[1] / "tests" / "data" / "px4_sample_log_small.ulg"
RATE, SECONDS = 400.0, 300.0
N_TRUE, K_TRUE = 0.01, 0.01
CI = 0.95


def _record(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    rng = np.random.default_rng(seed)
    n = int(RATE * SECONDS)
    y = N_TRUE * np.sqrt(RATE) * rng.standard_normal(n)
    y += np.cumsum(K_TRUE / np.sqrt(RATE) * rng.standard_normal(n))
    t = np.arange(n) / RATE + rng.normal(scale=0.02 / RATE, size=n)
    dropped = rng.uniform(0.30, 0.45)
    keep = rng.random(n) > dropped
    return y, t, y[keep], t[keep], dropped


def _fit(y: np.ndarray, t: np.ndarray | None) -> tuple[dict, float]:
    start = time.process_time()
    fit = inertial_noise(y, RATE, t=t, ci=CI)
    cpu = time.process_time() - start
    return {s: (fit.term(s).value, *fit.term(s).interval) for s in "NBK"}, cpu


def synthetic(seeds: int) -> list[str]:
    rows = {"full record": [], "placed on the base period": [], "uniform at the median": []}
    cpu = {k: [] for k in rows}
    for seed in range(seeds):
        y, t, yk, tk, _ = _record(seed)
        for name, args in zip(rows, ((y, None), (yk, tk), (yk, None)), strict=True):
            terms, c = _fit(*args)
            rows[name].append(terms)
            cpu[name].append(c)
    out = [
        f"## Synthetic: N = K = 0.01, 400 Hz, {SECONDS:g} s, 30-45 % dropped, {seeds} seeds",
        "",
        "| path | N bias | N 95 % covers | K bias | K 95 % covers | K median ratio | CPU s/fit |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, fits in rows.items():
        cells = []
        for sym, truth in (("N", N_TRUE), ("K", K_TRUE)):
            v = np.array([f[sym] for f in fits])
            cover = np.mean((v[:, 1] <= truth) & (truth <= v[:, 2]))
            cells += [f"{np.mean(v[:, 0]) / truth - 1:+.1%}", f"{cover:.0%}"]
        k_ratio = np.median([f["K"][0] / K_TRUE for f in fits])
        out.append(f"| {name} | {' | '.join(cells)} | {k_ratio:.3f} | {np.mean(cpu[name]):.3f} |")
    return out


def px4() -> list[str]:
    from noisevar.cli._common import load_file
    from noisevar.io import pick_column, record_times

    table = load_file(str(LOG), "vehicle_angular_velocity")
    t = record_times(table)
    grid = stamp_grid(t)
    rate = 1.0 / np.median(np.diff(t))
    out = [
        "",
        f"## PX4 `vehicle_angular_velocity` ({t.size} samples, {grid.dropped} of {grid.size} "
        f"slots empty, base period {grid.period * 1e3:.4f} ms, median rate {rate:.3f} Hz)",
        "",
        "Flight data (motion included: a regime warning on every axis), so no truth: the "
        "two paths' terms side by side (68.3 % intervals, `noisevar imu`'s).",
        "",
        "| axis | path | N (rad/s/√Hz) | B (rad/s) | K (rad/s²/√Hz) |",
        "|---|---|---|---|---|",
    ]
    for col in table.signals:
        z = np.asarray(pick_column(table, col), dtype=float)
        for name, times in (("placed", t), ("uniform at the median", None)):
            fit = inertial_noise(z, rate, t=times)
            cells = [
                f"{fit.term(s).value:.3g} [{fit.term(s).interval[0]:.3g}, "
                f"{fit.term(s).interval[1]:.3g}]"
                for s in "NBK"
            ]
            out.append(f"| {col} | {name} | {' | '.join(cells)} |")
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=40)
    args = p.parse_args()
    lines = ["# Allan deviation of logs that drop samples", ""]
    lines += [f"Load: {os.getloadavg()[0]:.2f} (1-min average) at the start.", ""]
    lines += synthetic(args.seeds) + px4()
    RESULTS.mkdir(exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
