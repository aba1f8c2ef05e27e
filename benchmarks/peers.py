"""Is `auto`'s RMSE really below the state-space MLE's? Paired runs with a bootstrap interval.

    python benchmarks/peers.py                 # 200 paired runs per cell, n = 1000 and 6000
    python benchmarks/peers.py --runs 50 --families random-jerk --sizes 1000

``benchmarks/accuracy.py`` runs the two statsmodels MLE peers on only 50 runs
per cell (a fit takes about a second at n = 6000), and a 50-run RMSE is only
known to about +-10 %: too coarse to say which of two estimators within a few
per cent of each other is better. This benchmark runs ``auto``, ``mle-level``
and ``mle-trend`` on the same runs (the seeds of ``accuracy.py``, so these are
the same signals as its first runs) and reports, per (family, n), the ratio
``RMSE(peer) / RMSE(auto)`` with a paired bootstrap 95 % interval (runs
resampled together). The verdict is "auto lower" when the whole interval is
above 1, "peer lower" when it is below 1, and "not resolved" otherwise.
Prints Markdown; also writes ``benchmarks/results/peers.md``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import noisevar
from noisevar.estimators.compare import run_monte_carlo

RESULTS = Path(__file__).resolve().parent / "results"
PEERS = ("mle-level", "mle-trend")


def _cell(task: tuple[str, int, int, int]) -> tuple[str, int, dict[str, np.ndarray], float]:
    """Relative errors of auto, the MLE peers and the oracle on the same ``runs`` signals."""
    family, n, runs, seed = task
    t0 = time.perf_counter()
    mc = run_monte_carlo(family, runs=runs, methods=["auto", *PEERS], n=n, seed=seed)
    errors = {m: np.asarray(mc.relative_errors[m], dtype=float) for m in ("auto", *PEERS)}
    errors["oracle"] = oracle_errors(family, n, runs, seed)
    return family, n, errors, time.perf_counter() - t0


def oracle_errors(family: str, n: int, runs: int, seed: int) -> np.ndarray:
    """Relative errors of the mean square of the actual noise, on the runs of ``_cell``.

    The estimator that knows the clean signal (run ``i`` is ``generate(family,
    seed=seed + i)``, as in :func:`noisevar.estimators.compare.monte_carlo`, whose
    target is the first run's mean noise variance). For noise of one level it
    is the efficient unbiased estimator (its RMSE is the Cramér-Rao floor
    ``sqrt(2/n)`` up to the runs' scatter); where the level varies along the
    record, it is the best an estimator can do that assumes nothing about how.
    """
    truth = noisevar.generate(family, n=n, seed=seed).true_variance
    out = np.empty(runs)
    for i in range(runs):
        g = noisevar.generate(family, n=n, seed=seed + i)
        out[i] = np.mean((g.measured - g.clean) ** 2) / truth - 1.0
    return out


def ratio_interval(
    e_peer: np.ndarray, e_auto: np.ndarray, draws: int = 4000, seed: int = 0
) -> tuple[float, float, float, int]:
    """``RMSE(peer) / RMSE(auto)`` over the runs both finished, with a paired bootstrap 95 % CI."""
    ok = np.isfinite(e_peer) & np.isfinite(e_auto)
    p2, a2 = e_peer[ok] ** 2, e_auto[ok] ** 2
    k = p2.size
    ratio = float(np.sqrt(p2.mean() / a2.mean()))
    idx = np.random.default_rng(seed).integers(0, k, size=(draws, k))
    boot = np.sqrt(p2[idx].mean(axis=1) / a2[idx].mean(axis=1))
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return ratio, float(lo), float(hi), k


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print Markdown."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1, help="the seed of benchmarks/accuracy.py")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 6000])
    ap.add_argument("--families", nargs="+", default=noisevar.signal_names())
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args(argv)
    all_families = noisevar.signal_names()
    tasks = [
        # the seed formula of benchmarks/accuracy.py: the same signals as its runs
        (f, n, args.runs, args.seed + 100_000 * all_families.index(f) + n)
        for n in args.sizes
        for f in args.families
    ]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        cells = list(pool.map(_cell, tasks, chunksize=1))
    elapsed = time.perf_counter() - t0
    lines = [
        "### `auto` against the state-space MLE, paired (`python benchmarks/peers.py`)",
        "",
        f"{args.runs} runs per cell, the same signals for the three estimators (the seeds of "
        "`benchmarks/accuracy.py`). Ratio = RMSE(peer) / RMSE(auto) of the relative variance "
        "error, with a paired bootstrap 95 % interval (4000 resamples of the runs): above 1 means "
        "`auto` is more accurate. Verdict: *auto lower* when the whole interval is above 1, "
        "*peer lower* when it is below 1, otherwise *not resolved* (the difference is within "
        "what this many runs can tell). *Oracle*: the mean square of the actual noise on the "
        "same runs, an estimator that knows the clean signal (for noise of one level its "
        "expected RMSE is the Cramér-Rao floor, below which no unbiased estimator's can be; "
        "where the level varies, it is the best an estimator can do that assumes nothing about "
        "how); the two ÷ oracle columns are RMSE ratios to it.",
        "",
        "| family | n | RMSE oracle | RMSE auto | auto ÷ oracle | peer | RMSE peer "
        "| peer ÷ oracle | ratio peer ÷ auto | 95 % interval | verdict |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    counts = {"auto lower": 0, "peer lower": 0, "not resolved": 0}
    tied: list[float] = []  # peer ÷ oracle where auto and the peer are not resolved
    for family, n, errors, _ in cells:
        e_auto = errors["auto"]
        rmse_auto = float(np.sqrt(np.nanmean(e_auto**2)))
        rmse_oracle = float(np.sqrt(np.mean(errors["oracle"] ** 2)))
        for peer in PEERS:
            ratio, lo, hi, k = ratio_interval(errors[peer], e_auto)
            verdict = "auto lower" if lo > 1.0 else "peer lower" if hi < 1.0 else "not resolved"
            counts[verdict] += 1
            rmse_peer = float(np.sqrt(np.nanmean(errors[peer] ** 2)))
            failed = int(np.sum(~np.isfinite(errors[peer])))
            note = f" ({failed} failed)" if failed else ""
            if verdict == "not resolved":
                tied.append(rmse_peer / rmse_oracle)
            lines.append(
                f"| {family} | {n} | {100 * rmse_oracle:.2f} % | {100 * rmse_auto:.2f} % | "
                f"{rmse_auto / rmse_oracle:.3f} | {peer}{note} | {100 * rmse_peer:.2f} % | "
                f"{rmse_peer / rmse_oracle:.3f} | {ratio:.3f} | {lo:.3f}–{hi:.3f} | "
                + (f"**{verdict}**" if verdict != "auto lower" else verdict)
                + " |"
            )
    lines += [
        "",
        f"Of {sum(counts.values())} comparisons: auto lower in {counts['auto lower']}, "
        f"peer lower in {counts['peer lower']}, not resolved in {counts['not resolved']} "
        f"(total {elapsed:.0f} s on {args.workers} workers).",
    ]
    if tied:
        lines += [
            "",
            f"Where auto and the peer are not resolved, the peer's RMSE is "
            f"{min(tied):.3f}–{max(tied):.3f} times the oracle's.",
        ]
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "peers.md").write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
