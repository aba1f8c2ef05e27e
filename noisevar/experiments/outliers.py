"""``noisevar experiment outliers``: Huber EKF with a magnetic-variation state (spec B3).

The DME/VOR fly-over of :mod:`noisevar.systems.robust` over ``--runs`` seeded runs
(batched), once with bursts of bearing outliers near the station and once
without. Metrics (issue 6): ``rmse_position_ekf``, ``rmse_position_huber``,
``rmse_position_no_bias_state`` (with outliers), ``magvar_estimate_deg``
(Huber filter, mean of the final estimates over runs), ``magvar_true_deg``;
the clean-record RMSEs for the "equal without outliers" target; paired
bootstrap intervals of both Huber/EKF ratios (same runs, same noise: is the
"within 1 %" comparison resolved by 100 runs?); the paper's ``κ = 1.345``
next to our default (:data:`noisevar.systems.robust.DEFAULT_KAPPA` = 2.5, chosen from
held-out seeds, see :mod:`noisevar.systems.robust`); and, with ``--kappa-sweep``, the
κ trade-off table on the same runs (``benchmarks/seeds.py`` runs it with
``1.345,1.5,2,2.5,3``).
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from noisevar.errors import NoisevarError
from noisevar.experiments import Experiment
from noisevar.systems.robust import (
    DEFAULT_KAPPA,
    PAPER_KAPPA,
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


def _kappa_list(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--kappa-sweep {text!r}: give comma-separated positive thresholds, e.g. 1.345,2,3"
        ) from None
    if any(not v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"--kappa-sweep {text!r}: thresholds must be positive")
    return values


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Scenario and Huber options of the outliers experiment."""
    parser.add_argument(
        "--kappa",
        type=float,
        default=DEFAULT_KAPPA,
        help=f"Huber threshold κ (default {DEFAULT_KAPPA}; the paper's is {PAPER_KAPPA})",
    )
    parser.add_argument(
        "--kappa-sweep",
        type=_kappa_list,
        default=[],
        help="comma-separated κ values of a trade-off table on the same runs, e.g. "
        "1.345,1.5,2,2.5,3 (each costs two Huber runs; default: none)",
    )
    parser.add_argument("--iterations", type=int, default=10, help="Huber IRLS iterations")
    parser.add_argument(
        "--magvar", type=float, default=-5.0, help="station magnetic variation (deg)"
    )
    parser.add_argument(
        "--burst-rate",
        type=float,
        default=0.08,
        help="probability per sample near the station that an outlier burst starts",
    )


def run(args: argparse.Namespace) -> dict[str, Any]:
    """Run the three filters with and without outliers; JSON-serialisable result."""
    runs = int(args.runs)
    if runs < 1:
        raise NoisevarError(f"--runs {runs}: give at least one run.")
    seed = int(args.seed)
    scen = RobustScenario(magvar_deg=args.magvar, burst_rate=args.burst_rate)
    noisy = simulate_robust(scen, seed=seed, runs=runs)
    res = run_robust(noisy, kappa=args.kappa, iterations=args.iterations)
    clean_scen = RobustScenario(magvar_deg=args.magvar, outliers=False)
    clean = simulate_robust(clean_scen, seed=seed, runs=runs)
    res_clean = run_robust(
        clean, kappa=args.kappa, iterations=args.iterations, filters=("ekf", "huber")
    )
    known = {float(args.kappa): (res, res_clean)}
    kappas = list(dict.fromkeys([float(args.kappa), PAPER_KAPPA, *args.kappa_sweep]))
    table = kappa_tradeoff(noisy, clean, kappas, iterations=args.iterations, seed=seed, known=known)
    i_paper = kappas.index(PAPER_KAPPA)
    ci_out = paired_rmse_ratio(
        res.position_mse_per_run("huber"), res.position_mse_per_run("ekf"), seed=seed
    )
    ci_clean = paired_rmse_ratio(
        res_clean.position_mse_per_run("huber"), res_clean.position_mse_per_run("ekf"), seed=seed
    )
    magvar_err = res.magvar_estimate_deg - args.magvar
    rm = res.rmse_position
    rc = res_clean.rmse_position
    metrics = {
        "rmse_position_ekf": rm["ekf"],
        "rmse_position_huber": rm["huber"],
        "rmse_position_no_bias_state": rm["no-bias"],
        "magvar_estimate_deg": float(np.mean(res.magvar_estimate_deg)),
        "magvar_true_deg": float(args.magvar),
        "magvar_error_rms_deg": float(np.sqrt(np.mean(magvar_err**2))),
        "magvar_error_max_abs_deg": float(np.max(np.abs(magvar_err))),
        "magvar_estimate_ekf_deg": float(np.mean(res.magvar_estimate_ekf_deg)),
        "huber_over_ekf_with_outliers": rm["huber"] / rm["ekf"],
        "rmse_position_ekf_no_outliers": rc["ekf"],
        "rmse_position_huber_no_outliers": rc["huber"],
        "huber_over_ekf_no_outliers": rc["huber"] / rc["ekf"],
        "huber_over_ekf_with_outliers_ci95": list(ci_out[1:]),
        "huber_over_ekf_no_outliers_ci95": list(ci_clean[1:]),
        "kappa": float(args.kappa),
        "rmse_position_huber_paper_kappa": float(table.rmse_huber_outliers[i_paper]),
        "rmse_position_huber_paper_kappa_no_outliers": float(table.rmse_huber_clean[i_paper]),
        "huber_paper_kappa_over_ekf_with_outliers": float(table.ratio_outliers[i_paper]),
        "huber_paper_kappa_over_ekf_no_outliers": float(table.ratio_clean[i_paper]),
        "huber_paper_kappa_over_ekf_with_outliers_ci95": table.ci_outliers[i_paper].tolist(),
        "huber_paper_kappa_over_ekf_no_outliers_ci95": table.ci_clean[i_paper].tolist(),
        "outlier_fraction": float(noisy.outlier.mean()),
        "flagged_runs": {name: int(np.sum(f.diverged)) for name, f in res.filters.items()},
        "flagged_runs_no_outliers": {
            name: int(np.sum(f.diverged)) for name, f in res_clean.filters.items()
        },
    }
    order = np.argsort(table.kappa)
    shown = [int(i) for i in order if table.kappa[i] in args.kappa_sweep]
    metrics["kappa_sweep"] = {
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
    return {
        "experiment": "outliers",
        "runs": runs,
        "seed": seed,
        "settings": {
            "kappa": args.kappa,
            "iterations": args.iterations,
            "magvar_deg": args.magvar,
            "burst_rate": args.burst_rate,
            "range_std_m": scen.range_std_m,
            "bearing_std_deg": scen.bearing_std_deg,
            "velocity_std": scen.velocity_std,
            "outlier_radius_m": scen.outlier_radius_m,
            "outlier_deg": list(scen.outlier_deg),
            "no_bias_filter": "Huber update without the magnetic-variation state",
            "rmse": f"horizontal position, m, over runs and steps {res.skip}..N",
            "kappa_default_reason": "chosen from held-out seeds 1-5 (500 runs): the only kappa "
            "of 1.345/1.5/2/2.5/3 whose paired 95 % intervals lie inside both targets "
            "(see noisevar.systems.robust)",
        },
        "definitions": DEFINITIONS,
        "metrics": metrics,
        "targets": {
            "huber_at_most_0.7x_ekf_with_outliers": metrics["huber_over_ekf_with_outliers"] <= 0.7,
            "huber_within_1pct_without_outliers": abs(metrics["huber_over_ekf_no_outliers"] - 1)
            <= 0.01,
            "magvar_within_0.5deg": abs(metrics["magvar_estimate_deg"] - args.magvar) <= 0.5,
        },
        "notes": [
            "the ratios are paired (same runs, same noise); their _ci95 intervals show whether "
            "100 runs resolve the 1 % target (at the paper's kappa they do not)",
            "flagged_runs counts runs the filter core's consistency check flags (NIS/NEES far "
            "above chi-square): outliers inflate the NIS of every filter; no estimates are "
            "discarded.",
        ],
    }


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
    help="robust Huber EKF with a magnetic-variation state on a DME/VOR fly-over (spec B3)",
    run=run,
    add_arguments=add_arguments,
    default_runs=100,
    format_table=format_table,
)
