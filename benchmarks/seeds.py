"""Benchmark of the four seed-paper methods (issue 6): targets against measured.

    python benchmarks/seeds.py              # 100 runs each, writes results/seeds.md
    python benchmarks/seeds.py --runs 20    # quicker
    python benchmarks/seeds.py --kappa-selection   # + the held-out κ study (seeds 1-5)
    python benchmarks/seeds.py --slip-runs 0       # without the 1000-run carrier slip study

Runs, one after the other, exactly the commands a user would type::

    noisevar experiment fusion   --runs N --seed 0 --format json
    noisevar experiment outliers --runs N --seed 0 --format json
    noisevar experiment carrier  --runs N --seed 0 --cn0 30 --format json
    noisevar experiment latency  --runs N --seed 0 --format json

then, for context, the Huber κ trade-off table (``outliers --kappa-sweep
1.345,1.5,2,2.5,3``, the same runs for every κ) and the carrier comparison
with other design dynamics (``--nominal-doppler-rate 100, 5, 1`` Hz/s
against the scenario's 25 Hz/s),
times each (wall clock, including the interpreter start, and CPU time),
checks the targets of issue 6 against the JSON metrics, and prints a
Markdown section (also written to ``benchmarks/results/seeds.md``), with the
carrier C/N0 sweep and the Huber κ trade-off table. A target that does not
hold is reported as such, with its numbers.

A fraction of 100 runs cannot tell 0 slips from 1 %, so the carrier's slip
rates are also counted over ``--slip-runs`` (default 1000) runs at 25, 30
and 35 dB-Hz (``noisevar.systems.carrier.slip_rates``, in-process, the benchmark's
seed; about half a minute), with Wilson 95 % intervals and a paired
McNemar test against the fixed EKF, for the EKF, the AEKF and the AEKF
with the paper's running-mean start of ``R̂`` (what the AEKF was before
the window started from the design ``R``).

The carrier's ``ekf`` is the fixed EKF designed for nominal conditions
(45 dB-Hz, the scenario's dynamics) and ``aekf`` adapts from that design
(eq. 22 + our stabilised Q); the EKF with the true noise is the
``matched`` reference row. The outliers experiment runs at our default
``κ = 2.5`` (chosen on held-out seeds, see ``noisevar.systems.robust``), with the
paper's 1.345 reported next to it.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results"
TIME_TARGET_S = 30.0

COMMANDS = {
    "fusion": ["fusion"],
    "outliers": ["outliers"],
    "carrier": ["carrier", "--cn0", "30"],
    "latency": ["latency"],
}
#: Carrier comparison with other design dynamics (Hz/s; the scenario's manoeuvres are 25 Hz/s).
DESIGN_RATES = (100.0, 5.0, 1.0)
KAPPAS = "1.345,1.5,2,2.5,3"
CONTEXT = {
    "outliers-kappa": ["outliers", "--kappa-sweep", KAPPAS],
}
CONTEXT |= {
    f"carrier-design-{r:g}": [
        "carrier",
        "--cn0",
        "30",
        "--sweep",
        "25,30",
        "--nominal-doppler-rate",
        f"{r:g}",
    ]
    for r in DESIGN_RATES
}


def run_experiment(
    args: list[str], runs: int, seed: int
) -> tuple[dict[str, Any], float, float, str]:
    """Run one experiment through the CLI; return its JSON, wall and CPU time, the command."""
    cmd = [sys.executable, "-m", "noisevar", "experiment", *args]
    cmd += ["--runs", str(runs), "--seed", str(seed), "--format", "json"]
    shown = "noisevar experiment " + " ".join(cmd[4:])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode != 0:
        raise SystemExit(f"{shown} failed ({proc.returncode}): {proc.stderr.strip()}")
    return json.loads(proc.stdout), elapsed, cpu, shown


def _yes(ok: bool) -> str:
    return "yes" if ok else "**no**"


def rows_for(name: str, out: dict[str, Any]) -> list[tuple[str, str, str, bool | None]]:
    """(target, measured, verdict) rows of one experiment (verdict None: context only)."""
    m = out["metrics"]
    if name == "fusion":
        diff = m["max_abs_diff_vs_centralized"]
        return [
            (
                "fused = centralised KF, max abs diff < 1e-8",
                f"{diff:.2e} m (no feedback: {m['max_abs_diff_vs_centralized_no_feedback']:.2e})",
                "",
                diff < 1e-8,
            ),
            (
                "isolation lowers RMSE when a sensor fails (bias, VB local filters)",
                f"{m['rmse_with_isolation']:.3f} m with vs {m['rmse_without_isolation']:.3f} m "
                "without",
                "",
                m["rmse_with_isolation"] < m["rmse_without_isolation"],
            ),
            (
                "frozen sensor, fixed-R local filters (context)",
                f"{m['rmse_failures']['frozen']['fixed+isolation']:.3f} m with vs "
                f"{m['rmse_failures']['frozen']['fixed']:.1f} m without",
                "",
                m["rmse_failures"]["frozen"]["fixed+isolation"]
                < m["rmse_failures"]["frozen"]["fixed"],
            ),
            (
                "noise step: VB fusion below fixed-R fusion (context)",
                f"VB {m['rmse_vb_fusion']:.3f} m, fixed {m['rmse_fixed_fusion']:.3f} m, fixed + "
                f"isolation {m['rmse_fixed_isolation_fusion']:.3f} m, oracle "
                f"{m['rmse_oracle_fusion']:.3f} m",
                "",
                m["rmse_vb_fusion"] < m["rmse_fixed_fusion"],
            ),
        ]
    if name == "outliers":
        r_out = m["huber_over_ekf_with_outliers"]
        r_clean = m["huber_over_ekf_no_outliers"]
        lo_o, hi_o = m["huber_over_ekf_with_outliers_ci95"]
        lo_c, hi_c = m["huber_over_ekf_no_outliers_ci95"]
        mv = m["magvar_estimate_deg"] - m["magvar_true_deg"]
        k = out["settings"]["kappa"]
        return [
            (
                "Huber position RMSE <= 0.7 x plain EKF, with outliers",
                f"κ = {k:g}: {m['rmse_position_huber']:.1f} / {m['rmse_position_ekf']:.1f} m = "
                f"{r_out:.3f} (paired 95 % interval {lo_o:.3f}-{hi_o:.3f})",
                "",
                r_out <= 0.7,
            ),
            (
                "Huber = EKF within 1 % without outliers",
                f"κ = {k:g}: {m['rmse_position_huber_no_outliers']:.1f} / "
                f"{m['rmse_position_ekf_no_outliers']:.1f} m = {r_clean:.4f} "
                f"(paired 95 % interval {lo_c:.4f}-{hi_c:.4f})",
                "",
                abs(r_clean - 1) <= 0.01,
            ),
            (
                "the same at the paper's κ = 1.345 (context)",
                f"{m['huber_paper_kappa_over_ekf_with_outliers']:.3f} "
                f"({m['huber_paper_kappa_over_ekf_with_outliers_ci95'][0]:.3f}-"
                f"{m['huber_paper_kappa_over_ekf_with_outliers_ci95'][1]:.3f}) with outliers, "
                f"{m['huber_paper_kappa_over_ekf_no_outliers']:.4f} "
                f"({m['huber_paper_kappa_over_ekf_no_outliers_ci95'][0]:.4f}-"
                f"{m['huber_paper_kappa_over_ekf_no_outliers_ci95'][1]:.4f}) without"
                + (
                    ": the interval is wider than the 1 % target, these runs do not resolve it"
                    if max(abs(v - 1) for v in m["huber_paper_kappa_over_ekf_no_outliers_ci95"])
                    > 0.01
                    else ""
                ),
                "",
                None,
            ),
            (
                "magnetic variation within 0.5°",
                f"{m['magvar_estimate_deg']:.3f}° vs {m['magvar_true_deg']:.1f}° (mean over runs; "
                f"rms error {m['magvar_error_rms_deg']:.3f}°, "
                f"worst {m['magvar_error_max_abs_deg']:.3f}°)",
                "",
                abs(mv) <= 0.5,
            ),
            (
                "EKF ignoring the variation (context)",
                f"{m['rmse_position_no_bias_state']:.0f} m",
                "",
                True,
            ),
        ]
    if name == "carrier":
        ok_rms = m["rms_phase_error_aekf_rad"] < m["rms_phase_error_ekf_rad"]
        ok_slip = m["loss_of_lock_aekf"] < m["loss_of_lock_ekf"]
        none = (
            " (neither slipped: see the slip-rate study below)"
            if max(m["loss_of_lock_aekf"], m["loss_of_lock_ekf"]) == 0
            else ""
        )
        st = out["settings"]
        design = f"{st['nominal_cn0_dbhz']:g} dB-Hz / {st['nominal_doppler_rate_hz_s']:g} Hz/s"
        return [
            (
                f"AEKF RMS phase error below fixed EKF at 30 dB-Hz (EKF designed for {design})",
                f"AEKF {m['rms_phase_error_aekf_rad']:.4f} rad vs EKF "
                f"{m['rms_phase_error_ekf_rad']:.4f} rad",
                "",
                ok_rms,
            ),
            (
                "AEKF fewer cycle slips at 30 dB-Hz",
                f"AEKF {m['loss_of_lock_aekf']:.2f} vs EKF {m['loss_of_lock_ekf']:.2f} of runs"
                + none,
                "",
                ok_slip,
            ),
            (
                "reference: EKF with the true R and matched Q (context)",
                f"{m['rms_phase_error_ekf_matched_rad']:.4f} rad, "
                f"{m['loss_of_lock_ekf_matched']:.2f} slipped; AEKF with R only "
                f"{m['rms_phase_error_aekf_r_only_rad']:.4f} rad, "
                f"{m['loss_of_lock_aekf_r_only']:.2f}",
                "",
                None,
            ),
            (
                "paper's eq. 26 Q = K C_d K^T (finding: it runs away)",
                f"{m['rms_phase_error_aekf_paper_q_rad']:.4f} rad, "
                f"{m['loss_of_lock_aekf_paper_q']:.2f} slipped; Q[0,0] grew "
                f"x{m['q_phase_aekf_paper_q_growth']:.3g}",
                "",
                None,
            ),
        ]
    if name == "latency":
        err = m["estimated_delay_s"] - m["true_delay_s"]
        return [
            (
                "delay within 10 ms at 10 Hz",
                f"{m['estimated_delay_s'] * 1e3:.2f} vs {m['true_delay_s'] * 1e3:.2f} ms (mean); "
                f"rms error {m['delay_error_rms_s'] * 1e3:.2f} ms, worst "
                f"{m['delay_error_max_abs_s'] * 1e3:.2f} ms, "
                f"{100 * m['fraction_within_10ms']:.0f} % of runs within 10 ms",
                "",
                abs(err) <= 0.010,
            ),
            (
                "residual delay: none / fixed / filtered (paper 5590 / 1695 / 1115 ms)",
                f"{m['residual_delay_none_s'] * 1e3:.1f} / "
                f"{m['residual_delay_fixed_s'] * 1e3:.1f} / "
                f"{m['residual_delay_filtered_s'] * 1e3:.1f} ms (filtered, settled: "
                f"{m['residual_delay_filtered_settled_s'] * 1e3:.1f} ms)",
                "",
                m["residual_delay_filtered_settled_s"]
                < m["residual_delay_fixed_s"]
                < m["residual_delay_none_s"],
            ),
        ]
    raise ValueError(name)


SWEEP_FILTERS = (
    ("ekf", "EKF nominal"),
    ("aekf", "AEKF"),
    ("ekf_matched", "EKF matched (ref.)"),
    ("aekf_r_only", "AEKF R only"),
    ("aekf_paper_q", "AEKF eq. 26"),
)


def sweep_table(out: dict[str, Any]) -> list[str]:
    """Markdown table of the carrier C/N0 sweep (RMS phase error / fraction slipped)."""
    sw = out["metrics"]["sweep"]
    st = out["settings"]
    head = " | ".join(label for _, label in SWEEP_FILTERS)
    lines = [
        "",
        f"Carrier C/N0 sweep (design {st['nominal_cn0_dbhz']:g} dB-Hz / "
        f"{st['nominal_doppler_rate_hz_s']:g} Hz/s; the same signals for every filter at each "
        "C/N0); RMS phase error (rad) / fraction of runs that slipped:",
        "",
        f"| C/N0 (dB-Hz) | {head} |",
        "|---" * (len(SWEEP_FILTERS) + 1) + "|",
    ]
    for i, c in enumerate(sw["cn0_dbhz"]):
        cells = " | ".join(
            f"{sw[f'rms_phase_error_{n}_rad'][i]:.4f} / {sw[f'loss_of_lock_{n}'][i]:.2f}"
            for n, _ in SWEEP_FILTERS
        )
        lines.append(f"| {c:.0f} | {cells} |")
    return lines


def design_table(outs: dict[str, dict[str, Any]]) -> list[str]:
    """Markdown table of the carrier comparison for other design dynamics (context)."""
    lines = [
        "",
        "Carrier, other design dynamics (context; the scenario's manoeuvres are 25 Hz/s, the "
        "design C/N0 45 dB-Hz); RMS phase error (rad) / fraction slipped:",
        "",
        "| design rate (Hz/s) | C/N0 | " + " | ".join(label for _, label in SWEEP_FILTERS) + " |",
        "|---" * (len(SWEEP_FILTERS) + 2) + "|",
    ]
    for out in outs.values():
        sw = out["metrics"]["sweep"]
        rate = out["settings"]["nominal_doppler_rate_hz_s"]
        for i, c in enumerate(sw["cn0_dbhz"]):
            cells = " | ".join(
                f"{sw[f'rms_phase_error_{n}_rad'][i]:.4f} / {sw[f'loss_of_lock_{n}'][i]:.2f}"
                for n, _ in SWEEP_FILTERS
            )
            lines.append(f"| {rate:g} | {c:.0f} | {cells} |")
    return lines


SLIP_CN0 = (25.0, 30.0, 35.0)
SLIP_FILTERS = (
    ("ekf", "EKF nominal"),
    ("aekf", "AEKF"),
    ("aekf_running", "AEKF, paper's running-mean start"),
)


def slip_study(runs: int, seed: int) -> list[str]:
    """Slip rates of the fixed EKF and the AEKFs over many runs, with intervals."""
    from noisevar.systems.carrier import comparison_variants, slip_rates

    v = comparison_variants(45.0)
    variants = {
        "ekf": v["ekf"],
        "aekf": v["aekf"],
        "aekf_running": {**v["aekf"], "r_start": "running"},
    }
    start, cpu = time.perf_counter(), time.process_time()
    rates = slip_rates(SLIP_CN0, runs=runs, seed=seed, variants=variants)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    lines = [
        "",
        f"Carrier slip rates over {runs} runs per C/N0 (seed {seed}, the same signals for every "
        "filter; design 45 dB-Hz / 25 Hz/s; `noisevar.systems.carrier.slip_rates`, "
        f"{wall:.0f} s wall, {cpu:.0f} s CPU). Slipped runs with the Wilson 95 % interval of the "
        "fraction; of them, those whose first slip came before the first manoeuvre (2 s: the "
        "loop was still pulling in at 0.5 s) and those back at their cycle count of 0.5 s at "
        "the end (an excursion, not a net slip) and those still slipping in the last second "
        "(1.5 s after the last manoeuvre: lock lost for good, or a wide loop slipping on noise); "
        "paired against the fixed EKF: runs where only the EKF / only "
        "this filter slipped, and the exact McNemar p-value; and the RMS phase error over all "
        "these runs:",
        "",
        "| C/N0 (dB-Hz) | filter | slipped | 95 % interval | before the 1st manoeuvre "
        "| back at the end | unlocked at the end | only EKF / only this | McNemar p "
        "| RMS phase error (rad) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for i, c in enumerate(rates.cn0_dbhz):
        for name, label in SLIP_FILTERS:
            lo, hi = rates.ci95[name][i]
            d = rates.discordant[name][i]
            paired = "—" if name == "ekf" else f"{d[0]} / {d[1]}"
            p = "—" if name == "ekf" else f"{rates.p_value[name][i]:.2g}"
            lines.append(
                f"| {c:.0f} | {label} | {rates.slipped[name][i]} / {runs} "
                f"| {100 * lo:.2f}-{100 * hi:.2f} % | {rates.before_manoeuvre[name][i]} "
                f"| {rates.returned[name][i]} | {rates.unlocked_at_end[name][i]} | {paired} "
                f"| {p} | {rates.rms_phase_error_rad[name][i]:.4f} |"
            )
    lines.append("")
    for i, c in enumerate(rates.cn0_dbhz):
        e, a = rates.slipped["ekf"][i], rates.slipped["aekf"][i]
        p = rates.p_value["aekf"][i]
        if a < e and p < 0.05:
            verdict = f"the AEKF slips less (McNemar p = {p:.2g})"
        elif a == e == 0:
            verdict = (
                "neither slipped: 'fewer slips' cannot be shown at this C/N0, both rates are "
                f"below {100 * rates.ci95['aekf'][i][1]:.2f} % (95 % upper bound)"
            )
        elif a > e and p < 0.05:
            verdict = f"the AEKF slips more (McNemar p = {p:.2g})"
        else:
            verdict = f"no significant difference (McNemar p = {p:.2g})"
        lines.append(f"- {c:.0f} dB-Hz: EKF {e}, AEKF {a} of {runs}: {verdict}.")
    return lines


def kappa_selection(runs: int, seeds: range) -> list[str]:
    """Recompute the held-out κ study behind the default κ (pooled over ``seeds``)."""
    from noisevar.systems.robust import RobustScenario, kappa_tradeoff, simulate_robust

    start = time.process_time()
    noisy = [simulate_robust(RobustScenario(), seed=s, runs=runs) for s in seeds]
    clean = [simulate_robust(RobustScenario(outliers=False), seed=s, runs=runs) for s in seeds]
    t = kappa_tradeoff(noisy, clean)
    lines = [
        "",
        f"κ selection study: seeds {seeds.start}-{seeds.stop - 1}, {t.runs} runs pooled "
        f"({time.process_time() - start:.0f} s CPU):",
        "",
        "| κ | with outliers | 95 % interval | without outliers | 95 % interval "
        "| both over the interval |",
        "|---|---|---|---|---|---|",
    ]
    ok = t.meets_with_confidence()
    for i, k in enumerate(t.kappa):
        lines.append(
            f"| {k:g} | {t.ratio_outliers[i]:.3f} | {t.ci_outliers[i, 0]:.3f}-"
            f"{t.ci_outliers[i, 1]:.3f} | {t.ratio_clean[i]:.4f} | {t.ci_clean[i, 0]:.4f}-"
            f"{t.ci_clean[i, 1]:.4f} | {_yes(ok[i])} |"
        )
    return lines


def kappa_table(out: dict[str, Any]) -> list[str]:
    """Markdown table of the Huber κ trade-off (same runs for every κ)."""
    ks = out["metrics"]["kappa_sweep"]
    lines = [
        "",
        f"Huber κ trade-off ({out['runs']} runs, seed {out['seed']}, the same runs for every κ; "
        "ratio Huber / plain-EKF position RMSE with its paired bootstrap 95 % interval; targets "
        "<= 0.7 with outliers, within 1 % without):",
        "",
        "| κ | with outliers | 95 % interval | without outliers | 95 % interval "
        "| magvar (°) | both targets | both over the interval |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for i, k in enumerate(ks["kappa"]):
        lo_o, hi_o = ks["huber_over_ekf_with_outliers_ci95"][i]
        lo_c, hi_c = ks["huber_over_ekf_no_outliers_ci95"][i]
        lines.append(
            f"| {k:g} | {ks['huber_over_ekf_with_outliers'][i]:.3f} | {lo_o:.3f}-{hi_o:.3f} "
            f"| {ks['huber_over_ekf_no_outliers'][i]:.4f} | {lo_c:.4f}-{hi_c:.4f} "
            f"| {ks['magvar_estimate_deg'][i]:.3f} | {_yes(ks['meets_both_targets'][i])} "
            f"| {_yes(ks['meets_both_targets_over_ci95'][i])} |"
        )
    lines += [
        "",
        "The default κ = 2.5 was chosen on seeds 1-5 (500 runs, held out from this seed) as "
        "the only κ of the grid whose intervals lie inside both targets there; the held-out "
        "table (`--kappa-selection`, `kappa_tradeoff`) shows those numbers.",
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-write", action="store_true", help="print only")
    parser.add_argument(
        "--kappa-selection",
        action="store_true",
        help="also recompute the held-out κ study (seeds 1-5, about a minute)",
    )
    parser.add_argument(
        "--slip-runs",
        type=int,
        default=1000,
        help="runs per C/N0 of the carrier slip-rate study (0: skip it; 1000: about 30 s)",
    )
    args = parser.parse_args(argv)

    lines = [
        "## Seed-paper methods: fusion, robust filter, carrier tracking, latency (issue 6)",
        "",
        f"`python benchmarks/seeds.py --runs {args.runs}` on {platform.machine()}, "
        f"{os.cpu_count()} CPUs, Python {platform.python_version()}; every experiment "
        f"seeded (`--seed {args.seed}`), {args.runs} Monte Carlo runs.",
        "",
        "| experiment | target | measured | met |",
        "|---|---|---|---|",
    ]
    timings = []
    outputs = {}
    for name, cmd in COMMANDS.items():
        out, elapsed, cpu, shown = run_experiment(cmd, args.runs, args.seed)
        outputs[name] = out
        timings.append((name, shown, elapsed, cpu))
        for target, measured, _, ok in rows_for(name, out):
            verdict = "context" if ok is None else _yes(ok)
            lines.append(f"| {name} | {target} | {measured} | {verdict} |")
    context = {}
    for name, cmd in CONTEXT.items():
        out, elapsed, cpu, shown = run_experiment(cmd, args.runs, args.seed)
        context[name] = out
        timings.append((name, shown, elapsed, cpu))
    load = os.getloadavg()[0]
    lines += [
        "",
        f"Run time ({args.runs} runs; target each < {TIME_TARGET_S:.0f} s). Wall clock of the "
        "command, interpreter start included, and the CPU time it used (user + system; the "
        "wall clock grows when other work shares the two cores: 1-minute load average "
        f"{load:.1f} at the end of this run):",
        "",
        "| command | wall (s) | CPU (s) | met (wall) |",
        "|---|---|---|---|",
    ]
    for _name, shown, elapsed, cpu in timings:
        lines.append(f"| `{shown}` | {elapsed:.1f} | {cpu:.1f} | {_yes(elapsed < TIME_TARGET_S)} |")
    lines += sweep_table(outputs["carrier"])
    lines += design_table({k: v for k, v in context.items() if k.startswith("carrier")})
    if args.slip_runs > 0:
        lines += slip_study(args.slip_runs, args.seed)
    lines += kappa_table(context["outliers-kappa"])
    if args.kappa_selection:
        lines += kappa_selection(args.runs, range(1, 6))
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "seeds.md").write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
