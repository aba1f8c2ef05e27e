"""The Kalman fit on glitches and heavy tails (issue 26 class 8): r's bias, RMSE, ci95 coverage.

    python benchmarks/kalman_glitches.py --runs 200  # the results file: 200 records per family
    python benchmarks/kalman_glitches.py             # 100 per family, about 4 min
    python benchmarks/kalman_glitches.py --runs 40   # a quick look
    python benchmarks/kalman_glitches.py --out /tmp/x.md   # elsewhere (e.g. on another checkout)
    python benchmarks/kalman_glitches.py --signals "cv track" --noises Gaussian   # one family

Families: four signals x four noises, ``n = 3000`` samples each, ``fit_kalman`` with its
defaults (``method="auto"``) on the model named.

Signals (per sample, no rate): a constant-velocity track (``q = 1e-3``, fitted ``"cv"``), a
constant-acceleration track (``q = 1e-5``, ``"ca"``), a random walk (``q = 0.1``, ``"rw"``),
all simulated from :func:`~noisevar.noise_model.kalman_fit.kinematic_model`'s own ``F`` and
``Q`` (so ``q`` has a truth), and a slow sine (amplitude 10, period 1000 samples, fitted
``"cv"``; no ``q`` truth). Noises (:func:`noisevar.synth.noise`, unit ``std``): Gaussian,
``contaminated`` (1 % of samples drawn at 10x std: variance 1.99, kurtosis 77), Student-t 5 dof
and Laplace.

Per family: r's mean relative error against the record's realised noise variance
(``mean(v²)``, glitches in) and against the process variance (what a filter should be told),
its RMSE against the process variance, and how often r's ci95 covers the process variance
(the parameter an interval is for; target 90-98 %) and the realised one; the median ci95
half-width (in %, geometric); q's mean relative error and coverage where q has a truth.
Targets (issue 26 item 8): |bias| <= 2 %, coverage 90-98 %, every family. Writes
``benchmarks/results/kalman_glitches.md``.
"""

from __future__ import annotations

import argparse
import platform
import shlex
import sys
import time
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from noisevar import synth  # noqa: E402
from noisevar.noise_model import fit_kalman  # noqa: E402
from noisevar.noise_model.kalman_fit import kinematic_model  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
N = 3000
#: Signal name -> (fitted model, true q per sample or None).
SIGNALS: dict[str, tuple[str, float | None]] = {
    "cv track": ("cv", 1e-3),
    "ca track": ("ca", 1e-5),
    "random walk": ("rw", 0.1),
    "slow sine": ("cv", None),
}
#: Noise label -> (synth kind, parameters).
NOISES: dict[str, tuple[str, dict]] = {
    "Gaussian": ("gauss", {}),
    "1 % at 10σ": ("contaminated", {"fraction": 0.01, "factor": 10.0}),
    "Student-t 5": ("student_t", {"dof": 5.0}),
    "Laplace": ("laplace", {}),
}
BIAS_MAX, COVER = 0.02, (0.90, 0.98)


def _signal(name: str, n: int, rng: np.random.Generator) -> NDArray:
    model, q = SIGNALS[name]
    if q is None:
        return 10.0 * np.sin(2 * np.pi * np.arange(n) / 1000.0 + rng.uniform(0, 2 * np.pi))
    F, _, Q1 = kinematic_model(model, 1.0)
    w = rng.standard_normal((n, F.shape[0])) @ np.linalg.cholesky(q * Q1).T
    x, pos = np.zeros(F.shape[0]), np.empty(n)
    for k in range(n):  # simulation only
        x = F @ x + w[k]
        pos[k] = x[0]
    return pos


def _cell(signal: str, noise: str, runs: int, n: int) -> dict[str, float]:
    model, q_true = SIGNALS[signal]
    kind, params = NOISES[noise]
    rel_real, rel_proc, cover_p, cover_r, half, q_rel, q_cover = ([] for _ in range(7))
    for i in range(runs):
        v = synth.noise(kind, n, rng=1000 + i, **params)  # the same noise for every signal
        z = _signal(signal, n, np.random.default_rng(5000 + i)) + v.values
        t = fit_kalman(z, model)
        realised = float(np.mean(v.values**2))
        lo, hi = t.r_interval
        rel_real.append(t.r / realised - 1.0)
        rel_proc.append(t.r / v.variance - 1.0)
        cover_p.append(lo <= v.variance <= hi)
        cover_r.append(lo <= realised <= hi)
        half.append(np.sqrt(hi / lo) - 1.0)
        if q_true is not None:
            q_rel.append(t.q / q_true - 1.0)
            q_cover.append(t.q_interval[0] <= q_true <= t.q_interval[1])
    return {
        "bias_real": float(np.mean(rel_real)),
        "bias_proc": float(np.mean(rel_proc)),
        "rmse": float(np.sqrt(np.mean(np.square(rel_proc)))),
        "cover_p": float(np.mean(cover_p)),
        "cover_r": float(np.mean(cover_r)),
        "half": float(np.median(half)),
        "q_bias": float(np.mean(q_rel)) if q_rel else float("nan"),
        "q_cover": float(np.mean(q_cover)) if q_cover else float("nan"),
    }


def _row(signal: str, noise: str, runs: int, c: dict[str, float]) -> str:
    ok = abs(c["bias_real"]) <= BIAS_MAX and COVER[0] <= c["cover_p"] <= COVER[1]
    q_bias, q_cover = (
        ("-", "-")
        if np.isnan(c["q_bias"])
        else (f"{100 * c['q_bias']:+.1f} %", f"{100 * c['q_cover']:.1f} %")
    )
    return (
        f"| {signal} ({SIGNALS[signal][0]}) | {noise} | {runs} | {100 * c['bias_real']:+.2f} % | "
        f"{100 * c['bias_proc']:+.2f} % | {100 * c['rmse']:.1f} % | {100 * c['cover_p']:.1f} % | "
        f"{100 * c['cover_r']:.1f} % | ±{100 * c['half']:.1f} % | {q_bias} | {q_cover} | "
        f"{'pass' if ok else 'FAIL'} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100, help="seeded records per family")
    ap.add_argument("--n", type=int, default=N, help="samples per record")
    ap.add_argument("--out", type=Path, default=RESULTS / "kalman_glitches.md")
    ap.add_argument("--note", default="", help="a line under the title (which code ran)")
    ap.add_argument("--signals", nargs="+", default=list(SIGNALS), choices=list(SIGNALS))
    ap.add_argument("--noises", nargs="+", default=list(NOISES), choices=list(NOISES))
    args = ap.parse_args()
    t0 = time.perf_counter()
    lines = [
        "# The Kalman fit on glitches and heavy tails",
        "",
        *([args.note, ""] if args.note else []),
        f"`python benchmarks/kalman_glitches.py {shlex.join(sys.argv[1:])}` ({args.n} samples per "
        f"record, {platform.python_version()}). r's bias against the realised noise variance "
        "(glitches in) and the process variance, RMSE against the process variance, ci95 "
        "coverage of the process variance (target 90-98 %) and of the realised one, the median "
        "ci95 half-width; q's mean relative error and coverage where q has a truth. Pass: "
        "|bias| <= 2 % and coverage 90-98 %.",
        "",
        "| signal (model) | noise | runs | r bias (realised) | r bias (process) | r RMSE "
        "| ci95 covers process var | covers realised | ci95 half-width | q bias | q covers "
        "| pass |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for signal in args.signals:
        for noise in args.noises:
            row = _row(signal, noise, args.runs, _cell(signal, noise, args.runs, args.n))
            print(row, flush=True)
            lines.append(row)
    lines += ["", f"Run time {time.perf_counter() - t0:.0f} s.", ""]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
