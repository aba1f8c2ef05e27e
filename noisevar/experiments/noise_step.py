"""``noisevar experiment noise-step``: tracking a three-fold step in the noise level.

Scenario :func:`noisevar.systems.scenarios.noise_step`: a manoeuvring 2-D
target, CV Kalman filter, position-noise std 5 m stepping to 15 m at mid-run;
``--runs`` seeded Monte Carlo runs filtered in one batch per method.
:mod:`noisevar.experiments.noise_ramp` is the same with a ramp.

Output (JSON)::

    {"methods": {name: {"r_tracking_error": x, "r_bias": x, "rmse": x,
                        "rmse_vs_oracle": x, "diverged_runs": k}},
     "best": name, "targets": {...}, "settings": {...}, "notes": [...]}

``r_tracking_error`` is ``mean |R̂_jj / R_jj - 1|`` over runs, both channels
and the steps from ``change end + --settle`` to the end; ``r_bias`` the same
without the absolute value; ``rmse`` the position RMSE over runs and all
steps.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.experiments import Experiment
from noisevar.kalman.evaluation import (
    divergence_summary,
    fmt,
    map_jobs,
    pooled_rmse,
    r_tracking_error,
)
from noisevar.kalman.strategies import (
    RStrategy,
    make_strategy,
    strategy_spec,
)
from noisevar.systems.scenarios import Scenario, noise_ramp, noise_step

METHODS = ("oracle", "fixed", "somd", "rae", "iae", "sage-husa", "vb", "rae-q")
ADAPTIVE = ("somd", "rae", "iae", "sage-husa", "vb", "rae-q")
TARGET_R_TRACKING = 0.20
TARGET_RMSE_VS_ORACLE = 0.10


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options shared by noise-step and noise-ramp."""
    parser.add_argument("--steps", type=int, default=6000, help="samples (T = 0.1 s)")
    parser.add_argument(
        "--factor", type=float, default=3.0, help="noise std after / before the change"
    )
    parser.add_argument(
        "--settle",
        type=int,
        default=500,
        help="steps after the change ends before R tracking is scored",
    )
    parser.add_argument("--window", type=int, default=50, help="window N of RAE / IAE / rae-q")
    parser.add_argument(
        "--forgetting", type=float, default=0.98, help="Sage-Husa forgetting factor b"
    )
    parser.add_argument("--rho", type=float, default=0.99, help="VB forgetting rho")
    parser.add_argument(
        "--somd-window", type=int, default=500, help="somd-online trailing window (steps)"
    )
    parser.add_argument(
        "--somd-every", type=int, default=20, help="somd-online: re-estimate every N steps"
    )
    parser.add_argument(
        "--jobs", type=int, default=1, help="worker processes, one filter each (default 1)"
    )
    parser.add_argument(
        "--methods", nargs="+", choices=METHODS, default=list(METHODS), help="filters to run"
    )


def strategy_for(name: str, sc: Scenario, args: argparse.Namespace) -> RStrategy:
    """The strategy object of one method name, with the experiment's settings."""
    settings = {
        "window": args.somd_window if name == "somd" else args.window,
        "every": args.somd_every,
        "forgetting": args.forgetting,
        "rho": args.rho,
    }
    params = strategy_spec(name).defaults()
    return make_strategy(
        name,
        h_smooth=sc.h_smooth,
        R_true=sc.R_true[sc.first_step :],
        **{k: settings[k] for k in params},
    )


GENERATORS: dict[str, Callable[..., Scenario]] = {
    "noise-step": noise_step,
    "noise-ramp": noise_ramp,
}


def _scenario(name: str, args: argparse.Namespace) -> Scenario:
    return GENERATORS[name](runs=args.runs, seed=args.seed, n_steps=args.steps, factor=args.factor)


def _filter_task(task: tuple[str, str, int, dict[str, Any], Scenario | None]) -> dict[str, Any]:
    """Run one filter over all runs (batched) and score it (worker-process safe).

    The last element of ``task`` is the scenario, or ``None`` in a worker
    process, which regenerates the seeded scenario (identical data).
    """
    scenario, name, start, settings, sc = task
    args = argparse.Namespace(**settings)
    if sc is None:
        sc = _scenario(scenario, args)
    res = sc.run(strategy_for(name, sc, args))
    err, bias = r_tracking_error(res, sc.R_true[sc.first_step :], start)
    div = divergence_summary(res)
    return {
        "r_tracking_error": err,
        "r_bias": bias,
        "rmse": pooled_rmse(res, (0, 2)),
        "diverged_runs": div["runs"],
        "divergence": div,
    }


def run_noise_change(sc: Scenario, args: argparse.Namespace) -> dict[str, Any]:
    """Run every method on a noise-change scenario and score it.

    Parameters
    ----------
    sc : Scenario
        ``noise_step`` or ``noise_ramp`` scenario.
    args : argparse.Namespace
        Parsed options (see :func:`add_arguments`).

    Returns
    -------
    dict
        See the module docstring.
    """
    methods = list(getattr(args, "methods", METHODS))
    start = sc.change[1] + args.settle - sc.first_step
    n_filtered = sc.z.shape[1] - sc.first_step
    if start >= n_filtered - 10:
        raise NoisevarError(
            f"--settle {args.settle} leaves no steps to score after the change (which ends at "
            f"step {sc.change[1]} of {sc.z.shape[1]}): use a smaller --settle or more --steps"
        )
    settings = {k: v for k, v in vars(args).items() if isinstance(v, (int, float, str, type(None)))}
    jobs = int(getattr(args, "jobs", 1) or 1)
    if jobs < 1:
        raise NoisevarError(f"--jobs must be at least 1, got {jobs}")
    # in this process the scenario is reused; worker processes regenerate it
    tasks = [(sc.name, name, start, settings, sc if jobs == 1 else None) for name in methods]
    out = dict(zip(methods, map_jobs(_filter_task, tasks, jobs), strict=True))
    oracle = out.get("oracle", {}).get("rmse")
    for entry in out.values():
        entry["rmse_vs_oracle"] = (
            None if oracle is None or entry["rmse"] is None else entry["rmse"] / oracle - 1.0
        )
    adaptive = [m for m in methods if m in ADAPTIVE]
    best = min(adaptive, key=lambda m: out[m]["r_tracking_error"]) if adaptive else None
    targets: dict[str, Any] = {"best": best}
    if best is not None:
        targets["best_r_tracking_within_20pct"] = bool(
            out[best]["r_tracking_error"] <= TARGET_R_TRACKING
        )
        ratio = out[best]["rmse_vs_oracle"]
        targets["best_rmse_within_10pct_of_oracle"] = bool(
            ratio is not None and ratio <= TARGET_RMSE_VS_ORACLE
        )
    notes = [
        f"R tracking scored from step {sc.change[1] + args.settle} (change ends at step "
        f"{sc.change[1]}, + --settle {args.settle}) to the end, both channels, all runs",
        "rmse: horizontal position over all runs and filtered steps",
    ]
    diverged = [
        f"{m} {out[m]['diverged_runs']}/{sc.runs}" for m in methods if out[m]["diverged_runs"]
    ]
    if diverged:
        notes.append(
            "diverged (NaN, exploding P, or windowed NIS/NEES > 10x): " + ", ".join(diverged)
        )
    return {
        "methods": out,
        "best": best,
        "targets": targets,
        "settings": {
            "scenario": sc.name,
            "runs": sc.runs,
            "seed": args.seed,
            "steps": int(sc.z.shape[1]),
            "change": list(sc.change),
            "factor": args.factor,
            "settle": args.settle,
            "window": args.window,
            "forgetting": args.forgetting,
            "rho": args.rho,
            "somd_window": args.somd_window,
            "somd_every": args.somd_every,
            "h_smooth": list(sc.h_smooth),
        },
        "notes": notes,
    }


def format_table(result: dict[str, Any]) -> str:
    """Readable table of R tracking and RMSE per method."""
    s = result["settings"]
    lines = [
        f"{s['scenario']}: noise std x{s['factor']:g} at steps {s['change'][0]}-{s['change'][1]}, "
        f"{s['runs']} runs",
        f"{'method':12s}{'|R/R-1|':>11s}{'R bias':>11s}{'rmse m':>11s}{'vs oracle':>11s}  diverged",
    ]
    for name, e in result["methods"].items():
        vs = e["rmse_vs_oracle"]
        lines.append(
            f"{name:12s}{fmt(e['r_tracking_error'])}{fmt(e['r_bias'])}{fmt(e['rmse'])}"
            f"{('-' if vs is None else f'{vs:+.1%}'):>11s}  {e['diverged_runs']}/{s['runs']}"
        )
    t = result["targets"]
    lines.append(
        f"best adaptive: {t.get('best')}; R tracking within 20 %: "
        f"{t.get('best_r_tracking_within_20pct')}; RMSE within 10 % of oracle: "
        f"{t.get('best_rmse_within_10pct_of_oracle')}"
    )
    lines.extend(f"note: {n}" for n in result["notes"])
    return "\n".join(lines)


def make_run(scenario: str) -> Callable[[argparse.Namespace], dict[str, Any]]:
    """``run(args)`` for the noise-change scenario ``"noise-step"`` or ``"noise-ramp"``."""

    def run(args: argparse.Namespace) -> dict[str, Any]:
        return run_noise_change(_scenario(scenario, args), args)

    return run


EXPERIMENT = Experiment(
    name="noise-step",
    help="manoeuvring target whose noise std steps up 3x mid-run: R tracking and RMSE",
    run=make_run("noise-step"),
    add_arguments=add_arguments,
    default_runs=20,
    format_table=format_table,
)
