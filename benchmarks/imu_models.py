"""IMU noise models: GMWM composite fits (`fit_imu_model`) against the issue's targets.

Sections (each can run alone with ``--only``; the others are kept from the last file):

1. ``ros``: allan_variance_ros's own simulator configuration (400 Hz, 3 h; white noise
   plus a bias random walk, Kalibr's model), ``seeds`` IMUs x 6 axes: N and K per axis,
   the model chosen, K's 68 % interval coverage; ``inertial_noise`` (IEEE-952 NNLS),
   allan-variance-analyzer's line reads and a plain allantools pipeline beside it.
2. ``composite``: white + quantisation + one or two Gauss-Markov + random walk, known
   truth: each parameter's error, interval coverage, right model chosen.
3. ``robust``: 0.1 % of the samples replaced by outliers at 20 sigma: N robust/classical.
4. ``speed``: 6 axes x 7.2e6 samples, composite fit with model choice: wall and CPU, each
   tool in a fresh process, 3 repeats interleaved,
   against allan-variance-analyzer's Allan variance and line fits on the same record.

Results: benchmarks/results/imu_models.md. allan-variance-analyzer is a benchmark-only
dependency (``pip install allan-variance-analyzer``); without it its columns say so.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import allantools
import numpy as np

from noisevar.noise_model import fit_imu_model, inertial_noise
from noisevar.noise_model.simulate import simulate_inertial

RESULTS = Path(__file__).resolve().parent / "results"
OUT = RESULTS / "imu_models.md"
TITLE = "### IMU noise models (GMWM): `python benchmarks/imu_models.py`"
ROS = {"accelerometer": (0.002502, 6.97e-5), "gyroscope": (1.888e-4, 2.557e-6)}
CI = 0.6826894921370859
#: z of a 95 % interval over that of the 68.3 % one the fits give (intervals are
#: symmetric in the log-parameters, so the log half-widths scale by this).
Z95 = 1.959963984540054


def covers(value: float, interval: tuple[float, float], truth: float) -> tuple[float, float]:
    """Whether the 68.3 % interval and the 95 % one (its log half-widths x 1.96) hold the truth."""
    lo, hi = interval
    if not (value > 0 and lo > 0):
        return (float(lo <= truth <= hi), float(lo <= truth <= hi))
    lo95 = value * (lo / value) ** Z95
    hi95 = value * (hi / value) ** Z95
    return (float(lo <= truth <= hi), float(lo95 <= truth <= hi95))


def allantools_lines(y: np.ndarray, rate: float) -> dict[str, float]:
    """Textbook line reads on allantools' OADEV: the slope -1/2 tangent's value at 1 s (N),
    the slope +1/2 tangent's at 3 s (K), and B = the minimum / 0.664."""
    taus, dev, _, _ = allantools.oadev(y, rate=rate, data_type="freq", taus="octave")
    return {
        "N": float(np.min(dev * np.sqrt(taus))),
        "K": float(np.min(dev * np.sqrt(3.0 / taus))),
        "B": float(dev.min() / 0.664),
    }


def ava_lines(data: np.ndarray, rate: float) -> tuple[np.ndarray, np.ndarray] | None:
    """allan-variance-analyzer's Allan deviation and line reads (N at 1 s, K at 3 s)."""
    try:
        from allan_variance_analyzer.analysis import (
            compute_rate_random_walk,
            compute_white_noise_params,
        )
        from allan_variance_analyzer.statistics import compute_allan_variances
    except ImportError:
        return None
    periods = np.round(np.arange(0.1, 1000, 0.1), 1)
    periods = periods[periods * rate * 4 < data.shape[0]]
    adev = np.sqrt(compute_allan_variances(data.copy(), periods, rate, 0))
    brk = int(np.where(periods == 10)[0][0])
    ns, ks = [], []
    for i in range(0, data.shape[1], 3):
        ns.append(compute_white_noise_params(periods, adev[:, i : i + 3], brk)[0])
        ks.append(compute_rate_random_walk(periods, adev[:, i : i + 3])[0])
    return np.concatenate(ns), np.concatenate(ks)


def ros_section(seeds: int, hours: float) -> list[str]:
    rate = 400.0
    n = int(hours * 3600 * rate)
    rows: dict[str, list[list[float]]] = {s: [] for s in ROS}
    for seed in range(seeds):
        cols, truth = [], []
        for k, (sensor, (nd, kd)) in enumerate(ROS.items()):
            for a in range(3):
                s = 1000 * seed + 10 * k + a
                cols.append(simulate_inertial(n, rate, random_walk=nd, rate_random_walk=kd, seed=s))
                truth.append((sensor, nd, kd))
        x = np.column_stack(cols)
        fits = fit_imu_model(x, rate)
        ieee = inertial_noise(x.T, rate)
        ava = ava_lines(x, rate)
        for j, (sensor, nd, kd) in enumerate(truth):
            f = fits[j]
            k_cov = (
                covers(f.value("K"), f.parameter("K").interval, kd) if "RW" in f.keys else (0, 0)
            )
            plain = allantools_lines(x[:, j], rate)
            rows[sensor].append(
                [
                    f.value("N") / nd - 1,
                    f.value("K") / kd - 1,
                    float(k_cov[0]),
                    float(f.model == "WN+RW"),
                    ieee[j].random_walk / nd - 1,
                    ieee[j].rate_random_walk / kd - 1,
                    plain["N"] / nd - 1,
                    plain["K"] / kd - 1,
                    (ava[0][j] / nd - 1) if ava else math.nan,
                    (ava[1][j] / kd - 1) if ava else math.nan,
                    float(k_cov[1]),
                ]
            )
        print(f"ros seed {seed} done", file=sys.stderr)
    lines = [
        "#### allan_variance_ros's simulator configuration, per axis",
        "",
        f"400 Hz, {hours:g} h ({n} samples), white noise + bias random walk; {seeds} IMUs x 3 "
        "axes per sensor. Errors: median [worst low, worst high]. K coverage: share of the "
        "axes whose 68.3 % (95 %) interval holds the truth.",
        "",
        "| sensor | tool | N error | K error | axes below -30 % (K) | K coverage 68 % (95 %) | "
        "WN+RW chosen |",
        "|---|---|---|---|---|---|---|",
    ]
    for sensor, r in rows.items():
        a = np.array(r)
        for name, cn, ck in [
            ("fit_imu_model (GMWM)", 0, 1),
            ("inertial_noise (IEEE-952 NNLS)", 4, 5),
            ("allantools OADEV + line reads", 6, 7),
            ("allan-variance-analyzer", 8, 9),
        ]:
            cov = f"{a[:, 2].mean():.0%} ({a[:, 10].mean():.0%})" if cn == 0 else ""
            chosen = f"{a[:, 3].mean():.0%}" if cn == 0 else ""
            lines.append(
                f"| {sensor} | {name} | {_spread(a[:, cn])} | {_spread(a[:, ck])} | "
                f"{int(np.sum(a[:, ck] < -0.3))} of {len(a)} | {cov} | {chosen} |"
            )
    return lines


def _spread(e: np.ndarray) -> str:
    if np.all(np.isnan(e)):
        return "not installed"
    return f"{np.median(e):+.2%} [{np.min(e):+.1%}, {np.max(e):+.1%}]"


COMPOSITE = {
    "one GM": dict(Q=1.29e-4, N=1e-3, K=1e-5, GM=((5e-4, 50.0),)),
    "two GM": dict(Q=1.29e-4, N=1e-3, K=1e-5, GM=((2e-3, 2.0), (5e-4, 100.0))),
}
#: The same with a random walk 4x stronger: visible over the last 1.5 decades of scales
#: instead of the last 2-3 scales (``--strong-rw``).
STRONG_RW = {k: {**v, "K": 4 * v["K"]} for k, v in COMPOSITE.items()}


def simulate_truth(t: dict, n: int, rate: float, seed: int) -> np.ndarray:
    """A record of the composite truth ``t`` (``Q``, ``N``, ``K``, ``GM``) at ``rate``."""
    return simulate_inertial(
        n,
        rate,
        quantization=t["Q"],
        random_walk=t["N"],
        rate_random_walk=t["K"],
        gauss_markov=t["GM"],
        seed=seed,
    )


def _truth(base: dict, rng: np.random.Generator) -> dict:
    """One run's truth: a scale over two decades for all terms, and a factor per term
    log-uniform within +-0.15 decade (each process stays visible)."""
    scale = 10 ** rng.uniform(-1.0, 1.0)

    def f() -> float:
        return 10 ** rng.uniform(-0.15, 0.15)

    gm = tuple((s * scale * f(), t * f()) for s, t in base["GM"])
    return dict(
        Q=base["Q"] * scale * f(), N=base["N"] * scale * f(), K=base["K"] * scale * f(), GM=gm
    )


def composite_section(
    runs: int, hours: float, models: dict = COMPOSITE, truths: tuple[str, ...] = ()
) -> list[str]:
    rate = 200.0
    n = int(hours * 3600 * rate)
    lines = [
        "#### Composite models with known truth",
        "",
        f"200 Hz, {hours:g} h ({n} samples), {runs} runs per model, base K "
        f"{models['one GM']['K']:g}; per run one scale over two "
        "decades (log-uniform) for all amplitudes, times a factor per parameter within "
        "+-0.15 decade. Error: median |relative error| [90th percentile]; coverage of the "
        "68.3 % delta-method intervals and of the 95 % ones; model chosen by the stepwise "
        "Hannan-Quinn search.",
        "",
        "| truth | parameter | median abs. error | 90 % | coverage 68.3 % | coverage 95 % "
        "| right model |",
        "|---|---|---|---|---|---|---|",
    ]
    for c, (label, base) in enumerate(models.items()):
        if truths and label not in truths:
            continue
        rng = np.random.default_rng(7 + c)
        want = "QN+WN+" + ("GM" if len(base["GM"]) == 1 else "2GM") + "+RW"
        errs: dict[str, list[float]] = {}
        cover: dict[str, list[tuple[float, float]]] = {}
        right = []
        t0 = time.perf_counter()
        for r in range(runs):
            t = _truth(base, rng)
            y = simulate_truth(t, n, rate, 5000 + 100 * c + r)
            fit = fit_imu_model(y, rate)
            right.append(fit.model == want)
            named = {"Q": t["Q"], "N": t["N"], "K": t["K"]}
            for i, (s, tc) in enumerate(sorted(t["GM"], key=lambda g: g[1])):
                gm = f"GM{i + 1}" if len(t["GM"]) > 1 else "GM1"
                named[f"{gm}.sigma"], named[f"{gm}.tau_c"] = s, tc
            for name, true in named.items():
                got = fit.value(name)
                errs.setdefault(name, []).append(abs(got / true - 1))
                hit = covers(got, fit.parameter(name).interval, true) if got > 0 else (0, 0)
                cover.setdefault(name, []).append(hit)
        print(
            f"composite {label}: {runs} runs in {time.perf_counter() - t0:.0f} s", file=sys.stderr
        )
        for name in errs:
            e, h = np.array(errs[name]), np.array(cover[name])
            lines.append(
                f"| {label} | {name} | {np.median(e):.2%} | {np.quantile(e, 0.9):.2%} | "
                f"{h[:, 0].mean():.0%} | {h[:, 1].mean():.0%} | {np.mean(right):.0%} |"
            )
    return lines


def robust_section(runs: int, hours: float) -> list[str]:
    rate = 200.0
    n = int(hours * 3600 * rate)
    nd, kd = 1e-3, 1e-5
    rob, cla = [], []
    for r in range(runs):
        y = simulate_inertial(n, rate, random_walk=nd, rate_random_walk=kd, seed=9000 + r)
        rng = np.random.default_rng(r)
        bad = rng.choice(n, n // 1000, replace=False)
        y[bad] = 20.0 * nd * math.sqrt(rate) * rng.choice([-1.0, 1.0], bad.size)
        rob.append(fit_imu_model(y, rate, robust=True).value("N") / nd - 1)
        cla.append(fit_imu_model(y, rate).value("N") / nd - 1)
    return [
        "#### Robust fit with outliers",
        "",
        f"White noise N = {nd:g} + random walk K = {kd:g}, 200 Hz, {hours:g} h, {runs} runs; "
        "0.1 % of the samples replaced by +-20 sigma (sigma the white noise's per-sample std).",
        "",
        "| fit | N error, median [worst] |",
        "|---|---|",
        f"| robust (Huber wavelet variance) | {np.median(rob):+.2%} [{max(rob, key=abs):+.2%}] |",
        f"| classical | {np.median(cla):+.2%} [{max(cla, key=abs):+.2%}] |",
    ]


#: The speed section's tools, each run in a fresh process on the same saved record.
SPEED_TOOLS = {
    "fit_imu_model": "fit_imu_model, 6 axes, model choice",
    "ava": "allan-variance-analyzer, Allan variance + line fits",
    "inertial_noise": "inertial_noise (IEEE-952 NNLS)",
}
SPEED_REPEATS = 3


def speed_record() -> np.ndarray:
    """6 axes x 7.2e6 samples (10 h at 200 Hz) of the one-GM composite model."""
    rate, n = 200.0, 7_200_000
    base = COMPOSITE["one GM"]
    return np.column_stack([simulate_truth(base, n, rate, s) for s in range(6)])


def speed_worker(tool: str, path: Path) -> None:
    """One tool on the saved record, in this fresh process: prints wall and CPU (s).

    The CPU is ``resource.getrusage`` of this process (all its threads: user + system)
    from after the record is loaded to the end of the tool's call.
    """
    x = np.load(path)
    rate = 200.0
    run = {
        "fit_imu_model": lambda: fit_imu_model(x, rate),
        "ava": lambda: ava_lines(x, rate),
        "inertial_noise": lambda: inertial_noise(x.T, rate),
    }[tool]
    r0, w0 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
    res = run()
    r1, w1 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    print(json.dumps({"wall": w1 - w0, "cpu": cpu, "ok": res is not None}))


def _load() -> str:
    """The 1-minute load average (as ``uptime`` shows it)."""
    return f"{os.getloadavg()[0]:.1f}"


def speed_section() -> list[str]:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "record.npy"
        np.save(path, speed_record())
        runs: dict[str, list[tuple[float, float, str]]] = {t: [] for t in SPEED_TOOLS}
        ok = dict.fromkeys(SPEED_TOOLS, True)
        for _ in range(SPEED_REPEATS):  # interleaved: each repeat runs every tool
            for tool in SPEED_TOOLS:
                load = _load()
                cmd = [sys.executable, __file__, "--speed-worker", tool, str(path)]
                out = subprocess.run(cmd, capture_output=True, text=True, check=True)
                res = json.loads(out.stdout.strip().splitlines()[-1])
                ok[tool] = ok[tool] and res["ok"]
                runs[tool].append((res["wall"], res["cpu"], load))
                print(tool, res, "load", load, file=sys.stderr)
    lines = [
        "#### Speed",
        "",
        "6 axes x 7.2e6 samples (10 h at 200 Hz), white + quantisation + GM + random walk, "
        f"saved once; each tool in a fresh process on it, {SPEED_REPEATS} repeats "
        "interleaved (each repeat runs every tool in turn). CPU: `resource.getrusage` of "
        "the process (all threads, user + system) around the call, after loading. The "
        "machine is shared (2 cores): the 1-minute load average before each run is given; "
        "wall times are loaded, CPU times less so.",
        "",
        "| tool | wall (s) per repeat | CPU (s) per repeat | load before each | "
        "median wall | median CPU |",
        "|---|---|---|---|---|---|",
    ]
    for tool, name in SPEED_TOOLS.items():
        if not ok[tool]:
            lines.append(f"| {name} | not installed | | | | |")
            continue
        w, c, ld = zip(*runs[tool], strict=True)
        lines.append(
            f"| {name} | {', '.join(f'{v:.1f}' for v in w)} | "
            f"{', '.join(f'{v:.2f}' for v in c)} | {', '.join(ld)} | "
            f"{np.median(w):.1f} | {np.median(c):.2f} |"
        )
    if ok["ava"] and ok["fit_imu_model"]:
        ours, ava = runs["fit_imu_model"], runs["ava"]
        cpu = [o[1] / a[1] for o, a in zip(ours, ava, strict=True)]
        wall = [o[0] / a[0] for o, a in zip(ours, ava, strict=True)]
        lines += [
            "",
            "fit_imu_model / allan-variance-analyzer, per repeat (adjacent runs): CPU "
            f"{', '.join(f'{r:.2f}' for r in cpu)} (median {np.median(cpu):.2f}); wall "
            f"{', '.join(f'{r:.2f}' for r in wall)} (median {np.median(wall):.2f}).",
        ]
    return lines


SECTIONS = ("ros", "composite", "robust", "speed")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10, help="IMUs in the ros section")
    ap.add_argument("--ros-hours", type=float, default=3.0)
    ap.add_argument("--runs", type=int, default=20, help="runs per composite model")
    ap.add_argument("--hours", type=float, default=10.0, help="composite record length")
    ap.add_argument("--robust-runs", type=int, default=10)
    ap.add_argument("--only", choices=SECTIONS, nargs="+")
    ap.add_argument("--strong-rw", action="store_true", help="composite with K x 4")
    ap.add_argument(
        "--truths", nargs="+", default=(), help='composite truths to run ("one GM", "two GM")'
    )
    ap.add_argument("--out", type=Path, default=OUT, help="results file (sections kept)")
    ap.add_argument("--speed-worker", nargs=2, metavar=("TOOL", "RECORD"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.speed_worker:
        speed_worker(args.speed_worker[0], Path(args.speed_worker[1]))
        return
    wanted = set(args.only or SECTIONS)
    kept = _previous_sections(args.out)
    run = {
        "ros": lambda: ros_section(args.seeds, args.ros_hours),
        "composite": lambda: composite_section(
            args.runs, args.hours, STRONG_RW if args.strong_rw else COMPOSITE, tuple(args.truths)
        ),
        "robust": lambda: robust_section(args.robust_runs, 1.0),
        "speed": speed_section,
    }
    out = [TITLE, ""]
    for name in SECTIONS:
        block = run[name]() if name in wanted else kept.get(name)
        if block:
            out += [*block, ""]
        args.out.parent.mkdir(exist_ok=True)
        args.out.write_text("\n".join(out), encoding="utf-8")
    print("\n".join(out))


def _previous_sections(path: Path) -> dict[str, list[str]]:
    if not path.is_file():
        return {}
    heads = {
        "#### allan_variance_ros": "ros",
        "#### Composite": "composite",
        "#### Robust": "robust",
        "#### Speed": "speed",
    }
    out: dict[str, list[str]] = {}
    current = None
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#### "):
            current = next((v for k, v in heads.items() if line.startswith(k)), None)
        if current:
            out.setdefault(current, []).append(line)
    return {k: v[:-1] if v and not v[-1] else v for k, v in out.items()}


if __name__ == "__main__":
    main()
