"""``noisevar experiment noise-step``: tracking a three-fold step in the noise level.

A manoeuvring 2-D target (:func:`noisevar.systems.scenarios.noise_step`), CV
Kalman filter, position-noise std 5 m stepping to ``factor`` x 5 m at mid-run;
every method filters all runs in one batch. ``noise-ramp`` shares this module.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.experiments.base import (
    JOBS,
    Experiment,
    ExperimentResult,
    ListParam,
    strategy_param,
)
from noisevar.kalman.evaluation import (
    divergence_summary,
    fmt,
    map_jobs,
    pooled_rmse,
    r_tracking_error,
)
from noisevar.kalman.strategies import RStrategy, make_strategy, strategy_spec
from noisevar.params import ParamSpec
from noisevar.systems.scenarios import Scenario, noise_ramp, noise_step

METHODS = ("oracle", "fixed", "somd", "rae", "iae", "sage-husa", "vb", "rae-q")
ADAPTIVE = ("somd", "rae", "iae", "sage-husa", "vb", "rae-q")
TARGET_R_TRACKING = 0.20
TARGET_RMSE_VS_ORACLE = 0.10

#: Parameters shared by noise-step and noise-ramp.
PARAMS = (
    ParamSpec("steps", "int", 6000, "samples (T = 0.1 s)"),
    ParamSpec("factor", "float", 3.0, "noise std after / before the change"),
    ParamSpec("settle", "int", 500, "steps after the change ends before R tracking is scored"),
    strategy_param("rae", "window", "window N of RAE / IAE / rae-q"),
    strategy_param("sage-husa", "forgetting", "Sage-Husa forgetting factor b"),
    strategy_param("vb", "rho", "VB forgetting rho"),
    ParamSpec("somd_window", "int", 500, "somd-online trailing window (steps)"),
    ParamSpec("somd_every", "int", 20, "somd-online: re-estimate every N steps"),
    JOBS,
    ListParam("methods", "strs", METHODS, "filters to run", choices=METHODS, sep=None),
)


@dataclass(frozen=True)
class NoiseChangeSettings:
    """What a worker needs to regenerate the scenario and build a filter."""

    scenario: str
    runs: int
    seed: int
    steps: int
    factor: float
    window: int
    forgetting: float
    rho: float
    somd_window: int | None
    somd_every: int

    def make_scenario(self) -> Scenario:
        """The seeded scenario (identical data in every process)."""
        generate = GENERATORS[self.scenario]
        return generate(runs=self.runs, seed=self.seed, n_steps=self.steps, factor=self.factor)

    def strategy(self, name: str, sc: Scenario) -> RStrategy:
        """The strategy object of one method name, with these settings."""
        values = {
            "window": self.somd_window if name == "somd" else self.window,
            "every": self.somd_every,
            "forgetting": self.forgetting,
            "rho": self.rho,
        }
        return make_strategy(
            name,
            h_smooth=sc.h_smooth,
            R_true=sc.R_true[sc.first_step :],
            **{k: values[k] for k in strategy_spec(name).defaults()},
        )


GENERATORS: dict[str, Callable[..., Scenario]] = {
    "noise-step": noise_step,
    "noise-ramp": noise_ramp,
}


@dataclass(frozen=True)
class NoiseChangeResult(ExperimentResult):
    """Result of noise-step / noise-ramp (fields: the JSON keys).

    Attributes
    ----------
    methods : dict
        Per method: ``r_tracking_error`` (mean ``|R̂_jj / R_jj - 1|`` over runs,
        both channels, from the change's end + ``settle`` on), ``r_bias`` (the
        same without ``|.|``), ``rmse`` (position, all runs and steps),
        ``rmse_vs_oracle``, ``diverged_runs`` and ``divergence``.
    best : str or None
        The adaptive method with the lowest ``r_tracking_error``.
    targets, settings : dict
        Whether ``best`` meets the targets; the parameters used.
    notes : tuple of str
        Scoring window and divergences.
    """

    methods: dict[str, dict[str, Any]]
    best: str | None
    targets: dict[str, Any]
    settings: dict[str, Any]
    notes: tuple[str, ...]


def _filter_task(task: tuple[NoiseChangeSettings, str, int, Scenario | None]) -> dict[str, Any]:
    """Run one filter over all runs (batched) and score it (worker-process safe).

    The last element of ``task`` is the scenario, or ``None`` in a worker
    process, which regenerates the seeded scenario (identical data).
    """
    settings, name, start, sc = task
    if sc is None:
        sc = settings.make_scenario()
    res = sc.run(settings.strategy(name, sc))
    err, bias = r_tracking_error(res, sc.R_true[sc.first_step :], start)
    div = divergence_summary(res)
    return {
        "r_tracking_error": err,
        "r_bias": bias,
        "rmse": pooled_rmse(res, (0, 2)),
        "diverged_runs": div["runs"],
        "divergence": div,
    }


def _targets(out: dict[str, dict[str, Any]], methods: list[str]) -> dict[str, Any]:
    """The best adaptive method and whether it meets the targets."""
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
    return targets


def _notes(sc: Scenario, settle: int, out: dict[str, dict[str, Any]]) -> list[str]:
    notes = [
        f"R tracking scored from step {sc.change[1] + settle} (change ends at step "
        f"{sc.change[1]}, + --settle {settle}) to the end, both channels, all runs",
        "rmse: horizontal position over all runs and filtered steps",
    ]
    diverged = [f"{m} {e['diverged_runs']}/{sc.runs}" for m, e in out.items() if e["diverged_runs"]]
    if diverged:
        notes.append(
            "diverged (NaN, exploding P, or windowed NIS/NEES > 10x): " + ", ".join(diverged)
        )
    return notes


def run_noise_change(
    settings: NoiseChangeSettings, settle: int, methods: tuple[str, ...], jobs: int = 1
) -> NoiseChangeResult:
    """Run every method on a noise-change scenario and score it.

    Parameters
    ----------
    settings : NoiseChangeSettings
        Scenario and filter settings.
    settle : int
        Steps after the change ends before R tracking is scored.
    methods : tuple of str
        Filters to run (of :data:`METHODS`).
    jobs : int
        Worker processes, one filter each.

    Returns
    -------
    NoiseChangeResult
        See the module docstring.
    """
    sc = settings.make_scenario()
    start = sc.change[1] + settle - sc.first_step
    n_filtered = sc.z.shape[1] - sc.first_step
    if start >= n_filtered - 10:
        raise NoisevarError(
            f"--settle {settle} leaves no steps to score after the change (which ends at "
            f"step {sc.change[1]} of {sc.z.shape[1]}): use a smaller --settle or more --steps"
        )
    # in this process the scenario is reused; worker processes regenerate it
    tasks = [(settings, name, start, sc if jobs == 1 else None) for name in methods]
    out = dict(zip(methods, map_jobs(_filter_task, tasks, jobs), strict=True))
    oracle = out.get("oracle", {}).get("rmse")
    for entry in out.values():
        entry["rmse_vs_oracle"] = (
            None if oracle is None or entry["rmse"] is None else entry["rmse"] / oracle - 1.0
        )
    targets = _targets(out, list(methods))
    return NoiseChangeResult(
        methods=out,
        best=targets["best"],
        targets=targets,
        settings={
            "scenario": sc.name,
            "runs": sc.runs,
            "seed": settings.seed,
            "steps": int(sc.z.shape[1]),
            "change": list(sc.change),
            "factor": settings.factor,
            "settle": settle,
            "window": settings.window,
            "forgetting": settings.forgetting,
            "rho": settings.rho,
            "somd_window": settings.somd_window,
            "somd_every": settings.somd_every,
            "h_smooth": list(sc.h_smooth),
        },
        notes=tuple(_notes(sc, settle, out)),
    )


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


def noise_change_experiment(scenario: str, help: str) -> Experiment:
    """The experiment of the noise-change scenario ``"noise-step"`` or ``"noise-ramp"``."""

    def run(
        *, settle: int, methods: tuple[str, ...], jobs: int, **settings: Any
    ) -> NoiseChangeResult:
        """Run the experiment (validated parameters; see :data:`PARAMS`)."""
        return run_noise_change(
            NoiseChangeSettings(scenario=scenario, **settings), settle, methods, jobs
        )

    return Experiment(
        name=scenario,
        help=help,
        compute=run,
        params=PARAMS,
        default_runs=20,
        table=format_table,
    )


EXPERIMENT = noise_change_experiment(
    "noise-step", "manoeuvring target whose noise std steps up 3x mid-run: R tracking and RMSE"
)
