"""``noisevar experiment fusion``: distributed VB fusion and chi-square fault isolation.

Two position sensors and a velocity sensor, one of which misbehaves
(:mod:`noisevar.systems.fusion`, ``docs/algorithms.md §B2``, ``§G6``): the
fused estimate against the centralised filter, isolation of a failing
sensor, VB against fixed ``R`` through a noise step and ramp.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from noisevar.experiments.base import Experiment, ExperimentResult
from noisevar.params import ParamSpec
from noisevar.systems.fusion import (
    FusionData,
    FusionResult,
    FusionScenario,
    max_abs_diff_vs_centralized,
    position_rmse,
    run_centralized,
    run_fusion,
    simulate_fusion,
)

#: Points kept in the R track of the JSON output.
TRACK_POINTS = 120

PARAMS = (
    ParamSpec("steps", "int", 600, "fusion steps (1 s each)"),
    ParamSpec(
        "failure",
        "str",
        "bias",
        "how the failing sensor fails (for the isolation metrics)",
        choices=("bias", "frozen"),
    ),
    ParamSpec(
        "local",
        "str",
        "vb",
        "R of the local filters in the isolation comparison",
        choices=("vb", "fixed"),
    ),
    ParamSpec("noise_factor", "float", 4.0, "noise std multiplier of the step/ramp"),
    ParamSpec("bias_sigmas", "float", 20.0, "bias of the failing sensor (sigmas)"),
    ParamSpec(
        "false_alarm",
        "float",
        1e-3,
        "chi-square test: probability of rejecting a healthy sample",
    ),
)


@dataclass(frozen=True)
class FusionExperimentResult(ExperimentResult):
    """Result of the fusion experiment (fields: the JSON keys)."""

    experiment: str = field(default="fusion", init=False)
    runs: int
    seed: int
    settings: dict[str, Any]
    metrics: dict[str, Any]
    targets: dict[str, Any]


def _track(
    result: FusionResult, data: FusionData, sensor: int = 0, channel: int = 0
) -> dict[str, list[float]]:
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


def _failures(
    common: dict[str, Any], seed: int, runs: int, fa: float
) -> dict[str, dict[str, float]]:
    """RMSE with and without isolation, and isolated fractions, per failure kind."""
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
    return failures


def _noise_step(
    common: dict[str, Any], seed: int, runs: int, fa: float
) -> tuple[FusionData, dict[str, FusionResult]]:
    """The noise step-up scenario and the fusion runs on it."""
    step = simulate_fusion(FusionScenario(fault="noise-step", **common), seed=seed + 1, runs=runs)
    return step, {
        "vb": run_fusion(step, local="vb"),
        "fixed": run_fusion(step, local="fixed"),
        "fixed+isolation": run_fusion(step, local="fixed", isolation=True, false_alarm=fa),
        "oracle": run_fusion(step, local="oracle"),
    }


def run(
    *,
    runs: int,
    seed: int,
    steps: int,
    failure: str,
    local: str,
    noise_factor: float,
    bias_sigmas: float,
    false_alarm: float,
) -> FusionExperimentResult:
    """Every fusion scenario over ``runs`` batched runs (validated parameters)."""
    common = {"n_steps": steps, "noise_factor": noise_factor, "bias_sigmas": bias_sigmas}
    fa = false_alarm

    clean = simulate_fusion(FusionScenario(fault="none", **common), seed=seed, runs=runs)
    central = run_centralized(clean)
    max_diff = max_abs_diff_vs_centralized(clean, central=central)
    max_diff_nofb = max_abs_diff_vs_centralized(clean, feedback=False, central=central)

    step, step_res = _noise_step(common, seed, runs, fa)
    ramp = simulate_fusion(FusionScenario(fault="noise-ramp", **common), seed=seed + 2, runs=runs)
    rmse_ramp = {name: run_fusion(ramp, local=name).rmse() for name in ("vb", "fixed", "oracle")}
    failures = _failures(common, seed, runs, fa)
    chosen = failures[failure]
    metrics = {
        "max_abs_diff_vs_centralized": max_diff,
        "max_abs_diff_vs_centralized_no_feedback": max_diff_nofb,
        "rmse_with_isolation": chosen[f"{local}+isolation"],
        "rmse_without_isolation": chosen[local],
        "rmse_vb_fusion": step_res["vb"].rmse(),
        "rmse_fixed_fusion": step_res["fixed"].rmse(),
        "rmse_fixed_isolation_fusion": step_res["fixed+isolation"].rmse(),
        "rmse_oracle_fusion": step_res["oracle"].rmse(),
        "rmse_ramp": rmse_ramp,
        "rmse_failures": failures,
        "rmse_centralized_no_fault": position_rmse(central.x, clean.truth),
        "vb_r_track": _track(step_res["vb"], step),
    }
    settings = {
        "steps": steps,
        "sensors": [s.name for s in clean.scenario.sensors],
        "faulty_sensor": clean.scenario.sensors[0].name,
        "failure": failure,
        "local": local,
        "noise_factor": noise_factor,
        "bias_sigmas": bias_sigmas,
        "false_alarm": fa,
        "rmse": "horizontal position, m, over runs and steps 20..N",
    }
    targets = {
        "fusion_equals_centralized_below": 1e-8,
        "equals_centralized": max_diff < 1e-8,
        "isolation_lowers_rmse": metrics["rmse_with_isolation"] < metrics["rmse_without_isolation"],
    }
    return FusionExperimentResult(
        runs=runs, seed=seed, settings=settings, metrics=metrics, targets=targets
    )


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
    help="distributed VB fusion (eq. 24) with chi-square fault isolation (§B2)",
    compute=run,
    params=PARAMS,
    default_runs=100,
    table=format_table,
)
