"""GMWM's model choice on allan_variance_ros's configuration, before and after a change.

The records of ``benchmarks/imu_k_bias.py`` (400 Hz, 3 h, white noise + bias random walk,
seed ``1000 s + 10 k + a``): ``fit_imu_model`` (model chosen) runs on each seed's 6 axes
and is set against the ``gmwm`` columns of ``results/imu_k_bias_axes.csv`` (the code of
that run, main before issue 30's dominance rule, ``fitting.identified``). Per sensor:
WN+RW chosen, K's median error, axes below -30 %, K = 0, and each axis whose model
changed.

``--first``/``--seeds`` chunks append to ``results/gmwm_choice_axes.csv`` (chunks may run
in parallel processes); ``--table`` writes ``results/gmwm_choice.md`` from that file.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model import fit_imu_model

sys.path.insert(0, str(Path(__file__).resolve().parent))
from imu_k_bias import AXES as BEFORE  # noqa: E402
from imu_k_bias import RATE, _records, append_rows  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
AFTER = RESULTS / "gmwm_choice_axes.csv"
OUT = RESULTS / "gmwm_choice.md"


def run(first: int, seeds: int) -> None:
    for seed in range(first, first + seeds):
        t0 = time.perf_counter()
        x, truth = _records(seed)
        fits = fit_imu_model(x, RATE)
        rows = [
            dict(seed=seed, sensor=s, axis=a, truth=kd, k=f.value("K"), model=f.model)
            for (s, a, _, kd), f in zip(truth, fits, strict=True)
        ]
        append_rows(AFTER, rows)
        print(f"seed {seed}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)


def _read(path: Path, k: str, model: str) -> dict:
    out = {}
    with path.open() as fh:
        for r in csv.DictReader(fh):
            key = (int(r["seed"]), r["sensor"], int(r["axis"]))
            out.setdefault(key, (float(r[k]) / float(r["truth"]) - 1.0, r[model]))
    return out


def _summary(rows: list[tuple[float, str]]) -> str:
    e = np.array([r[0] for r in rows])
    right = np.mean([r[1] == "WN+RW" for r in rows])
    return (
        f"{right:.1%} | {np.median(e):+.2%} | {int(np.sum(e < -0.3))} | "
        f"{int(np.sum(e <= -1.0))} | {e.min():+.1%}"
    )


def table() -> list[str]:
    before = _read(BEFORE, "gmwm_k", "gmwm_model")
    after = _read(AFTER, "k", "model")
    keys = sorted(set(before) & set(after))
    seeds = sorted({k[0] for k in keys})
    lines = [
        "### GMWM's model choice before / after the dominance rule: "
        "`python benchmarks/gmwm_choice.py --table`",
        "",
        f"allan_variance_ros's configuration, seeds {seeds[0]}-{seeds[-1]} ({len(seeds)} "
        "seeds x 3 axes per sensor), the same records; before: the `gmwm` columns of "
        "`imu_k_bias_axes.csv`.",
        "",
        "| sensor | code | WN+RW chosen | K error median | below -30 % | K = 0 | worst |",
        "|---|---|---|---|---|---|---|",
    ]
    for sensor in ("accelerometer", "gyroscope"):
        ks = [k for k in keys if k[1] == sensor]
        for name, d in (("before", before), ("after", after)):
            lines.append(f"| {sensor} ({len(ks)} axes) | {name} | {_summary([d[k] for k in ks])} |")
    lines += ["", "Axes whose chosen model changed (K error before -> after):", ""]
    for k in keys:
        if before[k][1] != after[k][1]:
            (eb, mb), (ea, ma) = before[k], after[k]
            lines.append(f"- seed {k[0]} {k[1]} axis {k[2]}: {mb} {eb:+.1%} -> {ma} {ea:+.1%}")
    lines += ["", "Axes not WN+RW after:", ""]
    for k in keys:
        if after[k][1] != "WN+RW":
            lines.append(f"- seed {k[0]} {k[1]} axis {k[2]}: {after[k][1]} {after[k][0]:+.1%}")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--seeds", type=int, default=0)
    ap.add_argument("--table", action="store_true")
    args = ap.parse_args()
    if args.seeds:
        run(args.first, args.seeds)
    if args.table:
        lines = table() + ["", f"Load average when written: {os.getloadavg()[0]:.1f}."]
        OUT.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
