"""GMWM's model choice on allan_variance_ros's configuration, before and after a change.

The records of ``benchmarks/imu_k_bias.py`` (400 Hz, 3 h, white noise + bias random walk,
seed ``1000 s + 10 k + a``): ``fit_imu_model`` (model chosen) runs on each seed's 6 axes
and is set against the ``gmwm`` columns of ``results/imu_k_bias_axes.csv`` (the code of
that run, main before issue 30's dominance rule, ``fitting.identified``). Per sensor:
WN+RW chosen, K's median error, axes below -30 %, K = 0, and each axis whose model
changed. Issue 30, fifth round: on each axis without a random walk, the rival model of
the note (``fitting.random_walk_note``) and its K; the null distribution of the GMWM
objective's drop from WN+RW to WN+GM and to WN+FL (the truth is WN+RW) against the
price of a parameter; and the same search with BIC.

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
from scipy import stats

from noisevar.noise_model import fit_imu_model
from noisevar.noise_model.gmwm.fitting import as_rows, choose, penalty, wavelet_variances

sys.path.insert(0, str(Path(__file__).resolve().parent))
from imu_k_bias import AXES as BEFORE  # noqa: E402
from imu_k_bias import HOURS, RATE, _records, append_rows  # noqa: E402
from imu_models import COMPOSITE, _truth, simulate_truth  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
AFTER = RESULTS / "gmwm_choice_axes.csv"
OUT = RESULTS / "gmwm_choice.md"
COMPOSITE_OUT = RESULTS / "gmwm_choice_composite.md"


NULL_MODELS = ("WN+RW", "WN+GM", "WN+FL")


def _rival_k(col: np.ndarray, fit, rate: float = RATE) -> float:  # noqa: ANN001
    """K of the rival model named by the random-walk note (NaN without a note)."""
    note = next((n for n in fit.notes if "is within" in n), None)
    if note is None:
        return float("nan")
    return fit_imu_model(col, rate, models=[note.split(" ")[0]]).value("K")


def run(first: int, seeds: int) -> None:
    for seed in range(first, first + seeds):
        t0 = time.perf_counter()
        x, truth = _records(seed)
        fits = fit_imu_model(x, RATE)
        bics = fit_imu_model(x, RATE, criterion="bic")
        wvs = wavelet_variances(as_rows(x, 0), robust=False)
        rows = []
        for i, ((s, a, _, kd), f, b) in enumerate(zip(truth, fits, bics, strict=True)):
            objective = {"+".join(t.keys): t.objective for t in choose(wvs[i], NULL_MODELS)[1]}
            rows.append(
                dict(
                    seed=seed,
                    sensor=s,
                    axis=a,
                    truth=kd,
                    k=f.value("K"),
                    model=f.model,
                    k_rival=_rival_k(x[:, i], f),
                    k_bic=b.value("K"),
                    model_bic=b.model,
                    **{f"o_{m.split('+')[1].lower()}": objective[m] for m in NULL_MODELS},
                )
            )
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
        "### GMWM's model choice before / after the dominance rule (after: the code of "
        "this run; the random-walk note changes no choice): "
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
    return lines + _fifth_round(_rows(AFTER))


def _rows(path: Path) -> list[dict]:
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    return sorted(rows, key=lambda r: (int(r["seed"]), r["sensor"], int(r["axis"])))


def _boundary(x: float) -> float:
    """P(objective drop > x) for one parameter on a boundary: half a chi-square(1)'s."""
    return 0.5 * float(stats.chi2.sf(x, 1))


def _fifth_round(rows: list[dict]) -> list[str]:
    """The random-walk note, the null distribution of the drops, and BIC (issue 30)."""
    price = penalty("hq", HOURS * 3600 * RATE)
    lines = ["", "#### Fifth round (issue 30): the random-walk note, the null drops, BIC", ""]
    lines += ["Axes without a random walk: the note's rival model K (K error):", ""]
    for r in rows:
        if "RW" not in r["model"].split("+"):
            kr = float(r["k_rival"]) / float(r["truth"]) - 1.0
            what = "no note" if np.isnan(kr) else f"note's K {kr:+.1%}"
            lines.append(f"- seed {r['seed']} {r['sensor']} axis {r['axis']}: {r['model']}, {what}")
    d_gm = np.array([float(r["o_rw"]) - float(r["o_gm"]) for r in rows])
    d_fl = np.array([float(r["o_rw"]) - float(r["o_fl"]) for r in rows])
    lines += [
        "",
        f"Null distribution ({len(rows)} axes, truth WN+RW): the GMWM objective's drop from "
        f"WN+RW to WN+GM (one more parameter, WN+RW its boundary tau_c -> inf) and to "
        f"WN+FL (as many); HQ's price of a parameter {price:.2f}.",
        "",
        "| drop above | WN+GM measured | boundary chi-square | WN+FL measured |",
        "|---|---|---|---|",
    ]
    for x in (0.0, 2.71, 3.84, price, 8.0):
        lines.append(
            f"| {x:.2f} | {np.mean(d_gm > x):.1%} ({int(np.sum(d_gm > x))}) | "
            f"{_boundary(x) if x > 0 else 0.5:.1%} | {np.mean(d_fl > x):.1%} "
            f"({int(np.sum(d_fl > x))}) |"
        )
    lines += [
        "",
        'The same search with BIC (`criterion="bic"`, price '
        f"{penalty('bic', HOURS * 3600 * RATE):.1f}):",
        "",
        "| sensor | WN+RW chosen | K error median | below -30 % | K = 0 | worst |",
        "|---|---|---|---|---|---|",
    ]
    for sensor in ("accelerometer", "gyroscope"):
        sub = [
            (float(r["k_bic"]) / float(r["truth"]) - 1.0, r["model_bic"])
            for r in rows
            if r["sensor"] == sensor
        ]
        lines.append(f"| {sensor} ({len(sub)} axes) | {_summary(sub)} |")
    return lines


def composite(runs: int) -> list[str]:
    """HQ against BIC on the composite truths of ``imu_models.py`` (its records, seeds and
    truths): right model, runs without the random walk, and the note's K on those."""
    rate, n = 200.0, int(10 * 3600 * 200.0)
    lines = [
        f"### HQ against BIC on the composite truths: `python benchmarks/gmwm_choice.py "
        f"--composite {runs}`",
        "",
        f"`imu_models.py`'s composite records (10 h at 200 Hz, {runs} runs per truth, its "
        "seeds and truths); K error of the note's rival model on the runs that drop the RW.",
        "",
        "| truth | criterion | right model | no random walk | with the note | note's K error |",
        "|---|---|---|---|---|---|",
    ]
    for c, (label, base) in enumerate(COMPOSITE.items()):
        rng = np.random.default_rng(7 + c)
        want = "QN+WN+" + ("GM" if len(base["GM"]) == 1 else "2GM") + "+RW"
        got: dict[str, list] = {"hq": [], "bic": []}
        for r in range(runs):
            t = _truth(base, rng)
            y = simulate_truth(t, n, rate, 5000 + 100 * c + r)
            for crit, out in got.items():
                f = fit_imu_model(y, rate, criterion=crit)
                kr = _rival_k(y, f, rate) / t["K"] - 1.0 if "RW" not in f.keys else None
                out.append((f.model == want, "RW" not in f.keys, kr))
            print(f"composite {label} run {r}", file=sys.stderr)
        for crit, out in got.items():
            errs = [e for _, _, e in out if e is not None and not np.isnan(e)]
            lines.append(
                f"| {label} | {crit} | {np.mean([o[0] for o in out]):.0%} | "
                f"{sum(o[1] for o in out)} | {len(errs)} | "
                + (", ".join(f"{e:+.0%}" for e in errs) or "-")
                + " |"
            )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--seeds", type=int, default=0)
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--composite", type=int, default=0, help="runs per composite truth")
    args = ap.parse_args()
    if args.composite:
        lines = composite(args.composite)
        lines += ["", f"Load average when written: {os.getloadavg()[0]:.1f}."]
        COMPOSITE_OUT.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))
    if args.seeds:
        run(args.first, args.seeds)
    if args.table:
        lines = table() + ["", f"Load average when written: {os.getloadavg()[0]:.1f}."]
        OUT.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
