"""Heavy-tailed noise: ``auto``'s RMSE against each simple peer's (issue 26 item 8).

    python benchmarks/heavy_tails.py              # 200 seeded runs per cell, n = 6000
    python benchmarks/heavy_tails.py --family-runs 50   # 50 on the accuracy families
    python benchmarks/heavy_tails.py --runs 40    # a quick look
    python benchmarks/heavy_tails.py --somd       # somd among the peers (as slow as the rest)

Noise: Student-t with 3 and 5 dof and Laplace, scaled to variance ``std²`` by
:mod:`noisevar.synth`. Signals: a slow sine (amplitude 10 std, period 1000 samples), the
fast signal of ``benchmarks/glitches_fast.py`` (four sinusoids of 15-80 samples per period,
amplitudes 5-30 std) and the clean signals of ``benchmarks/accuracy.py``'s families (noise at
the family's own std). Per cell (noise, signal): the RMSE of ``.variance`` relative to the
process variance ``std²`` of ``auto`` (through :func:`noisevar.estimate`, diagnostics and
all) and of each simple peer (the same way), on the same seeded records, and the
ratio ``RMSE(auto) / RMSE(best peer)`` with a paired bootstrap 95 % interval (runs resampled
together). Target: ``auto`` no worse than the best simple peer, i.e. the ratio's interval
reaches down to 1 or below. Writes ``benchmarks/results/heavy_tails.md``. Every cell draws
the same seeded noise, so ``noise-step`` and ``noise-ramp`` (one clean signal, two noise
profiles, which this benchmark replaces) give the same row.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import noisevar
from noisevar import synth
from noisevar.errors import NoisevarError

sys.path.insert(0, str(Path(__file__).resolve().parent))
from accuracy import FAMILIES  # noqa: E402
from glitches_fast import _fast  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
N = 6000
PEERS = ("rice", "diff2", "hkt2", "somd")
#: The peers timed by default (somd costs as much as the other three together: --somd)
FAST_PEERS = ("rice", "diff2", "hkt2")
NOISES = {
    "student-t 5 dof": ("student_t", {"dof": 5.0}),
    "student-t 3 dof": ("student_t", {"dof": 3.0}),
    "laplace": ("laplace", {}),
}


def _signal(name: str, run: int) -> tuple[np.ndarray, float]:
    """The clean signal of run ``run`` and the noise std it is measured with."""
    if name == "slow sine":
        return 10.0 * np.sin(2 * np.pi * np.arange(N) / 1000.0 + 0.1 * run), 1.0
    if name == "fast":
        return _fast(N, np.random.default_rng(100 + run)), 1.0
    g = noisevar.generate(name, n=N, seed=1 + run)
    return g.clean, float(np.sqrt(g.true_variance))


def _relative(z: NDArray, method: str, variance: float) -> float:
    """The relative error of ``method``'s variance (NaN when the method refuses the record)."""
    try:
        return noisevar.estimate(z, method=method).variance / variance - 1.0
    except NoisevarError:
        return float("nan")


def cell(task: tuple[str, str, int, tuple[str, ...]]) -> dict[str, np.ndarray]:
    """Relative errors of ``auto`` and each peer on ``runs`` seeded records."""
    noise, signal, runs, peers = task
    kind, params = NOISES[noise]
    err: dict[str, list[float]] = {m: [] for m in ("auto", *peers)}
    for r in range(runs):
        clean, std = _signal(signal, r)
        draw = synth.noise(kind, N, rng=5000 + r, std=std, **params)
        z = clean + draw.values
        for m in err:
            err[m].append(_relative(z, m, draw.variance))
    return {m: np.asarray(v) for m, v in err.items()}


def ratio_interval(
    e_auto: np.ndarray, e_peer: np.ndarray, draws: int = 4000, seed: int = 0
) -> tuple[float, float, float]:
    """``RMSE(auto) / RMSE(peer)`` with a paired bootstrap 95 % interval."""
    ok = np.isfinite(e_auto) & np.isfinite(e_peer)
    a2, p2 = e_auto[ok] ** 2, e_peer[ok] ** 2
    idx = np.random.default_rng(seed).integers(0, a2.size, size=(draws, a2.size))
    boot = np.sqrt(a2[idx].mean(axis=1) / p2[idx].mean(axis=1))
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return float(np.sqrt(a2.mean() / p2.mean())), float(lo), float(hi)


def _row(noise: str, signal: str, e: dict[str, np.ndarray]) -> tuple[str, bool]:
    """One table row and whether ``auto`` is no worse than the best peer.

    A peer that refuses more than a tenth of the records is shown (with its refusals)
    but not a contender; RMSEs are over the records each method estimated.
    """
    peers = [m for m in e if m != "auto"]
    done = {m: np.isfinite(v) for m, v in e.items()}
    rmse = {m: 100 * float(np.sqrt(np.mean(v[done[m]] ** 2))) for m, v in e.items()}
    contenders = [m for m in peers if done[m].mean() >= 0.9]
    best = min(contenders, key=rmse.__getitem__)
    ratio, lo, hi = ratio_interval(e["auto"], e[best])
    ok = lo <= 1.0
    cells = [
        f"{rmse[m]:.2f}" + ("" if done[m].all() else f" ({(~done[m]).sum()} refused)")
        for m in peers
    ]
    row = (
        f"| {noise} | {signal} | {rmse['auto']:.2f} | {' | '.join(cells)} | "
        f"{ratio:.3f} ({lo:.3f}-{hi:.3f}) vs {best} | {'yes' if ok else 'NO'} |"
    )
    return row, ok


def main(argv: list[str] | None = None) -> int:
    """Run every cell and print (and write) the Markdown table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--family-runs", type=int, default=None, help="runs on accuracy's families")
    ap.add_argument("--somd", action="store_true", help="somd among the peers (slow)")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args(argv)
    family_runs = args.family_runs or args.runs
    runs = {"slow sine": args.runs, "fast": args.runs} | {f: family_runs for f in FAMILIES}
    peers = PEERS if args.somd else FAST_PEERS
    head = " | ".join(f"{m} RMSE %" for m in peers)
    lines = [
        f"# Heavy tails: auto against the simple peers (n = {N}, {args.runs} runs per cell"
        + ("" if family_runs == args.runs else f", {family_runs} on accuracy's families")
        + ")",
        "",
        f"load: {os.getloadavg()[0]:.1f}",
        "",
        f"| noise | signal | auto RMSE % | {head} | auto / best peer (95 % CI) | no worse |",
        "|---|---|---|" + "---|" * len(peers) + "---|---|",
    ]
    t0, fails = time.perf_counter(), 0
    tasks = [(noise, signal, n, peers) for signal, n in runs.items() for noise in NOISES]
    with ProcessPoolExecutor(args.workers) as pool:
        for (noise, signal, _, _), e in zip(tasks, pool.map(cell, tasks), strict=True):
            row, ok = _row(noise, signal, e)
            fails += not ok
            lines.append(row)
            print(row, flush=True)
    lines += ["", f"{fails} cells where auto is worse; {time.perf_counter() - t0:.0f} s"]
    text = "\n".join(lines) + "\n"
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "heavy_tails.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
