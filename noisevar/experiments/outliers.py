"""``noisevar experiment outliers``: Huber EKF with a magnetic-variation state.

The DME/VOR fly-over of :mod:`noisevar.systems.robust` (``docs/algorithms.md
§B3``, ``§G5``), with and without bursts of bearing outliers: EKF, Huber EKF
and Huber EKF without the bias state, paired bootstrap intervals of the
Huber/EKF ratios, and an optional κ trade-off table on the same runs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from noisevar.experiments.base import Experiment, ExperimentResult, ListParam
from noisevar.params import ParamSpec
from noisevar.systems.robust import (
    DEFAULT_KAPPA,
    PAPER_KAPPA,
    KappaTradeoff,
    RobustResult,
    RobustScenario,
    kappa_tradeoff,
    paired_rmse_ratio,
    run_robust,
    simulate_robust,
)

DEFINITIONS = {
    "rmse_position_*": "horizontal position RMSE (m) over runs and steps 30..N",
    "huber": "EKF with the magnetic-variation state and the Huber update at --kappa",
    "huber_paper_kappa": "the same at the paper's kappa = 1.345",
    "no_bias_state": "Huber update without the magnetic-variation state",
    "*_ci95": "paired bootstrap 95 % interval of the ratio (runs resampled; both filters "
    "on the same noise)",
    "kappa_sweep": "Huber/EKF ratios for each kappa on the same runs (with / without outliers)",
}

NOTES = (
    "the ratios are paired (same runs, same noise); their _ci95 intervals show whether "
    "100 runs resolve the 1 % target (at the paper's kappa they do not)",
    "flagged_runs counts runs the filter core's consistency check flags (NIS/NEES far "
    "above chi-square): outliers inflate the NIS of every filter; no estimates are "
    "discarded.",
)

PARAMS = (
    ParamSpec(
        "kappa",
        "float",
        DEFAULT_KAPPA,
        f"Huber threshold κ (default {DEFAULT_KAPPA}; the paper's is {PAPER_KAPPA})",
        lo=0,
    ),
    ListParam(
        "kappa_sweep",
        "floats",
        (),
        "comma-separated κ values of a trade-off table on the same runs, e.g. "
        "1.345,1.5,2,2.5,3 (each costs two Huber runs; default: none)",
        lo=0,
    ),
    ParamSpec("iterations", "int", 10, "Huber IRLS iterations"),
    ParamSpec("magvar", "float", -5.0, "station magnetic variation (deg)"),
    ParamSpec(
        "burst_rate",
        "float",
        0.08,
        "probability per sample near the station that an outlier burst starts",
    ),
)


@dataclass(frozen=True)
class OutliersResult(ExperimentResult):
    """Result of the outliers experiment (fields: the JSON keys)."""

    experiment: str = field(default="outliers", init=False)
    runs: int
    seed: int
    settings: dict[str, Any]
    definitions: dict[str, str] = field(default_factory=lambda: dict(DEFINITIONS), init=False)
    metrics: dict[str, Any]
    targets: dict[str, bool]
    notes: tuple[str, ...] = field(default=NOTES, init=False)


def _paper_kappa_metrics(table: KappaTradeoff, i: int) -> dict[str, Any]:
    """The Huber filter at the paper's κ (row ``i`` of the trade-off table)."""
    return {
        "rmse_position_huber_paper_kappa": float(table.rmse_huber_outliers[i]),
        "rmse_position_huber_paper_kappa_no_outliers": float(table.rmse_huber_clean[i]),
        "huber_paper_kappa_over_ekf_with_outliers": float(table.ratio_outliers[i]),
        "huber_paper_kappa_over_ekf_no_outliers": float(table.ratio_clean[i]),
        "huber_paper_kappa_over_ekf_with_outliers_ci95": table.ci_outliers[i].tolist(),
        "huber_paper_kappa_over_ekf_no_outliers_ci95": table.ci_clean[i].tolist(),
    }


def _sweep(table: KappaTradeoff, kappa_sweep: tuple[float, ...]) -> dict[str, list[Any]]:
    """The trade-off rows of the requested κ values, in increasing κ."""
    order = np.argsort(table.kappa)
    shown = [int(i) for i in order if table.kappa[i] in kappa_sweep]
    return {
        "kappa": table.kappa[shown].tolist(),
        "huber_over_ekf_with_outliers": table.ratio_outliers[shown].tolist(),
        "huber_over_ekf_with_outliers_ci95": table.ci_outliers[shown].tolist(),
        "huber_over_ekf_no_outliers": table.ratio_clean[shown].tolist(),
        "huber_over_ekf_no_outliers_ci95": table.ci_clean[shown].tolist(),
        "rmse_position_huber": table.rmse_huber_outliers[shown].tolist(),
        "rmse_position_huber_no_outliers": table.rmse_huber_clean[shown].tolist(),
        "magvar_estimate_deg": table.magvar_estimate_deg[shown].tolist(),
        "meets_both_targets": table.meets()[shown].tolist(),
        "meets_both_targets_over_ci95": table.meets_with_confidence()[shown].tolist(),
    }


def _metrics(
    res: RobustResult, res_clean: RobustResult, magvar: float, seed: int
) -> dict[str, Any]:
    """RMSEs, ratios with paired intervals and magnetic-variation errors at ``--kappa``."""
    ci_out = paired_rmse_ratio(
        res.position_mse_per_run("huber"), res.position_mse_per_run("ekf"), seed=seed
    )
    ci_clean = paired_rmse_ratio(
        res_clean.position_mse_per_run("huber"), res_clean.position_mse_per_run("ekf"), seed=seed
    )
    magvar_err = res.magvar_estimate_deg - magvar
    rm = res.rmse_position
    rc = res_clean.rmse_position
    return {
        "rmse_position_ekf": rm["ekf"],
        "rmse_position_huber": rm["huber"],
        "rmse_position_no_bias_state": rm["no-bias"],
        "magvar_estimate_deg": float(np.mean(res.magvar_estimate_deg)),
        "magvar_true_deg": float(magvar),
        "magvar_error_rms_deg": float(np.sqrt(np.mean(magvar_err**2))),
        "magvar_error_max_abs_deg": float(np.max(np.abs(magvar_err))),
        "magvar_estimate_ekf_deg": float(np.mean(res.magvar_estimate_ekf_deg)),
        "huber_over_ekf_with_outliers": rm["huber"] / rm["ekf"],
        "rmse_position_ekf_no_outliers": rc["ekf"],
        "rmse_position_huber_no_outliers": rc["huber"],
        "huber_over_ekf_no_outliers": rc["huber"] / rc["ekf"],
        "huber_over_ekf_with_outliers_ci95": list(ci_out[1:]),
        "huber_over_ekf_no_outliers_ci95": list(ci_clean[1:]),
    }


def _settings(scen: RobustScenario, kappa: float, iterations: int, skip: int) -> dict[str, Any]:
    return {
        "kappa": kappa,
        "iterations": iterations,
        "magvar_deg": scen.magvar_deg,
        "burst_rate": scen.burst_rate,
        "range_std_m": scen.range_std_m,
        "bearing_std_deg": scen.bearing_std_deg,
        "velocity_std": scen.velocity_std,
        "outlier_radius_m": scen.outlier_radius_m,
        "outlier_deg": list(scen.outlier_deg),
        "no_bias_filter": "Huber update without the magnetic-variation state",
        "rmse": f"horizontal position, m, over runs and steps {skip}..N",
        "kappa_default_reason": "chosen from held-out seeds 1-5 (500 runs): the only kappa "
        "of 1.345/1.5/2/2.5/3 whose paired 95 % intervals lie inside both targets "
        "(see noisevar.systems.robust)",
    }


def run(
    *,
    runs: int,
    seed: int,
    kappa: float,
    kappa_sweep: tuple[float, ...],
    iterations: int,
    magvar: float,
    burst_rate: float,
) -> OutliersResult:
    """The three filters with and without outliers (validated parameters)."""
    scen = RobustScenario(magvar_deg=magvar, burst_rate=burst_rate)
    noisy = simulate_robust(scen, seed=seed, runs=runs)
    res = run_robust(noisy, kappa=kappa, iterations=iterations)
    clean = simulate_robust(RobustScenario(magvar_deg=magvar, outliers=False), seed=seed, runs=runs)
    res_clean = run_robust(clean, kappa=kappa, iterations=iterations, filters=("ekf", "huber"))
    known = {float(kappa): (res, res_clean)}
    kappas = list(dict.fromkeys([float(kappa), PAPER_KAPPA, *kappa_sweep]))
    table = kappa_tradeoff(noisy, clean, kappas, iterations=iterations, seed=seed, known=known)
    metrics = _metrics(res, res_clean, magvar, seed)
    metrics["kappa"] = float(kappa)
    metrics.update(_paper_kappa_metrics(table, kappas.index(PAPER_KAPPA)))
    metrics["outlier_fraction"] = float(noisy.outlier.mean())
    metrics["flagged_runs"] = {name: int(np.sum(f.diverged)) for name, f in res.filters.items()}
    metrics["flagged_runs_no_outliers"] = {
        name: int(np.sum(f.diverged)) for name, f in res_clean.filters.items()
    }
    metrics["kappa_sweep"] = _sweep(table, kappa_sweep)
    targets = {
        "huber_at_most_0.7x_ekf_with_outliers": metrics["huber_over_ekf_with_outliers"] <= 0.7,
        "huber_within_1pct_without_outliers": abs(metrics["huber_over_ekf_no_outliers"] - 1)
        <= 0.01,
        "magvar_within_0.5deg": abs(metrics["magvar_estimate_deg"] - magvar) <= 0.5,
    }
    return OutliersResult(
        runs=runs,
        seed=seed,
        settings=_settings(scen, kappa, iterations, res.skip),
        metrics=metrics,
        targets=targets,
    )


def format_table(result: dict[str, Any]) -> str:
    """Readable summary of :func:`run`'s result."""
    m = result["metrics"]
    s = result["settings"]

    def ci(pair: list[float], digits: int = 3) -> str:
        return f"{pair[0]:.{digits}f}, {pair[1]:.{digits}f}"

    lines = [
        f"outliers: {result['runs']} runs, seed {result['seed']}, κ={s['kappa']}, "
        f"{s['iterations']} iterations (position RMSE in m)",
        "                              with outliers   without",
        f"  EKF with magvar state       {m['rmse_position_ekf']:12.1f}  "
        f"{m['rmse_position_ekf_no_outliers']:8.1f}",
        f"  Huber EKF with magvar state {m['rmse_position_huber']:12.1f}  "
        f"{m['rmse_position_huber_no_outliers']:8.1f}",
        f"  Huber EKF, no magvar state  {m['rmse_position_no_bias_state']:12.1f}",
        f"  Huber / EKF                 {m['huber_over_ekf_with_outliers']:12.3f}  "
        f"{m['huber_over_ekf_no_outliers']:8.3f}",
        f"  95 % paired interval         [{ci(m['huber_over_ekf_with_outliers_ci95'])}]  "
        f"[{ci(m['huber_over_ekf_no_outliers_ci95'])}]",
        f"  paper κ = 1.345: Huber / EKF {m['huber_paper_kappa_over_ekf_with_outliers']:.3f}"
        f" [{ci(m['huber_paper_kappa_over_ekf_with_outliers_ci95'])}]  "
        f"{m['huber_paper_kappa_over_ekf_no_outliers']:.3f} "
        f"[{ci(m['huber_paper_kappa_over_ekf_no_outliers_ci95'])}]",
        f"  magnetic variation: true {m['magvar_true_deg']:.2f}°, Huber estimate "
        f"{m['magvar_estimate_deg']:.3f}° (rms error {m['magvar_error_rms_deg']:.3f}°), "
        f"EKF {m['magvar_estimate_ekf_deg']:.3f}°",
    ]
    ks = m["kappa_sweep"]
    if ks["kappa"]:
        lines.append("  κ sweep   Huber/EKF with outliers     without outliers")
        for i, k in enumerate(ks["kappa"]):
            lines.append(
                f"  {k:7.3f}   {ks['huber_over_ekf_with_outliers'][i]:.3f} "
                f"[{ci(ks['huber_over_ekf_with_outliers_ci95'][i])}]     "
                f"{ks['huber_over_ekf_no_outliers'][i]:.4f} "
                f"[{ci(ks['huber_over_ekf_no_outliers_ci95'][i], 4)}]"
            )
    return "\n".join(lines)


EXPERIMENT = Experiment(
    name="outliers",
    help="robust Huber EKF with a magnetic-variation state on a DME/VOR fly-over (§B3)",
    compute=run,
    params=PARAMS,
    default_runs=100,
    table=format_table,
)
