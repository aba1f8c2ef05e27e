"""K's bias, spread and interval coverage against the information bound (issue 30).

On allan_variance_ros's simulator configuration (400 Hz, 3 h, white noise + bias random
walk, the same records as ``imu_models.py --only ros``: seed ``1000 s + 10 k + a``), per
axis, on the SAME records:

- ``fit_imu_model`` (GMWM, model chosen) and the same with the model fixed to WN+RW;
- ``inertial_noise`` (IEEE-952 NNLS on the Allan variance);
- a Whittle maximum-likelihood fit of WN+RW on the first differences (the efficient
  reference; benchmark-only code below), its interval from ``fisher_bound`` at its
  estimate;
- ``fisher_bound`` at the truth: the relative sd any efficient estimator has.

Each run appends its axes to ``results/imu_k_bias_axes.csv`` (``--first``/``--seeds``
chunks may run in parallel processes); ``--table`` writes ``results/imu_k_bias.md`` from
every axis in that file. Also ``--one-gm``: the bound of issue 30's composite one-GM truth
and of issue 27's single record.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats
from scipy.signal import windows

from noisevar.noise_model import fisher_bound, fit_imu_model, inertial_noise
from noisevar.noise_model.simulate import simulate_inertial

sys.path.insert(0, str(Path(__file__).resolve().parent))
from imu_models import COMPOSITE, ROS, _truth, covers, simulate_truth  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
AXES = RESULTS / "imu_k_bias_axes.csv"
#: ``--ieee``: inertial_noise alone, rerun after its intervals' change (same records).
IEEE_AXES = RESULTS / "imu_k_bias_ieee.csv"
OUT = RESULTS / "imu_k_bias.md"
RATE = 400.0
HOURS = 3.0
Z68, Z95 = stats.norm.ppf(0.5 + 0.6826894921370859 / 2), stats.norm.ppf(0.975)
TOOLS = ("gmwm", "gmwm_wnrw", "ieee", "whittle")
NAMES = {
    "gmwm": "fit_imu_model (GMWM, model chosen)",
    "gmwm_wnrw": "fit_imu_model, model fixed WN+RW",
    "ieee": "inertial_noise (IEEE-952 NNLS)",
    "whittle": "Whittle ML of WN+RW (reference)",
}


#: Tukey taper's cosine fraction on the differences (:func:`whittle_wn_rw`).
TAPER = 0.1


def whittle_wn_rw(y: np.ndarray, iters: int = 50) -> tuple[float, float]:
    """Whittle ML of white noise ``s2`` + random walk ``g2`` (per sample) on the differences.

    ``S(f) = 4 sin^2(pi f) s2 + g2``; Fisher scoring in the logs from a line start. The
    differences are tapered (Tukey, :data:`TAPER`): untapered, the DFT of differenced
    white noise carries the end-to-end term ``w_m - w_0`` at every frequency, a floor of
    ``2 s2 / m`` that is 90x the random walk's ``g2`` on this configuration.
    """
    d = np.diff(y)
    m = _smooth_below(d.size)  # a 5-smooth length: the FFT of 4 319 999 takes 9 s
    d = d[:m]
    h = windows.tukey(m, TAPER)
    per = np.abs(np.fft.rfft(d * h)[1:]) ** 2 / np.sum(h * h)  # k = 1 .. m // 2
    f = np.arange(1, per.size + 1) / m
    w = np.ones_like(f)
    if m % 2 == 0:
        w[-1] = 0.5
    sin2 = 4.0 * np.sin(np.pi * f) ** 2
    x = np.log([np.median(per[per.size // 2 :] / sin2[per.size // 2 :]), np.mean(per[:8])])
    for _ in range(iters):
        a, b = sin2 * math.exp(x[0]), np.full_like(f, math.exp(x[1]))
        s = a + b
        g = np.array([a / s, b / s])
        score = (g * w) @ (per / s - 1.0)
        step = np.linalg.solve((g * w) @ g.T, score)
        x = x + np.clip(step, -2.0, 2.0)
        if np.max(np.abs(step)) < 1e-9:
            break
    return math.exp(x[0]), math.exp(x[1])


def _smooth_below(m: int) -> int:
    """The largest ``2^a 3^b 5^c`` not above ``m``."""
    best = 1
    for a in range(int(math.log2(m)) + 1):
        for b in range(int(math.log(m, 3)) + 1):
            v = 2**a * 3**b
            if v > m:
                break
            while v * 5 <= m:
                v *= 5
            best = max(best, v)
    return best


def one_seed(seed: int) -> list[dict]:
    x, truth = _records(seed)
    n = x.shape[0]
    auto = fit_imu_model(x, RATE)
    fixed = fit_imu_model(x, RATE, models=["WN+RW"])
    ieee = inertial_noise(x.T, RATE)
    rows = []
    for j, (sensor, a, nd, kd) in enumerate(truth):
        sd_true = fisher_bound("WN+RW", {"N": nd, "K": kd}, n, RATE).sd("K")
        s2, g2 = whittle_wn_rw(x[:, j])
        kw, nw = math.sqrt(g2 * RATE), math.sqrt(s2 / RATE)
        sd_hat = fisher_bound("WN+RW", {"N": nw, "K": kw}, n, RATE).sd("K")
        row = dict(seed=seed, sensor=sensor, axis=a, truth=kd, bound=sd_true)
        for tool, fit in (("gmwm", auto[j]), ("gmwm_wnrw", fixed[j])):
            k = fit.value("K")
            hit = covers(k, fit.parameter("K").interval, kd) if k > 0 else (0.0, 0.0)
            row.update({f"{tool}_k": k, f"{tool}_c68": hit[0], f"{tool}_c95": hit[1]})
            row[f"{tool}_model"] = fit.model
        t = ieee[j].term("K")
        lo, hi = t.interval
        row.update(ieee_k=t.value, ieee_c68=float(lo <= kd <= hi), ieee_c95=math.nan)
        row.update(ieee_model="IEEE")
        row.update(
            whittle_k=kw,
            whittle_c68=float(abs(math.log(kw / kd)) <= Z68 * sd_hat),
            whittle_c95=float(abs(math.log(kw / kd)) <= Z95 * sd_hat),
            whittle_model="WN+RW",
        )
        rows.append(row)
    return rows


def _records(seed: int) -> tuple[np.ndarray, list[tuple[str, int, float, float]]]:
    n = int(HOURS * 3600 * RATE)
    cols, truth = [], []
    for k, (sensor, (nd, kd)) in enumerate(ROS.items()):
        for a in range(3):
            s = 1000 * seed + 10 * k + a
            cols.append(simulate_inertial(n, RATE, random_walk=nd, rate_random_walk=kd, seed=s))
            truth.append((sensor, a, nd, kd))
    return np.column_stack(cols), truth


def run_ieee(first: int, seeds: int) -> None:
    """inertial_noise alone on the same records: K and its 68.3 % interval's coverage."""
    for seed in range(first, first + seeds):
        x, truth = _records(seed)
        rows = []
        for (sensor, a, _, kd), fit in zip(truth, inertial_noise(x.T, RATE), strict=True):
            lo, hi = fit.term("K").interval
            rows.append(
                dict(
                    seed=seed,
                    sensor=sensor,
                    axis=a,
                    truth=kd,
                    k=fit.term("K").value,
                    c68=float(lo <= kd <= hi),
                )
            )
        append_rows(IEEE_AXES, rows)
        print(f"ieee seed {seed}", file=sys.stderr)


def append_rows(path: Path, rows: list[dict]) -> None:
    """Append ``rows`` to the CSV ``path`` (its header first when the file is new)."""
    new = not path.exists()
    with path.open("a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        if new:
            w.writeheader()
        w.writerows(rows)


def run(first: int, seeds: int) -> None:
    RESULTS.mkdir(exist_ok=True)
    for seed in range(first, first + seeds):
        t0 = time.perf_counter()
        rows = one_seed(seed)
        append_rows(AXES, rows)
        print(f"seed {seed}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)


def clopper(hits: int, total: int) -> tuple[float, float]:
    """Clopper-Pearson 95 % interval of a proportion."""
    lo = stats.beta.ppf(0.025, hits, total - hits + 1) if hits > 0 else 0.0
    hi = stats.beta.ppf(0.975, hits + 1, total - hits) if hits < total else 1.0
    return float(lo), float(hi)


def _median_sd(e: np.ndarray, rng: np.random.Generator) -> float:
    """Bootstrap standard deviation of the median."""
    idx = rng.integers(0, e.size, size=(2000, e.size))
    return float(np.std(np.median(e[idx], axis=1)))


def _rate(c: np.ndarray) -> str:
    c = c[~np.isnan(c)]
    if c.size == 0:
        return "-"
    lo, hi = clopper(int(c.sum()), c.size)
    return f"{c.mean():.0%} [{lo:.0%}, {hi:.0%}]"


def table() -> list[str]:
    with AXES.open() as fh:
        rows = list(csv.DictReader(fh))
    seeds = sorted({int(r["seed"]) for r in rows})
    rng = np.random.default_rng(0)
    lines = [
        "### K against the information bound: `python benchmarks/imu_k_bias.py --table`",
        "",
        f"allan_variance_ros's configuration (400 Hz, 3 h, WN + RW), {len(seeds)} seeds "
        f"({seeds[0]}-{seeds[-1]}) x 3 axes per sensor, every tool on the same records. "
        "Error of K per axis: median (bootstrap sd of the median) [worst low, worst high]; "
        "sd of log error beside the bound's (`fisher_bound` at the truth: any efficient "
        "estimator's); coverage of the 68.3 % and 95 % intervals with their Clopper-Pearson "
        "95 % interval.",
        "",
        "The `--ieee` row reruns `inertial_noise` alone on the same records: its intervals "
        "changed in b637e13 (bootstrap draws correlated across taus); the `--seeds` rows "
        "hold the code of their run (here seeds 0-60 ran before b637e13, in two processes "
        "of 30 at load 10-34).",
        "",
        "| sensor | tool | K error median (sd) | worst low, high | sd log error | bound sd | "
        "below -30 % | cover 68.3 % | cover 95 % | WN+RW chosen |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    ieee_rows = list(csv.DictReader(IEEE_AXES.open())) if IEEE_AXES.exists() else []
    for sensor in ROS:
        sub = [r for r in rows if r["sensor"] == sensor]
        truth = np.array([float(r["truth"]) for r in sub])
        bound = np.median([float(r["bound"]) for r in sub])
        for tool in TOOLS:
            k = np.array([float(r[f"{tool}_k"]) for r in sub])
            e = k / truth - 1.0
            logs = np.log(np.maximum(k, 1e-300) / truth)[k > 0]
            chosen = np.mean([r[f"{tool}_model"] == "WN+RW" for r in sub])
            chosen_txt = f"{chosen:.0%}" if tool == "gmwm" else "-"
            lines.append(
                f"| {sensor} | {NAMES[tool]} | {np.median(e):+.2%} ({_median_sd(e, rng):.2%}) | "
                f"{e.min():+.1%}, {e.max():+.1%} | {np.std(logs):.3f} ({int(np.sum(k <= 0))} "
                f"at 0) | {bound:.3f} | {int(np.sum(e < -0.3))} of {e.size} | "
                f"{_rate(np.array([float(r[f'{tool}_c68']) for r in sub]))} | "
                f"{_rate(np.array([float(r[f'{tool}_c95']) for r in sub]))} | "
                f"{chosen_txt} |"
            )
            more = [r for r in ieee_rows if r["sensor"] == sensor]
            if tool == "ieee" and more:
                e = np.array([float(r["k"]) / float(r["truth"]) - 1 for r in more])
                c = np.array([float(r["c68"]) for r in more])
                lines.append(
                    f"| {sensor} | inertial_noise, intervals correlated across taus (`--ieee`, "
                    f"seeds {more[0]['seed']}-{more[-1]['seed']}) | {np.median(e):+.2%} | "
                    f"{e.min():+.1%}, {e.max():+.1%} | {np.std(np.log1p(e)):.3f} | {bound:.3f} | "
                    f"{int(np.sum(e < -0.3))} of {e.size} | {_rate(c)} | - | - |"
                )
    return lines


def one_gm_lines() -> list[str]:
    """The bound of issue 30's composite one-GM truth and of issue 27's single record."""
    base = {"Q": 1.29e-4, "N": 1e-3, "GM1.sigma": 5e-4, "GM1.tau_c": 50.0, "K": 1e-5}
    n = int(10 * 3600 * 200)
    b = fisher_bound("QN+WN+GM+RW", base, n, 200.0)
    lines = [
        "",
        "#### The bound on issue 30's composite truth and issue 27's single record",
        "",
        "| record | parameter | bound sd | median abs. error at the bound | "
        "P(abs. error < target) at the bound |",
        "|---|---|---|---|---|",
    ]
    for name in b.names:
        s = b.sd(name)
        target = 0.03 if name == "N" else 0.10
        lines.append(
            f"| one GM, 10 h at 200 Hz (base truth) | {name} | {s:.2%} | "
            f"{math.expm1(stats.norm.ppf(0.75) * s):.2%} | {b.within(name, target):.0%} "
            f"(< {target:.0%}) |"
        )
    lines += composite_runs_lines(n)
    n3 = int(HOURS * 3600 * RATE)
    for sensor, (nd, kd) in ROS.items():
        r = fisher_bound("WN+RW", {"N": nd, "K": kd}, n3, RATE)
        lines.append(
            f"| ROS config, 3 h at 400 Hz, {sensor} | K | {r.sd('K'):.2%} | "
            f"{math.expm1(stats.norm.ppf(0.75) * r.sd('K')):.2%} | "
            f"{r.within('K', 0.03):.0%} (< 3 %) |"
        )
        e = np.expm1(r.sd("K") * np.random.default_rng(2).standard_normal((20000, 30)))
        lines.append(
            f"| ROS config, {sensor}, 30 axes (10 IMUs) | K | | | P(30-axis median within "
            f"3 %) = {np.mean(np.abs(np.median(e, axis=1)) < 0.03):.0%}; P(no axis below "
            f"-30 %) = {np.mean(np.min(e, axis=1) > -0.3):.0%} |"
        )
    return lines + kalibr_lines()


def kalibr_lines(seconds: float = 11000.0) -> list[str]:
    """Issue 27's single record (``exports.py``: 11000 s at 400 Hz): the Kalibr file keeps
    the largest of the three axes' K, so at the bound its error is the max of three."""
    out = []
    n = int(seconds * RATE)
    z = np.random.default_rng(3).standard_normal((100000, 3))
    for sensor, (nd, kd) in ROS.items():
        s = fisher_bound("WN+RW", {"N": nd, "K": kd}, n, RATE).sd("K")
        top = np.expm1(s * z.max(axis=1))
        out.append(
            f"| issue 27's record ({seconds:g} s), {sensor}, Kalibr's K (largest of 3 axes) | K "
            f"| {s:.2%} per axis | the largest's median {np.median(top):+.2%} "
            f"[90 %: {np.quantile(top, 0.05):+.1%}, {np.quantile(top, 0.95):+.1%}] | "
            f"{np.mean(np.abs(top) < 0.03):.0%} (< 3 %) |"
        )
    return out


def composite_runs_lines(n: int, runs: int = 20) -> list[str]:
    """The bound on each of the 20 truths of ``imu_models.py --only composite --truths
    "one GM"`` (the same generator), and the median abs. error an efficient estimator
    would have over them (seeded Monte Carlo of the normal log errors)."""
    rng = np.random.default_rng(7)  # composite_section's generator for "one GM"
    sds = {}
    for _ in range(runs):
        t = _truth(COMPOSITE["one GM"], rng)
        ((sigma, tc),) = t["GM"]
        vals = {"Q": t["Q"], "N": t["N"], "GM1.sigma": sigma, "GM1.tau_c": tc, "K": t["K"]}
        b = fisher_bound("QN+WN+GM+RW", vals, n, 200.0)
        for name in b.names:
            sds.setdefault(name, []).append(b.sd(name))
    mc = np.random.default_rng(1)
    out = []
    for name, v in sds.items():
        e = np.abs(np.expm1(np.array(v) * mc.standard_normal((20000, runs))))
        med = np.median(e, axis=1)
        target = 0.03 if name == "N" else 0.10
        out.append(
            f"| one GM, the {runs} runs' truths | {name} | {np.median(v):.2%} "
            f"[{np.min(v):.2%}, {np.max(v):.2%}] | median over runs {np.median(med):.2%} "
            f"(90 % of {runs}-run medians in [{np.quantile(med, 0.05):.2%}, "
            f"{np.quantile(med, 0.95):.2%}]) | P(median < {target:.0%}) = "
            f"{np.mean(med < target):.0%} |"
        )
    return out


def composite_spread(runs: int) -> list[str]:
    """GMWM on the composite one-GM records of ``imu_models.py --only composite`` (same
    truths and seeds): each parameter's log error, its sd against the bound's rms, its
    median abs. error against a normal one's at the bound."""
    rate, n = 200.0, int(10 * 3600 * 200)
    rng = np.random.default_rng(7)
    errs: dict[str, list[float]] = {}
    sds: dict[str, list[float]] = {}
    for r in range(runs):
        t = _truth(COMPOSITE["one GM"], rng)
        ((sigma, tc),) = t["GM"]
        vals = {"Q": t["Q"], "N": t["N"], "GM1.sigma": sigma, "GM1.tau_c": tc, "K": t["K"]}
        y = simulate_truth(t, n, rate, 5000 + r)
        fit = fit_imu_model(y, rate)
        b = fisher_bound("QN+WN+GM+RW", vals, n, rate)
        for name, v in vals.items():
            got = fit.value(name)
            errs.setdefault(name, []).append(math.log(got / v) if got > 0 else math.nan)
            sds.setdefault(name, []).append(b.sd(name))
    lines = [
        "",
        f"#### GMWM's spread on the composite one-GM runs ({runs} runs, `--composite {runs}`)",
        "",
        "| parameter | sd of log error (runs with the term) | bound rms | median abs. error | "
        "a normal estimator's at the bound | 90 % abs. error | normal's at the bound |",
        "|---|---|---|---|---|---|---|",
    ]
    z = np.random.default_rng(4).standard_normal((4000, runs))
    for name, e in errs.items():
        e, s = np.array(e), np.array(sds[name])
        ok = np.isfinite(e)
        normal = np.abs(np.expm1(z * s))
        lines.append(
            f"| {name} | {np.std(e[ok]):.3f} ({ok.sum()} of {runs}) | "
            f"{math.sqrt(np.mean(s**2)):.3f} | {np.median(np.abs(np.expm1(e[ok]))):.2%} | "
            f"{np.median(np.median(normal, axis=1)):.2%} | "
            f"{np.quantile(np.abs(np.expm1(e[ok])), 0.9):.2%} | "
            f"{np.median(np.quantile(normal, 0.9, axis=1)):.2%} |"
        )
    return lines


TWO_GM_HEAD = "#### The bound on issue 30's composite two-GM truth"


def two_gm_lines() -> list[str]:
    """The bound of issue 30's composite two-GM truth (``imu_models.py --truths "two GM"``),
    with its random walk as given and x 4 (``--strong-rw``): what any efficient estimator
    can reach on 10 h at 200 Hz."""
    n = int(10 * 3600 * 200)
    lines = [
        "",
        TWO_GM_HEAD,
        "",
        "| truth | parameter | bound sd | median abs. error at the bound | "
        "P(abs. error < 10 %) at the bound |",
        "|---|---|---|---|---|",
    ]
    for label, k in (("K 1e-5", 1e-5), ("K x 4 (--strong-rw)", 4e-5)):
        vals = {
            "Q": 1.29e-4,
            "N": 1e-3,
            "GM1.sigma": 2e-3,
            "GM1.tau_c": 2.0,
            "GM2.sigma": 5e-4,
            "GM2.tau_c": 100.0,
            "K": k,
        }
        b = fisher_bound("QN+WN+GM+GM+RW", vals, n, 200.0)
        for name in b.names:
            s = b.sd(name)
            lines.append(
                f"| two GM, {label} | {name} | {s:.2%} | "
                f"{math.expm1(stats.norm.ppf(0.75) * s):.2%} | {b.within(name, 0.10):.0%} |"
            )
    return lines


def replace_section(text: str, head: str, lines: list[str]) -> str:
    """``text`` with the section starting at ``head`` (to the next ``####`` or the load
    line) replaced by ``lines``, or ``lines`` added before the load line."""
    body = text.rstrip("\n").split("\n")
    tail = [i for i, line in enumerate(body) if line.startswith("Load average")]
    end = tail[0] if tail else len(body)
    if head in body:
        start = body.index(head) - 1
        nxt = [i for i in range(start + 2, len(body)) if body[i].startswith("####")]
        end = nxt[0] - 1 if nxt else end
        return "\n".join(body[:start] + lines + body[end:]) + "\n"
    return "\n".join(body[:end] + lines + [""] + body[end:]) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--seeds", type=int, default=0)
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--composite", type=int, default=0, help="runs of the one-GM spread")
    ap.add_argument("--ieee", action="store_true", help="inertial_noise alone (--first, --seeds)")
    ap.add_argument("--two-gm", action="store_true", help="the two-GM truth's bound, into the file")
    args = ap.parse_args()
    if args.seeds:
        (run_ieee if args.ieee else run)(args.first, args.seeds)
    if args.two_gm:
        lines = two_gm_lines()
        OUT.write_text(replace_section(OUT.read_text(), TWO_GM_HEAD, lines))
        print("\n".join(lines))
    if args.table:
        load = os.getloadavg()
        lines = table() + one_gm_lines()
        if args.composite:
            lines += composite_spread(args.composite)
        lines += ["", f"Load average when the table was written: {load[0]:.1f}."]
        OUT.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
