"""``noisevar experiment fusion``: distributed VB fusion and chi-square fault isolation (spec B2).

One seeded Monte Carlo batch (``--runs``) per scenario of
:mod:`noisevar.systems.fusion`: two position sensors and a velocity sensor, one of
which misbehaves. Metrics (issue 6):

* ``max_abs_diff_vs_centralized``: no fault, fixed ``R``, no isolation; the
  distributed estimate (eq. (24)) against the centralised Kalman filter;
* ``rmse_with_isolation``, ``rmse_without_isolation``: the failing sensor
  (``--failure``: a large bias, or a frozen output), local filters ``--local``;
* ``rmse_vb_fusion``, ``rmse_fixed_fusion``: the sensor's noise steps up;
* ``vb_r_track``: the VB estimate of that sensor's variance against the truth.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.experiments import Experiment
from noisevar.systems.fusion import (
    FusionScenario,
    max_abs_diff_vs_centralized,
    position_rmse,
    run_centralized,
    run_fusion,
    simulate_fusion,
)

#: Points kept in the R track of the JSON output.
TRACK_POINTS = 120


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Scenario options of the fusion experiment."""
    parser.add_argument("--steps", type=int, default=600, help="fusion steps (1 s each)")
    parser.add_argument(
        "--failure",
        choices=("bias", "frozen"),
        default="bias",
        help="how the failing sensor fails (for the isolation metrics)",
    )
    parser.add_argument(
        "--local",
        choices=("vb", "fixed"),
        default="vb",
        help="R of the local filters in the isolation comparison",
    )
    parser.add_argument(
        "--noise-factor", type=float, default=4.0, help="noise std multiplier of the step/ramp"
    )
    parser.add_argument(
        "--bias-sigmas", type=float, default=20.0, help="bias of the failing sensor (sigmas)"
    )
    parser.add_argument(
        "--false-alarm",
        type=float,
        default=1e-3,
        help="chi-square test: probability of rejecting a healthy sample",
    )


def _track(result, data, sensor: int = 0, channel: int = 0) -> dict[str, list[float]]:
    n = result.time.size
    idx = np.unique(np.linspace(0, n - 1, min(TRACK_POINTS, n)).round().astype(int))
    estimate = np.nanmean(result.R_track[sensor][:, :, channel], axis=0)
    return {
        "sensor": result.sensor_names[sensor],
        "channel": int(channel),
        "time_s": result.time[idx].tolist(),
        "r_estimate": estimate[idx].tolist(),
        "r_true": data.true_R(sensor)[idx, channel].tolist(),
    }


def run(args: argparse.Namespace) -> dict[str, Any]:
    """Run every fusion scenario once over ``--runs`` batched runs; JSON result."""
    runs = int(args.runs)
    if runs < 1:
        raise NoisevarError(f"--runs {runs}: give at least one run.")
    seed = int(args.seed)
    common = {
        "n_steps": args.steps,
        "noise_factor": args.noise_factor,
        "bias_sigmas": args.bias_sigmas,
    }
    fa = args.false_alarm

    clean = simulate_fusion(FusionScenario(fault="none", **common), seed=seed, runs=runs)
    central = run_centralized(clean)
    max_diff = max_abs_diff_vs_centralized(clean, central=central)
    max_diff_nofb = max_abs_diff_vs_centralized(clean, feedback=False, central=central)

    step = simulate_fusion(FusionScenario(fault="noise-step", **common), seed=seed + 1, runs=runs)
    step_res = {
        "vb": run_fusion(step, local="vb"),
        "fixed": run_fusion(step, local="fixed"),
        "fixed+isolation": run_fusion(step, local="fixed", isolation=True, false_alarm=fa),
        "oracle": run_fusion(step, local="oracle"),
    }
    ramp = simulate_fusion(FusionScenario(fault="noise-ramp", **common), seed=seed + 2, runs=runs)
    ramp_res = {
        "vb": run_fusion(ramp, local="vb"),
        "fixed": run_fusion(ramp, local="fixed"),
        "oracle": run_fusion(ramp, local="oracle"),
    }
    failures: dict[str, dict[str, float]] = {}
    for j, kind in enumerate(("bias", "frozen")):
        data = simulate_fusion(FusionScenario(fault=kind, **common), seed=seed + 3 + j, runs=runs)
        failures[kind] = {}
        for local in ("vb", "fixed"):
            for iso in (False, True):
                res = run_fusion(data, local=local, isolation=iso, false_alarm=fa)
                failures[kind][res.label] = res.rmse()
                if iso:
                    in_fault, healthy = res.isolated_fraction(0)
                    failures[kind][f"{res.label}: isolated fraction in fault"] = in_fault
                    failures[kind][f"{res.label}: isolated fraction healthy"] = healthy

    chosen = failures[args.failure]
    metrics = {
        "max_abs_diff_vs_centralized": max_diff,
        "max_abs_diff_vs_centralized_no_feedback": max_diff_nofb,
        "rmse_with_isolation": chosen[f"{args.local}+isolation"],
        "rmse_without_isolation": chosen[args.local],
        "rmse_vb_fusion": step_res["vb"].rmse(),
        "rmse_fixed_fusion": step_res["fixed"].rmse(),
        "rmse_fixed_isolation_fusion": step_res["fixed+isolation"].rmse(),
        "rmse_oracle_fusion": step_res["oracle"].rmse(),
        "rmse_ramp": {name: r.rmse() for name, r in ramp_res.items()},
        "rmse_failures": failures,
        "rmse_centralized_no_fault": position_rmse(central.x, clean.truth),
        "vb_r_track": _track(step_res["vb"], step),
    }
    return {
        "experiment": "fusion",
        "runs": runs,
        "seed": seed,
        "settings": {
            "steps": args.steps,
            "sensors": [s.name for s in clean.scenario.sensors],
            "faulty_sensor": clean.scenario.sensors[0].name,
            "failure": args.failure,
            "local": args.local,
            "noise_factor": args.noise_factor,
            "bias_sigmas": args.bias_sigmas,
            "false_alarm": fa,
            "rmse": "horizontal position, m, over runs and steps 20..N",
        },
        "metrics": metrics,
        "targets": {
            "fusion_equals_centralized_below": 1e-8,
            "equals_centralized": max_diff < 1e-8,
            "isolation_lowers_rmse": metrics["rmse_with_isolation"]
            < metrics["rmse_without_isolation"],
        },
    }


def format_table(result: dict[str, Any]) -> str:
    """Readable summary of :func:`run`'s result."""
    m = result["metrics"]
    s = result["settings"]
    lines = [
        f"fusion: {result['runs']} runs, seed {result['seed']} (position RMSE in m)",
        f"  fused vs centralised, max |diff|     {m['max_abs_diff_vs_centralized']:.3g}"
        f"   (no feedback: {m['max_abs_diff_vs_centralized_no_feedback']:.3g})",
        f"  {s['failure']} failure, {s['local']} local filters:",
        f"    with isolation     {m['rmse_with_isolation']:10.3f}",
        f"    without isolation  {m['rmse_without_isolation']:10.3f}",
        "  noise step-up:",
        f"    vb fusion          {m['rmse_vb_fusion']:10.3f}",
        f"    fixed fusion       {m['rmse_fixed_fusion']:10.3f}",
        f"    fixed + isolation  {m['rmse_fixed_isolation_fusion']:10.3f}",
        f"    oracle             {m['rmse_oracle_fusion']:10.3f}",
        "  noise ramp-up:  " + ", ".join(f"{k} {v:.3f}" for k, v in m["rmse_ramp"].items()),
    ]
    for kind, rows in m["rmse_failures"].items():
        lines.append(
            f"  {kind}: "
            + ", ".join(f"{k} {v:.3f}" for k, v in rows.items() if "fraction" not in k)
        )
    return "\n".join(lines)


EXPERIMENT = Experiment(
    name="fusion",
    help="distributed VB fusion (eq. 24) with chi-square fault isolation (spec B2)",
    run=run,
    add_arguments=add_arguments,
    default_runs=100,
    format_table=format_table,
)
