"""The K a filter is given, per axis, beside the model's K parameter (issue 30).

The Kalibr file and every consumer export take K from ``noise_model/kalibr.py
composite_k``: each axis's ``FilterBias.random_walk`` (K_eq = sqrt(3 AVAR_bias(T) / T) over
the horizon T, which is K itself for a WN+RW model), the largest over axes. Here, per
axis, on the records of ``gmwm_choice.py`` / ``imu_k_bias.py`` (allan_variance_ros's
configuration: 400 Hz, 3 h, white noise + bias random walk, seed ``1000 s + 10 k + a``):

- the chosen model's K parameter and its interval (0 where the model has no random walk);
- K_eq at the default horizon (``model.HORIZON``) and at other horizons, with the
  delta-method interval ``FilterBias.interval``.

The truth there is a random walk alone, whose K_eq is K at every horizon: both are
compared with the truth K. ``--composite N``: the composite truths of ``imu_models.py``
(10 h at 200 Hz, its seeds), where a GM truth's K_eq is not K: K_eq is compared with the
truth's own K_eq (``fitting.filter_bias`` of the true parameters at the same T), K with
the true K.

``--first``/``--seeds`` chunks append to ``results/gmwm_filter_k_axes.csv``;
``--composite`` writes ``results/gmwm_filter_k_composite.csv``; ``--table`` writes
``results/gmwm_filter_k.md`` from both.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

import numpy as np

from noisevar.noise_model.gmwm import AUTO
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm.fitting import (
    as_rows,
    build,
    choose,
    filter_bias,
    wavelet_variances,
)
from noisevar.noise_model.gmwm.model import HORIZON, ONE_SIGMA

sys.path.insert(0, str(Path(__file__).resolve().parent))
from imu_k_bias import RATE, _records, append_rows  # noqa: E402
from imu_models import COMPOSITE, Z95, _truth, covers, simulate_truth  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
AXES = RESULTS / "gmwm_filter_k_axes.csv"
COMPOSITE_AXES = RESULTS / "gmwm_filter_k_composite.csv"
OUT = RESULTS / "gmwm_filter_k.md"
#: Horizons (s) at which K_eq is measured; HORIZON (10 s) is the default's.
HORIZONS = (1.0, HORIZON, 100.0, 1000.0)


def _fit_row(wv: est.WaveletVariance, rate: float) -> dict:
    """The chosen model, its K and interval, and K_eq with its interval at each horizon."""
    sol, tried = choose(wv, AUTO)
    fit = build(sol, tried, wv, rate, "u", ONE_SIGMA, False, HORIZON)
    k = next((p for p in fit.parameters if p.name == "K"), None)
    row = dict(
        model=fit.model,
        k=k.value if k else 0.0,
        k_lo=k.interval[0] if k else 0.0,
        k_hi=k.interval[1] if k else 0.0,
    )
    sol = est.order_gm(sol)
    p = np.exp(sol.log_params)
    for t in HORIZONS:
        fb = filter_bias(sol.keys, p, rate, t, sol.log_cov, ONE_SIGMA)
        row |= {f"keq_{t:g}": fb.random_walk, f"keq_{t:g}_lo": fb.interval[0]}
        row[f"keq_{t:g}_hi"] = fb.interval[1]
    # the fit's own FilterBias (default horizon) is the one the exports read
    assert row[f"keq_{HORIZON:g}"] == fit.filter_bias.random_walk
    return row


def run(first: int, seeds: int) -> None:
    for seed in range(first, first + seeds):
        t0 = time.process_time()
        x, truth = _records(seed)
        wvs = wavelet_variances(as_rows(x, 0), robust=False)
        rows = []
        for (s, a, _, kd), wv in zip(truth, wvs, strict=True):
            row = dict(seed=seed, sensor=s, axis=a, truth=kd)
            row |= {f"true_keq_{t:g}": kd for t in HORIZONS}  # a random walk alone: K_eq = K
            rows.append(row | _fit_row(wv, RATE))
        append_rows(AXES, rows)
        print(f"seed {seed}: {time.process_time() - t0:.1f} CPU s", file=sys.stderr)


def true_k_eq(t: dict, rate: float, horizon: float) -> float:
    """The truth's K_eq: ``filter_bias`` of its GMs and random walk (internal units)."""
    keys = ("GM",) * len(t["GM"]) + ("RW",)
    p = [v for s, tc in t["GM"] for v in (s * s, tc * rate)] + [t["K"] ** 2 / rate]
    return filter_bias(keys, np.array(p), rate, horizon).random_walk


def run_composite(runs: int, skip: int = 0) -> None:
    """``imu_models.py``'s composite truths, records and seeds (``gmwm_choice.py``'s too);
    the first ``skip`` runs' truths are drawn but not fitted (they are in the file)."""
    rate, n = 200.0, int(10 * 3600 * 200.0)
    for c, (label, base) in enumerate(COMPOSITE.items()):
        rng = np.random.default_rng(7 + c)
        rows = []
        for r in range(runs):
            t = _truth(base, rng)
            if r < skip:
                continue
            y = simulate_truth(t, n, rate, 5000 + 100 * c + r)
            (wv,) = wavelet_variances(as_rows(y, 0), robust=False)
            row = dict(seed=r, sensor=label, axis=0, truth=t["K"])
            row |= {f"true_keq_{h:g}": true_k_eq(t, rate, h) for h in HORIZONS}
            rows.append(row | _fit_row(wv, rate))
            print(f"composite {label} run {r}", file=sys.stderr)
        if rows:
            append_rows(COMPOSITE_AXES, rows)


def _rows(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    seen = {}
    for r in rows:  # the last run of an axis counts
        seen[(int(r["seed"]), r["sensor"], int(r["axis"]))] = r
    return [seen[k] for k in sorted(seen)]


def _stats(rows: list[dict], col: str, truth: str) -> str:
    """median error | below -30 % | K = 0 | worst low, high | cover 68.3 % | cover 95 %."""
    e, c68, c95 = [], [], []
    for r in rows:
        v, tv = float(r[col]), float(r[truth])
        e.append(v / tv - 1.0)
        a, b = covers(v, (float(r[f"{col}_lo"]), float(r[f"{col}_hi"])), tv)
        c68.append(a)
        c95.append(b)
    e = np.array(e)
    return (
        f"{np.median(e):+.2%} | {int(np.sum(e < -0.3))} | {int(np.sum(e <= -1.0))} | "
        f"{e.min():+.1%}, {e.max():+.1%} | {np.mean(c68):.0%} | {np.mean(c95):.0%}"
    )


HEAD = [
    "| records | sensor | axes | K given | compared with | median error | below -30 % | "
    "K = 0 | worst low, high | cover 68.3 % | cover 95 % |",
    "|---|---|---|---|---|---|---|---|---|---|---|",
]


def _block(rows: list[dict], label: str, sensors: tuple[str, ...], truth_k: str) -> list[str]:
    out = []
    for sensor in sensors:
        sub = [r for r in rows if r["sensor"] == sensor]
        if not sub:
            continue
        for col, what in (("k", "K parameter"), (f"keq_{HORIZON:g}", f"K_eq, T = {HORIZON:g} s")):
            # a composite truth's K_eq is its own, not K; on the WN+RW truths they are equal
            truth = "truth" if col == "k" else f"true_keq_{HORIZON:g}"
            name = "true K" if col == "k" else truth_k
            out.append(
                f"| {label} | {sensor} | {len(sub)} | {what} | {name} | {_stats(sub, col, truth)} |"
            )
    return out


def _horizons(rows: list[dict], sensors: tuple[str, ...]) -> list[str]:
    lines = [
        "| records | sensor | T (s) | median error | below -30 % | K = 0 | worst low, high | "
        "cover 68.3 % | cover 95 % | median K_eq / K_eq(10 s) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, sub_rows in rows:
        for sensor in sensors:
            sub = [r for r in sub_rows if r["sensor"] == sensor]
            if not sub:
                continue
            for t in HORIZONS:
                ratio = np.median([float(r[f"keq_{t:g}"]) / float(r["keq_10"]) for r in sub])
                lines.append(
                    f"| {label} | {sensor} | {t:g} | "
                    f"{_stats(sub, f'keq_{t:g}', f'true_keq_{t:g}')} | {ratio:.3f} |"
                )
    return lines


def _off_model(rows: list[dict]) -> list[str]:
    lines = []
    for r in rows:
        if r["model"] != "WN+RW":
            tv = float(r["truth"])
            lines.append(
                f"- seed {r['seed']} {r['sensor']} axis {r['axis']}: {r['model']}, K "
                f"{float(r['k']) / tv - 1:+.1%}, K_eq(10 s) {float(r['keq_10']) / tv - 1:+.1%} "
                f"[{float(r['keq_10_lo']) / tv - 1:+.1%}, {float(r['keq_10_hi']) / tv - 1:+.1%}]"
                f", K_eq(1000 s) {float(r['keq_1000']) / tv - 1:+.1%}"
            )
    return lines


def table() -> list[str]:
    ros, comp = _rows(AXES), _rows(COMPOSITE_AXES)
    sensors = ("accelerometer", "gyroscope")
    seeds = sorted({int(r["seed"]) for r in ros})
    first10 = [r for r in ros if int(r["seed"]) < 10]
    lines = [
        "### The K a filter is given, per axis: `python benchmarks/gmwm_filter_k.py --table`",
        "",
        f"allan_variance_ros's configuration (400 Hz, 3 h, WN + RW), {len(seeds)} seeds "
        f"({seeds[0]}-{seeds[-1]}) x 3 axes per sensor, the records of `gmwm_choice.py`. "
        "`K parameter`: the chosen model's K (0 without a random walk); `K_eq`: "
        "`FilterBias.random_walk` at the "
        f"default horizon T = {HORIZON:g} s, what `composite_k` (Kalibr file, consumer "
        "exports) takes per axis before the largest over axes. The truth is a random walk "
        "alone: its K_eq is K at every T. Coverage: `FilterBias.interval` (delta method) "
        "and the K parameter's interval, 68.3 % and their log half-widths x 1.96.",
        "",
        *HEAD,
        *_block(ros, f"ROS, {len(seeds)} seeds", sensors, "true K"),
        *_block(first10, "ROS, seeds 0-9 (the target's 10 x 6)", sensors, "true K"),
    ]
    if comp:
        lines += _block(comp, "composite, 10 h 200 Hz", ("one GM", "two GM"), "true K_eq")
    lines += ["", "Axes not WN+RW (errors against the true K):", "", *_off_model(ros)]
    lines += ["", "#### K_eq against the horizon T", ""]
    groups = [("ROS", ros)] + ([("composite", comp)] if comp else [])
    lines += _horizons(groups, sensors + ("one GM", "two GM"))
    return lines + [
        "",
        f"95 % coverage: the 68.3 % interval's log half-widths x {Z95:.2f} (`imu_models.covers`).",
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--seeds", type=int, default=0)
    ap.add_argument("--composite", type=int, default=0, help="runs per composite truth")
    ap.add_argument("--skip", type=int, default=0, help="composite runs already in the file")
    ap.add_argument("--table", action="store_true")
    args = ap.parse_args()
    if args.seeds:
        run(args.first, args.seeds)
    if args.composite:
        run_composite(args.composite, args.skip)
    if args.table:
        lines = table() + ["", f"Load average when written: {os.getloadavg()[0]:.1f}."]
        OUT.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
