"""The cached calls of the pages (``st.cache_data`` / ``st.cache_resource`` wrappers).

Computations on the loaded signal are cached by its **content hash** (computed once
at load), never by hashing the array on every rerun; arguments named with a leading
underscore are not hashed. Cached results are shared read-only objects, kept in the
server's one cache bounded in bytes (:mod:`dashboard.budget`, ``NOISEVAR_MEMORY_MB``):
every session asking for the same record and parameters gets the one computation.
"""

from __future__ import annotations

import inspect
import json
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import plotly.graph_objects as go
import streamlit as st

import noisevar
from dashboard import workers
from dashboard.budget import cached
from dashboard.state import LoadedSignal, sensor_matrix
from noisevar import estimators
from noisevar.errors import NoisevarError
from noisevar.estimators.compare import MethodResult, run_method, run_methods
from noisevar.estimators.results import VarianceEstimate
from noisevar.filters.envelope import (
    HScan,
    WindowAmplitude,
    detrend_windows,
    noise_amplitude,
    scan_h,
)
from noisevar.io import LoadedTable, channel_record, load_table, log_topics, pick_column

if TYPE_CHECKING:
    from noisevar.kalman.result import FilterResult
    from noisevar.kalman.strategies import RStrategy
    from noisevar.systems.carrier import CarrierResult, CarrierSweep
    from noisevar.systems.fusion import FusionData, FusionResult
    from noisevar.systems.latency import DelayEstimate, LatencyResult
    from noisevar.systems.robust import RobustResult
    from noisevar.systems.scenarios import Scenario

#: An experiment's JSON-like result (nested dicts of numbers and strings).
JsonDict = dict[str, Any]
#: Settings of the Adaptive filter page (strategy parameters by name).
Settings = dict[str, float | int | str]

#: The method :func:`noisevar.estimate` uses when none is named (the package's one default).
DEFAULT_METHOD: str = estimators.DEFAULT_METHOD

#: The carrier filters the Carrier tracking page shows (``comparison_variants`` names).
CARRIER_FILTERS = ("ekf", "aekf", "ekf_matched", "aekf_paper_q")


def params_key(params: dict[str, object]) -> str:
    """A stable JSON key of a parameter dict (the hashable cache argument)."""
    return json.dumps(params, sort_keys=True, default=str)


# --------------------------------------------------------------------- loading
@st.cache_data(show_spinner=False)
def sample_descriptions(sample_dir: str) -> dict[str, str]:
    """One-line descriptions of the sample files, from ``make_samples.py``'s docstring."""
    script = Path(sample_dir) / "make_samples.py"
    out: dict[str, str] = {}
    if not script.is_file():
        return out
    text = script.read_text(encoding="utf-8", errors="replace")
    doc = text.split('"""')[1] if text.count('"""') >= 2 else ""
    current = None
    for line in doc.splitlines():
        m = re.match(r"^``([^`]+)``\s+(.*)$", line.strip())
        if m:
            current = m.group(1)
            out[current] = m.group(2).strip()
        elif current and line.startswith(" ") and line.strip():
            out[current] += " " + line.strip()
        else:
            current = None
    return out


@cached
def load_bytes_cached(
    digest: str,
    name: str,
    _raw: bytes,
    topic: str | None = None,
    time_unit: str | None = None,
    series: str | None = None,
) -> LoadedTable:
    """:func:`noisevar.io.load_table` of file bytes (a log's ``topic``, times in
    ``time_unit``, the rows of one ``series``), cached by their content hash."""
    return load_table(_raw, name, topic=topic, time_unit=time_unit, series=series)


@cached
def log_params_cached(digest: str, name: str, _raw: bytes) -> dict[str, float]:
    """:func:`noisevar.io.logs.params.log_parameters` of file bytes ({}: none), cached."""
    from noisevar.io.logs.params import log_parameters

    return log_parameters(_raw, name)


@cached
def log_topics_cached(digest: str, name: str, _raw: bytes) -> list | None:
    """:func:`noisevar.io.log_topics` of file bytes (None: not a log), cached."""
    return log_topics(_raw, name)


@cached
def generate_cached(name: str, kwargs_json: str) -> noisevar.GeneratedSignal:
    """:func:`noisevar.generate` with JSON keyword arguments, cached."""
    return noisevar.generate(name, **json.loads(kwargs_json))


# --------------------------------------------------------------------- figures
@cached
def _figure_cached(kind: str, key: str, _build: Callable[[], go.Figure]) -> go.Figure:
    return _build()


def figure(kind: str, inputs: dict[str, object], build: Callable[[], go.Figure]) -> go.Figure:
    """``build()``, once per ``inputs`` (everything the figure depends on), cached.

    A control moved back to an earlier value redraws from the cache. The figure is
    shared: do not modify it.
    """
    return _figure_cached(kind, params_key(inputs), build)


# ------------------------------------------------------------------ estimators
@cached
def _estimate_cached(
    digest: str,
    method: str,
    params_json: str,
    start: int,
    stop: int,
    _z: np.ndarray,
    _t: np.ndarray | None,
) -> VarianceEstimate:
    whole = (start, stop) == (0, _z.size)
    z = _z if whole else _z[start:stop]
    t = _t if whole or _t is None else _t[start:stop]
    return workers.call(noisevar.estimate, z, method=method, t=t, **json.loads(params_json))


def estimate(
    sig: LoadedSignal, method: str, params: dict[str, object], stretch: slice | None = None
) -> VarianceEstimate:
    """:func:`noisevar.estimate` on the signal (or a stretch of it), cached by content hash."""
    start, stop = (0, sig.n) if stretch is None else (stretch.start, stretch.stop)
    key = (sig.digest, method, params_key(params), int(start), int(stop))
    return _estimate_cached(*key, sig.z, sig.times)  # digest covers the times


@cached
def _scan_cached(digest: str, window: int, _z: np.ndarray) -> HScan:
    return scan_h(_z, window)


def h_scan(sig: LoadedSignal, window: int) -> HScan:
    """:func:`noisevar.filters.envelope.scan_h` on the signal, cached."""
    return _scan_cached(sig.digest, int(window), sig.z)


@cached
def _amplitude_cached(
    digest: str, window: int, which: str, _x: np.ndarray
) -> tuple[WindowAmplitude, np.ndarray]:
    return noise_amplitude(_x, window), detrend_windows(_x, window).ravel()


def amplitude(
    sig: LoadedSignal, window: int, x: np.ndarray | None = None, which: str = "raw"
) -> tuple[WindowAmplitude, np.ndarray]:
    """Envelope amplitude (eq. 13) and the window-detrended record, cached.

    ``x`` defaults to the raw signal; pass a filter output with a ``which``
    label that identifies it (e.g. the estimate's parameters).
    """
    return _amplitude_cached(sig.digest, int(window), which, sig.z if x is None else x)


@cached
def _rows_cached(
    digest: str, methods: tuple[str, ...], params_json: str, _z: np.ndarray, _t: np.ndarray | None
) -> list[MethodResult]:
    return workers.call(run_methods, _z, list(methods), json.loads(params_json), _t)


@cached
def _peer_started(
    digest: str, method: str, params_json: str, _z: np.ndarray, _t: np.ndarray | None
) -> workers.Started:
    return workers.start_batch(run_method, _z, method, json.loads(params_json), _t)


def fast_rows(
    sig: LoadedSignal, methods: Sequence[str], params: dict[str, dict[str, object]]
) -> list[MethodResult]:
    """:func:`~noisevar.estimators.compare.run_methods` on the signal (the fast methods: what
    the Compare table shows at once), cached and ahead of the waiting batches."""
    return _rows_cached(sig.digest, tuple(methods), params_key(params), sig.z, sig.times)


def peer_row(
    sig: LoadedSignal, method: str, params: dict[str, object], start: bool = True
) -> workers.Started | None:
    """A slow method's row (:func:`~noisevar.estimators.compare.run_method`) as a task on
    the pool, shared by every session asking for the same record and parameters.

    With ``start=False``, only a task already started (None: none is). A task that ended
    in an error other than a NoisevarError (a broken pool) is forgotten and started anew.
    """
    args = (sig.digest, method, params_key(params), sig.z, sig.times)
    started = _peer_started.peek(*args)
    if started is not None and started.done() and started.future.exception() is not None:
        _peer_started.forget(*args)
        started = None
    if started is None and start:
        started = _peer_started(*args)
    return started


# --------------------------------------------------------------- several sensors
@cached
def _redundant_cached(
    table_digest: str, columns: tuple[str, ...], align: bool, period: float, _sig: LoadedSignal
) -> tuple[noisevar.RedundantEstimate, np.ndarray, DelayEstimate | None, float]:
    from noisevar.systems.latency import align_signals, estimate_delay

    data = sensor_matrix(_sig, columns)
    delay = None
    removed = 0.0
    if align:
        delay = estimate_delay(data[:, 0], data[:, 1], period)
        if delay.is_significant(period):
            # whole samples only: interpolating between samples would average (and so
            # shrink) the noise whose variance is being measured
            removed = round(delay.delay_s / period) * period
            a, b = align_signals(data[:, 0], data[:, 1], removed, period)
            data = np.column_stack([a, b])
    return noisevar.estimate_redundant(data), data, delay, removed


def redundant(
    sig: LoadedSignal, columns: Sequence[str], align: bool = False
) -> tuple[noisevar.RedundantEstimate, np.ndarray, DelayEstimate | None, float]:
    """Redundant SOMD on several columns (optionally delay-aligned first, two sensors), cached.

    With ``align`` the delay of the second sensor behind the first is
    estimated (:func:`noisevar.systems.latency.estimate_delay`) and, when significant
    (``DelayEstimate.is_significant``), removed by a whole-sample shift.

    Returns
    -------
    (RedundantEstimate, ndarray, DelayEstimate or None, float)
        The estimate, the (aligned) sensor matrix it used, the delay estimate,
        and the shift removed (s; 0 when none).
    """
    period = float(sig.sample_period or 1.0)
    return _redundant_cached(sig.table_digest, tuple(columns), bool(align), period, sig)


@cached
def _delay_cached(
    table_digest: str, ref: str, other: str, period: float, _sig: LoadedSignal
) -> DelayEstimate:
    from noisevar.systems.latency import estimate_delay

    return estimate_delay(pick_column(_sig.table, ref), pick_column(_sig.table, other), period)


def delay_between(sig: LoadedSignal, ref: str, other: str) -> DelayEstimate:
    """:func:`~noisevar.systems.latency.estimate_delay` of ``other`` behind ``ref``, cached."""
    return _delay_cached(sig.table_digest, ref, other, float(sig.sample_period or 1.0), sig)


@cached
def _column_estimate_cached(
    table_digest: str, column: str, method: str, _sig: LoadedSignal
) -> VarianceEstimate:
    z, t = channel_record(_sig.table, column)  # as the command line reads it: one answer
    return noisevar.estimate(z, method=method, t=t)


def column_estimate(
    sig: LoadedSignal, column: str, method: str = DEFAULT_METHOD
) -> VarianceEstimate:
    """A single-signal estimate of one column of the signal's table, cached."""
    return _column_estimate_cached(sig.table_digest, column, method, sig)


# ---------------------------------------------------------------- Kalman filters
def scenario_defaults(name: str) -> dict[str, Any]:
    """The keyword parameters of a filter scenario and their defaults (its signature)."""
    from noisevar.systems.scenarios import SCENARIOS

    if name not in SCENARIOS:
        raise NoisevarError(f"unknown scenario {name!r}; choose one of {list(SCENARIOS)}")
    params = inspect.signature(SCENARIOS[name]).parameters
    return {k: p.default for k, p in params.items() if p.default is not inspect.Parameter.empty}


@cached
def kalman_scenario(name: str, seed: int, params_json: str) -> Scenario:
    """A seeded filter scenario of :mod:`noisevar.systems.scenarios` (one run), cached.

    ``params_json`` holds the scenario's own parameters the page set (its duration or
    number of steps, its noise increase...), as :func:`params_key` writes them.
    """
    from noisevar.systems.scenarios import SCENARIOS

    scenario_defaults(name)  # an unknown name is one clear error
    return SCENARIOS[name](runs=1, seed=int(seed), **json.loads(params_json))


def make_filter_strategy(
    name: str, settings: Settings, h_smooth: float, R_true: np.ndarray | None = None
) -> RStrategy:
    """A fresh R-adaptation strategy object from the page's settings."""
    from noisevar.kalman.strategies import make_strategy, strategy_spec

    spec = strategy_spec(name)
    if "R_true" in spec.needs and R_true is None:
        raise NoisevarError(f"the {name} filter needs the true R: only for scenarios")
    tunable = spec.defaults()
    params = {k: settings[k] for k in tunable if settings.get(k) is not None}
    if "h_smooth" in spec.needs:
        params.pop("window", None)  # the page's window is RAE/IAE's; SOMD uses all samples so far
    return make_strategy(name, h_smooth=h_smooth, R_true=R_true, **params)


@cached
def _scenario_run_cached(
    scenario_key: str, strategy: str, settings_json: str, huber: float | None, _sc: Scenario
) -> FilterResult:
    from noisevar.kalman import HuberUpdate

    settings = json.loads(settings_json)
    strat = make_filter_strategy(strategy, settings, _sc.h_smooth, _sc.R_true[_sc.first_step :])
    robust = HuberUpdate(kappa=huber) if huber else None
    return _sc.run(strat, robust=robust)


def scenario_run(
    sc: Scenario, scenario_key: str, strategy: str, settings: Settings, huber: float | None
) -> FilterResult:
    """One strategy on a scenario (:meth:`Scenario.run`), cached by scenario and settings."""
    return _scenario_run_cached(scenario_key, strategy, params_key(settings), huber, sc)


@cached
def _data_run_cached(
    table_digest: str,
    columns: tuple[str, ...],
    period: float,
    h: float,
    r0_factor: float,
    strategy: str,
    settings_json: str,
    huber: float | None,
    _sig: LoadedSignal,
) -> tuple[FilterResult, np.ndarray, np.ndarray]:
    from noisevar.kalman import HuberUpdate, run_filter
    from noisevar.systems.scenarios import constant_velocity_model

    z = sensor_matrix(_sig, columns)
    quick = np.array([column_estimate(_sig, c).variance for c in columns])
    r0 = quick * r0_factor
    model = constant_velocity_model(z[0], period, h, r0, columns)
    settings = json.loads(settings_json)
    h_smooth = float(settings.get("h_smooth", 9e-4))
    strat = make_filter_strategy(strategy, settings, h_smooth)
    robust = HuberUpdate(kappa=huber) if huber else None
    return run_filter(model, z, strategy=strat, robust=robust), z, quick


def data_run(
    sig: LoadedSignal,
    columns: Sequence[str],
    h: float,
    r0_factor: float,
    strategy: str,
    settings: Settings,
    huber: float | None,
) -> tuple[FilterResult, np.ndarray, np.ndarray]:
    """One strategy on chosen columns of the loaded table, cached.

    The model is :func:`noisevar.systems.scenarios.constant_velocity_model`.

    Returns
    -------
    (FilterResult, ndarray, ndarray)
        The run, the measurements ``(N, m)`` and each channel's quick
        single-signal variance estimate (method auto).
    """
    period = float(sig.sample_period or 1.0)
    return _data_run_cached(
        sig.table_digest,
        tuple(columns),
        period,
        float(h),
        float(r0_factor),
        strategy,
        params_key(settings),
        huber,
        sig,
    )


@cached
def table1(runs: int, seed: int) -> JsonDict:
    """The GPS-circle experiment (the paper's Table 1) with ``runs`` Monte Carlo runs, cached."""
    from noisevar.experiments.gps_circle import EXPERIMENT

    return EXPERIMENT.run(runs=int(runs), seed=int(seed)).to_dict()


# ------------------------------------------------------ the other seed systems
@cached
def fusion_data(
    fault: str, steps: int, runs: int, seed: int, noise_factor: float, bias: float
) -> FusionData:
    """:func:`noisevar.systems.fusion.simulate_fusion` for the page's settings, cached."""
    from noisevar.systems.fusion import FusionScenario, simulate_fusion

    scen = FusionScenario(
        n_steps=int(steps), fault=fault, noise_factor=float(noise_factor), bias_sigmas=float(bias)
    )
    return simulate_fusion(scen, seed=int(seed), runs=int(runs))


@cached
def _fusion_run_cached(
    data_key: str, config: str, false_alarm: float, _data: FusionData
) -> FusionResult:
    from noisevar.systems.fusion import run_fusion

    local, _, iso = config.partition("+")
    return run_fusion(_data, local=local, isolation=bool(iso), false_alarm=float(false_alarm))


def fusion_run(data: FusionData, data_key: str, config: str, false_alarm: float) -> FusionResult:
    """``run_fusion`` for a configuration like ``"vb+isolation"``, cached."""
    return _fusion_run_cached(data_key, config, float(false_alarm), data)


@cached
def _fusion_equivalence_cached(data_key: str, _data: FusionData) -> float:
    from noisevar.systems.fusion import max_abs_diff_vs_centralized

    return max_abs_diff_vs_centralized(_data)


def fusion_equivalence(data: FusionData, data_key: str) -> float:
    """Largest |fused − centralised| state difference (fixed R, no isolation), cached."""
    return _fusion_equivalence_cached(data_key, data)


@cached
def robust_run(
    outliers: bool,
    magvar: float,
    burst_rate: float,
    kappa: float,
    iterations: int,
    runs: int,
    seed: int,
) -> RobustResult:
    """:func:`noisevar.systems.robust.run_robust` on a simulated fly-over, cached."""
    from noisevar.systems.robust import RobustScenario, run_robust, simulate_robust

    scen = RobustScenario(
        magvar_deg=float(magvar), outliers=bool(outliers), burst_rate=float(burst_rate)
    )
    data = simulate_robust(scen, seed=int(seed), runs=int(runs))
    return run_robust(data, kappa=float(kappa), iterations=int(iterations))


@cached
def carrier_runs(
    settings_json: str, runs: int, seed: int, window: int, nominal_cn0: float
) -> dict[str, CarrierResult]:
    """The realistic comparison (``carrier.compare``) on the same signals, cached.

    ``ekf`` is designed for ``nominal_cn0``; ``aekf`` adapts from that design
    (eq. 22 R, stabilised Q); ``ekf_matched`` knows the true noise;
    ``aekf_paper_q`` is the paper's eq. 26 (it runs away).
    """
    from noisevar.systems.carrier import CarrierScenario, compare, comparison_variants

    scen = CarrierScenario(**json.loads(settings_json))
    variants = comparison_variants(nominal_cn0_dbhz=float(nominal_cn0))
    chosen = {k: variants[k] for k in CARRIER_FILTERS}
    return compare(scen, chosen, seed=int(seed), runs=int(runs), window=int(window))


@cached
def carrier_sweep(
    settings_json: str, cn0: tuple[float, ...], runs: int, seed: int, nominal_cn0: float
) -> CarrierSweep:
    """:func:`noisevar.systems.carrier.cn0_sweep` of the page's filters for its scenario, cached."""
    from noisevar.systems.carrier import CarrierScenario, cn0_sweep, comparison_variants

    scen = CarrierScenario(**json.loads(settings_json))
    variants = comparison_variants(nominal_cn0_dbhz=float(nominal_cn0))
    chosen = {k: variants[k] for k in CARRIER_FILTERS}
    return cn0_sweep(tuple(cn0), runs=int(runs), seed=int(seed), scenario=scen, variants=chosen)


@cached
def latency_run(settings_json: str, seed: int, max_delay: float) -> LatencyResult:
    """:func:`noisevar.systems.latency.run_latency` on a simulated flight, cached."""
    from noisevar.systems.latency import LatencyScenario, run_latency, simulate_latency

    record = simulate_latency(LatencyScenario(**json.loads(settings_json)), seed=int(seed))
    return run_latency(record, max_delay_s=float(max_delay))
