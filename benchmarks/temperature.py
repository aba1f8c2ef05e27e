"""Temperature model on simulated gyros: bias(T) slope and warm-up time constant (§E9).

    python benchmarks/temperature.py               # 20 runs per configuration (a few minutes)
    python benchmarks/temperature.py --runs 5
    python benchmarks/temperature.py --weights 60   # also profiled vs oracle K vs no weights

Each run simulates one gyro axis for 10 h at 100 Hz: bias ``a + b (T - 25 °C)`` plus a
power-on transient ``A exp(-t/tau)``, on a slow temperature ramp (the temperature sensor has
0.05 °C of white noise). Each run draws its own truth: ``b`` log-uniform in
[0.5, 2] x 1.7e-4 rad/s/°C (0.01 °/s/°C), ``tau`` log-uniform in [300, 1200] s, ``A`` in
±[0.5, 2] x 1e-3 rad/s, ``a`` in ±2e-3 rad/s. The noise is allan_variance_ros's gyroscope:
white N = 1.888e-4 rad/s/√Hz, and in the second and third configurations its rate random
walk K = 2.557e-6 rad/s²/√Hz too (a random bias drift, not driven by T).

Configurations: ``white`` (ramp 5 -> 45 °C), ``white + K`` (same ramp), ``white + K, up and
down`` (5 -> 45 -> 5 °C). ``temperature_model`` runs with its defaults (order and warm-up
chosen by BIC). Targets (issue 30): b within 5 %, tau within 20 %; the median and the worst
absolute relative error over the runs, the intervals' coverage (68.3 % stated) and the
model choice are reported.

Prints Markdown; also writes ``benchmarks/results/temperature.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from noisevar.noise_model import _temperature_fit as tf
from noisevar.noise_model import temperature_model
from noisevar.noise_model.simulate import simulate_thermal
from noisevar.noise_model.temperature import TARGET_BLOCKS
from noisevar.noise_model.temperature_bound import model_bound, temperature_bound

RESULTS = Path(__file__).resolve().parent / "results"
RATE = 100.0
HOURS = 10.0
N_GYRO, K_GYRO = 1.888e-4, 2.557e-6
CONFIGS = {
    "white": (0.0, False),
    "white + K": (K_GYRO, False),
    "white + K, up and down": (K_GYRO, True),
}
TARGETS = {"b": 0.05, "tau": 0.20}
Z68 = 0.9945  # the 68.3 % two-sided normal quantile (ONE_SIGMA)


def _truth(rng: np.random.Generator) -> dict[str, float]:
    sign = rng.choice([-1.0, 1.0], size=2)
    return {
        "a": float(rng.uniform(-2e-3, 2e-3)),
        "b": float(1.7e-4 * np.exp(rng.uniform(np.log(0.5), np.log(2.0)))),
        "A": float(sign[0] * 1e-3 * np.exp(rng.uniform(np.log(0.5), np.log(2.0)))),
        "tau": float(np.exp(rng.uniform(np.log(300.0), np.log(1200.0)))),
    }


def _temperature(n: int, updown: bool, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """True and measured temperature (°C)."""
    s = np.linspace(0.0, 1.0, n)
    true = 5.0 + 40.0 * (1.0 - np.abs(2.0 * s - 1.0) if updown else s)
    return true, true + 0.05 * rng.standard_normal(n)


def _record(seed: int, k: float, updown: bool):
    """The truth, true and measured temperature, and the gyro samples of one run."""
    rng = np.random.default_rng(seed)
    truth = _truth(rng)
    n = int(HOURS * 3600 * RATE)
    true_t, meas_t = _temperature(n, updown, rng)
    y = simulate_thermal(
        true_t,
        RATE,
        polynomial=(truth["a"], truth["b"]),
        warmup=(truth["A"], truth["tau"]),
        random_walk=N_GYRO,
        rate_random_walk=k,
        seed=seed + 1,
    )
    return truth, true_t, meas_t, y


def one_run(seed: int, k: float, updown: bool) -> dict[str, float]:
    truth, true_t, meas_t, y = _record(seed, k, updown)
    t0 = time.process_time()
    m = temperature_model(y, meas_t, RATE, unit="rad/s", seed=seed)
    cpu = time.process_time() - t0
    b = m.coefficient("b")
    out = _bound_columns(true_t, meas_t, truth, k, m)
    out |= {
        "b_err": b.value / truth["b"] - 1.0,
        "b_cov": float(b.interval[0] <= truth["b"] <= b.interval[1]),
        "order": m.order,
        "cpu": cpu,
        "warm": float(m.warmup is not None),
        "tau_err": np.nan,
        "tau_cov": np.nan,
    }
    if m.warmup is not None:
        lo, hi = m.warmup.time_constant_interval
        out["tau_err"] = m.warmup.time_constant / truth["tau"] - 1.0
        out["tau_cov"] = float(lo <= truth["tau"] <= hi)
    return out


def _bound_columns(true_t, meas_t, truth, k, m) -> dict[str, float]:
    """The Cramér-Rao bound at the truth, and the fit's z-scores and asymptotic coverage."""
    bound = temperature_bound(true_t, RATE, white=N_GYRO, walk=k, warmup=(truth["A"], truth["tau"]))
    b = m.coefficient("b").value
    out = {
        "sd_b": bound.sd("b") / truth["b"],
        "sd_tau": bound.sd("log_time_constant"),
        "z_b": (b - truth["b"]) / bound.sd("b"),
        "z_tau": np.nan,
        "fisher_b_cov": np.nan,
        "fisher_tau_cov": np.nan,
    }
    # the same bound at the fit's own estimates (N, K, A, tau, order): an asymptotic interval
    est = model_bound(m, meas_t)
    out["fisher_b_cov"] = float(abs(b - truth["b"]) <= Z68 * est.sd("b"))
    if m.warmup is not None:
        log_err = np.log(m.warmup.time_constant / truth["tau"])
        out["z_tau"] = log_err / bound.sd("log_time_constant")
        out["fisher_tau_cov"] = float(abs(log_err) <= Z68 * est.sd("log_time_constant"))
    return out


def at_bound(sd: np.ndarray, log: bool, seed: int = 5) -> tuple[float, float]:
    """Median over draws of the median and worst |error| of an efficient estimator.

    Each run's error is normal with the bound's standard deviation (of ``ln tau`` for tau).
    """
    z = np.random.default_rng(seed).standard_normal((20000, sd.size)) * sd
    err = np.abs(np.expm1(z)) if log else np.abs(z)
    return float(np.median(np.median(err, axis=1))), float(np.median(err.max(axis=1)))


def _pct(x: float) -> str:
    return f"{100 * x:.2f} %"


def section(runs: int, name: str, k: float, updown: bool) -> tuple[str, dict]:
    rows = [one_run(1000 * i + 17, k, updown) for i in range(runs)]
    b = np.abs([r["b_err"] for r in rows])
    tau = np.abs([r["tau_err"] for r in rows if r["warm"]])
    found = int(sum(r["warm"] for r in rows))
    summary = {
        "b_med": float(np.median(b)),
        "b_max": float(np.max(b)),
        "b_cov": float(np.mean([r["b_cov"] for r in rows])),
        "tau_med": float(np.median(tau)) if tau.size else np.nan,
        "tau_max": float(np.max(tau)) if tau.size else np.nan,
        "tau_cov": float(np.nanmean([r["tau_cov"] for r in rows])) if tau.size else np.nan,
        "found": found,
        "linear": int(sum(r["order"] == 1 for r in rows)),
        "cpu": float(np.median([r["cpu"] for r in rows])),
    }
    s = summary
    ok_b = (
        "yes"
        if s["b_max"] <= TARGETS["b"]
        else ("median only" if s["b_med"] <= TARGETS["b"] else "**no**")
    )
    ok_t = (
        "yes"
        if found == runs and s["tau_max"] <= TARGETS["tau"]
        else ("median only" if s["tau_med"] <= TARGETS["tau"] else "**no**")
    )
    line = (
        f"| {name} | {_pct(s['b_med'])} / {_pct(s['b_max'])} | {ok_b} | {_pct(s['b_cov'])} | "
        f"{found}/{runs} | {_pct(s['tau_med'])} / {_pct(s['tau_max'])} | {ok_t} | "
        f"{_pct(s['tau_cov'])} | {s['linear']}/{runs} | {s['cpu']:.2f} s |"
    )
    return line, _bound_line(name, rows), summary


def _rms(x: list[float]) -> float:
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x**2))) if x.size else np.nan


def _bound_line(name: str, rows: list[dict]) -> str:
    """One row of the Cramér-Rao table: the bound, an efficient estimator, the fit."""
    sd_b = np.array([r["sd_b"] for r in rows])
    sd_t = np.array([r["sd_tau"] for r in rows])
    b_med, b_max = at_bound(sd_b, log=False)
    t_med, t_max = at_bound(sd_t, log=True)
    fb = np.nanmean([r["fisher_b_cov"] for r in rows])
    ft = np.nanmean([r["fisher_tau_cov"] for r in rows])
    return (
        f"| {name} | {_pct(np.median(sd_b))} ({_pct(sd_b.min())}-{_pct(sd_b.max())}) | "
        f"{_pct(b_med)} / {_pct(b_max)} | {_rms([r['z_b'] for r in rows]):.2f} | "
        f"{_pct(np.median(sd_t))} ({_pct(sd_t.min())}-{_pct(sd_t.max())}) | "
        f"{_pct(t_med)} / {_pct(t_max)} | {_rms([r['z_tau'] for r in rows]):.2f} | "
        f"{_pct(fb)} | {_pct(ft)} |"
    )


@contextmanager
def _weights(ratio: float | None):
    """Fix the walk/white ratio of the fit's weights (None: profiled, as the package does).

    A benchmark-only probe of the package's private weighting: ``ratio`` is ``q/s2``.
    """
    saved = tf.Axis.estimate_white
    if ratio is not None:
        tf.Axis.estimate_white = lambda ax, order, warm: ax.with_white(  # noqa: ARG005
            tf.Whitener.make(ratio, 1.0, ax.y.size - 1)
        )
    try:
        yield
    finally:
        tf.Axis.estimate_white = saved


def weights_check(runs: int) -> list[str]:
    """RMS of error / bound on the up-and-down runs: profiled, oracle and no walk weights.

    Order 1 and the warm-up imposed (no model choice); also the fit on the true temperature.
    """
    h = (int(HOURS * 3600 * RATE) // TARGET_BLOCKS) / RATE
    oracle = K_GYRO**2 * h / (N_GYRO**2 / h - K_GYRO**2 * h / 6.0)
    cases = {
        "profiled (the package)": (None, False),
        "oracle K (true walk/white ratio)": (oracle, False),
        "levels-OLS (no walk)": (0.0, False),
        "profiled, true temperature": (None, True),
    }
    z = {name: ([], []) for name in cases}
    for i in range(runs):
        truth, true_t, meas_t, y = _record(1000 * i + 17, K_GYRO, True)
        bound = temperature_bound(
            true_t, RATE, white=N_GYRO, walk=K_GYRO, warmup=(truth["A"], truth["tau"])
        )
        for name, (ratio, exact) in cases.items():
            with _weights(ratio):
                m = temperature_model(
                    y, true_t if exact else meas_t, RATE, order=1, warmup=True, bootstrap=10
                )
            z[name][0].append((m.coefficient("b").value - truth["b"]) / bound.sd("b"))
            log_err = np.log(m.warmup.time_constant / truth["tau"])
            z[name][1].append(log_err / bound.sd("log_time_constant"))
    lines = [
        "",
        f"Weights, on {runs} runs of `white + K, up and down` (order 1 and the warm-up "
        "imposed): RMS of the error over the Cramér-Rao standard deviation "
        f"(`--weights {runs}`).",
        "",
        "| weights | b RMS z | ln tau RMS z |",
        "|---|---|---|",
    ]
    for name, (zb, zt) in z.items():
        lines.append(f"| {name} | {_rms(zb):.3f} | {_rms(zt):.3f} |")
    return lines


BOUND_HEAD = [
    "",
    "Information limit: the Cramér-Rao bound of each run at its truth "
    "(`noisevar.noise_model.temperature_bound`: the inverse Fisher information of the block "
    "means under the record's N and K, the warm-up included), as a standard deviation relative "
    "to the truth (tau: of ln tau), median (range) over the runs. *Efficient*: the median and "
    "worst error over these runs that an unbiased estimator at the bound would give (median "
    "of 20000 draws). *RMS z*: the fit's errors over the bound's standard deviation (1 = at "
    "the bound). *Asymptotic coverage*: the bound at the fit's own estimates as a 68.3 % "
    "interval.",
    "",
    "| configuration | b bound | b efficient: median / worst | b RMS z | tau bound "
    "| tau efficient: median / worst | tau RMS z | b asymptotic coverage "
    "| tau asymptotic coverage |",
    "|---|---|---|---|---|---|---|---|---|",
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--out", type=Path, default=RESULTS / "temperature.md")
    ap.add_argument("--configs", nargs="+", choices=list(CONFIGS), default=list(CONFIGS))
    ap.add_argument(
        "--weights",
        type=int,
        default=0,
        metavar="RUNS",
        help="also compare the fit's weights (profiled, oracle K, none) on RUNS runs",
    )
    args = ap.parse_args()
    head = [
        "### Temperature model (`python benchmarks/temperature.py`)",
        "",
        f"{args.runs} runs per configuration, 10 h at 100 Hz, one gyro axis each; "
        f"{platform.python_version()}, {os.cpu_count()} CPUs. Errors are absolute relative "
        "errors: median / worst. Coverage of the 68.3 % intervals. Targets: b 5 %, tau 20 %.",
        "",
        "| configuration | b error | b within 5 % | b coverage | warm-up found | tau error "
        "| tau within 20 % | tau coverage | order 1 chosen | CPU per fit |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines, bound_lines = [], []
    for name in args.configs:
        k, updown = CONFIGS[name]
        line, bound_line, _ = section(args.runs, name, k, updown)
        print(line, bound_line, sep="\n", flush=True)
        lines.append(line)
        bound_lines.append(bound_line)
    weights = weights_check(args.weights) if args.weights else []
    text = "\n".join(head + lines + BOUND_HEAD + bound_lines + weights) + "\n"
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)


if __name__ == "__main__":
    main()
