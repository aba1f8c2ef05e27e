"""Every estimator side by side, on one signal and over Monte Carlo runs.

* :func:`compare_methods` runs each method of :func:`noisevar.methods` on one
  signal and collects estimates, 95 % intervals, timings and failures into a
  :class:`Comparison` (a table; one method failing does not stop the others).
* :func:`monte_carlo` repeats that over generated signals with fresh noise
  (the paper's Fig. 2) and **yields** a :class:`MonteCarloResult` snapshot as
  it goes, so a caller can draw a progress bar and stop early: a dashboard
  stops iterating, a script calls ``close()`` on the generator, or
  :func:`run_monte_carlo` takes a callback that returns ``False`` to cancel.
  Each snapshot holds the relative errors so far and the Cramér-Rao floor
  ``sqrt(2/n)`` (docs/algorithms.md §A8): the relative standard deviation of the best
  possible variance estimate from ``n`` Gaussian samples.
* :func:`simulate_sensors` makes several real sensors of one quantity (for
  the redundant SOMD of docs/algorithms.md §A1).
"""

from __future__ import annotations

import csv
import io
import math
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators import METHODS, estimate
from noisevar.estimators.mc_summary import summary_row
from noisevar.estimators.results import VarianceEstimate, row_columns
from noisevar.io import LoadedTable, table_from_arrays
from noisevar.signals import generate, signal_names, signal_spec

#: Record length above which :func:`default_methods` leaves the slow methods out.
SLOW_METHOD_LIMIT = 20_000
#: Columns of a comparison row before the estimate's (:meth:`Comparison.rows`).
COMPARE_LEAD = ("method", "kind")
#: Columns of a comparison row after the estimate's.
COMPARE_TAIL = ("rel_halfwidth", "ms", "rel_error", "covers_truth", "error", "description")


def single_signal_methods() -> list[str]:
    """Methods that estimate from one signal alone (all but those that need a reference)."""
    return [m for m, spec in METHODS.items() if not spec.needs_reference]


def slow_methods() -> list[str]:
    """Methods that take seconds on a long record (their spec says ``slow``)."""
    return [m for m, spec in METHODS.items() if spec.slow]


#: The built-in slow methods (:func:`slow_methods` also sees methods registered later).
SLOW_METHODS = tuple(slow_methods())


def default_methods(n: int, monte_carlo: bool = False) -> list[str]:
    """The methods a comparison runs by default on ``n`` samples.

    All single-signal methods; the state-space maximum-likelihood peers
    (about 0.4 s per 6000 samples, seconds per 1e5) only on one signal of at
    most :data:`SLOW_METHOD_LIMIT` samples, never by default in a Monte Carlo.

    Parameters
    ----------
    n : int
        Record length.
    monte_carlo : bool
        Defaults for a Monte Carlo run (no slow methods).

    Returns
    -------
    list of str
    """
    slow_ok = n <= SLOW_METHOD_LIMIT and not monte_carlo
    return [m for m in single_signal_methods() if slow_ok or not METHODS[m].slow]


def relative_error(value: float, true_value: float) -> float:
    """``value / true_value - 1`` (NaN when the truth is not positive)."""
    if not (true_value and true_value > 0 and math.isfinite(true_value)):
        return float("nan")
    return float(value) / float(true_value) - 1.0


def cramer_rao_floor(n: int) -> float:
    """Relative standard deviation floor ``sqrt(2/n)`` of a variance from ``n`` samples."""
    if n < 1:
        raise NoisevarError(f"n must be positive, got {n}")
    return math.sqrt(2.0 / n)


# ------------------------------------------------------------------ one signal
@dataclass
class MethodResult:
    """One method's outcome in a :class:`Comparison`.

    Attributes
    ----------
    method, kind, description : str
        From the method registry.
    estimate : VarianceEstimate or None
        None when the method failed.
    error : str or None
        The failure message (a :class:`NoisevarError`).
    seconds : float
        Wall time of the call.
    """

    method: str
    kind: str
    description: str
    estimate: VarianceEstimate | None
    error: str | None
    seconds: float

    @property
    def variance(self) -> float:
        """Estimated variance (NaN if failed)."""
        return self.estimate.variance if self.estimate else float("nan")

    @property
    def ci95(self) -> tuple[float, float]:
        """95 % interval (NaN if failed)."""
        return self.estimate.ci95 if self.estimate else (float("nan"), float("nan"))


@dataclass
class Comparison:
    """Every method on one signal.

    Attributes
    ----------
    n : int
        Samples in the signal.
    results : list of MethodResult
        One per method, in the order asked.
    true_variance : float or None
        The known noise variance (generated signals), for relative errors.
    """

    n: int
    results: list[MethodResult]
    true_variance: float | None = None

    @property
    def cr_floor(self) -> float:
        """Cramér-Rao relative standard deviation ``sqrt(2/n)``."""
        return cramer_rao_floor(self.n)

    def rows(self) -> list[dict[str, Any]]:
        """The comparison as table rows (one dict per method, JSON-ready).

        Returns
        -------
        list of dict
            Each :data:`COMPARE_LEAD`, the estimate's row
            (:meth:`~noisevar.estimators.results.VarianceEstimate.to_row`, the one row
            schema; empty for a method that failed) and :data:`COMPARE_TAIL`
            (``rel_error`` and ``covers_truth`` only with a known truth); every row has
            the same keys.
        """
        out = []
        for r in self.results:
            e = r.estimate
            row: dict[str, Any] = {
                "method": r.method,
                "kind": r.kind,
                **(e.to_row() if e else {}),
                "rel_halfwidth": e.relative_halfwidth if e else float("nan"),
                "ms": 1000.0 * r.seconds,
            }
            if self.true_variance is not None:
                row["rel_error"] = relative_error(r.variance, self.true_variance)
                lo, hi = r.ci95
                row["covers_truth"] = bool(lo <= self.true_variance <= hi) if e else False
            row["error"] = r.error
            row["description"] = r.description
            out.append(row)
        keys = {k: None for row in out for k in row}
        tail = [c for c in COMPARE_TAIL if c in keys]
        cols = row_columns(keys, lead=COMPARE_LEAD, tail=tail)
        return [{c: row.get(c) for c in cols} for row in out]

    def to_csv(self) -> str:
        """The table as CSV text."""
        return rows_to_csv(self.rows())


def rows_to_csv(rows: Sequence[Mapping[str, Any]]) -> str:
    """Table rows (dicts) as CSV text: the union of their keys as columns, in first-seen order.

    Floats in full (``repr``: read back, the same float); a key missing from a row is empty.
    """
    if not rows:
        return ""
    fields: dict[str, None] = {}
    for row in rows:
        fields.update(dict.fromkeys(row))
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(fields), lineterminator="\n", restval="")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: repr(float(v)) if isinstance(v, float) else v for k, v in row.items()})
    return buf.getvalue()


def _check_methods(names: Sequence[str] | None, default: list[str]) -> list[str]:
    if names is None:
        return default
    names = list(names)
    if not names:
        raise NoisevarError("no method chosen: pick at least one")
    unknown = [m for m in names if m not in METHODS]
    if unknown:
        raise NoisevarError(
            f"unknown method(s) {', '.join(unknown)}; choose from: {', '.join(METHODS)}"
        )
    return names


def compare_methods(
    z: ArrayLike,
    methods: Sequence[str] | None = None,
    params: Mapping[str, Mapping[str, Any]] | None = None,
    true_variance: float | None = None,
    t: ArrayLike | None = None,
) -> Comparison:
    """Run several estimators on one signal.

    Parameters
    ----------
    z : array_like, shape (n,)
        The signal.
    methods : sequence of str, optional
        Methods to run (default :func:`default_methods`).
    params : mapping of str to mapping, optional
        Keyword parameters per method, e.g. ``{"somd": {"h_smooth": 1e-4}}``.
    true_variance : float, optional
        Known noise variance, for relative errors and interval coverage.
    t : array_like, shape (n,), optional
        Sample times, as :func:`~noisevar.estimators.estimate` takes them.

    Returns
    -------
    Comparison

    Raises
    ------
    NoisevarError
        Unknown methods, or a signal no method can use (not numeric, empty).
    """
    z = np.asarray(z, dtype=float)
    names = _check_methods(methods, default_methods(z.size))
    return comparison_of(z.size, run_methods(z, names, params, t), true_variance)


def run_methods(
    z: ArrayLike,
    methods: Sequence[str],
    params: Mapping[str, Mapping[str, Any]] | None = None,
    t: ArrayLike | None = None,
) -> list[MethodResult]:
    """:func:`run_method` for each of ``methods`` in order (``params`` by method)."""
    z = np.asarray(z, dtype=float)
    return [run_method(z, m, (params or {}).get(m), t) for m in methods]


def run_method(
    z: ArrayLike, method: str, params: Mapping[str, Any] | None = None, t: ArrayLike | None = None
) -> MethodResult:
    """One row of :func:`compare_methods`: ``method`` (with its keyword ``params``) on the
    signal and its times ``t``; a :class:`NoisevarError` is kept as the row's ``error``."""
    _check_methods([method], [])
    t0 = time.perf_counter()
    try:
        est, err = estimate(np.asarray(z, float), method=method, t=t, **dict(params or {})), None
    except NoisevarError as exc:
        est, err = None, str(exc)
    meta = METHODS[method]
    return MethodResult(method, meta.kind, meta.description, est, err, time.perf_counter() - t0)


def comparison_of(
    n: int, results: Sequence[MethodResult], true_variance: float | None = None
) -> Comparison:
    """The :class:`Comparison` of rows computed one by one (:func:`run_method`); a
    :class:`NoisevarError` when every method failed (the first one's message)."""
    results = list(results)
    if results and all(r.estimate is None for r in results):
        raise NoisevarError(f"every method failed; the first said: {results[0].error}")
    return Comparison(n, results, true_variance)


# ----------------------------------------------------------------- Monte Carlo
@dataclass
class MonteCarloResult:
    """Relative errors of several methods over repeated noise realisations.

    A snapshot: :func:`monte_carlo` yields one after every run, with the
    arrays filled so far.

    Attributes
    ----------
    signal : str
        Signal family (:func:`noisevar.signal_names`).
    n : int
        Samples per run.
    runs_requested : int
        Runs asked for.
    runs_done : int
        Runs finished so far.
    seed : int
        Run ``i`` uses seed ``seed + i``.
    true_variance : float
        The generator's noise variance (record mean).
    methods : list of str
        Methods compared.
    relative_errors : dict of str to ndarray
        ``estimate / true - 1`` per run (NaN where the method failed).
    failures : dict of str to int
        Failed runs per method.
    seconds : dict of str to float
        Total time per method.
    first_error : dict of str to str
        The first failure message of each method that failed.
    signal_params : dict
        Extra generator parameters.
    params : dict of str to dict
        Each method's parameters in use (empty: its defaults).
    """

    signal: str
    n: int
    runs_requested: int
    runs_done: int
    seed: int
    true_variance: float
    methods: list[str]
    relative_errors: dict[str, NDArray]
    failures: dict[str, int]
    seconds: dict[str, float]
    first_error: dict[str, str] = field(default_factory=dict)
    signal_params: dict[str, Any] = field(default_factory=dict)
    params: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def finished(self) -> bool:
        """All requested runs are done."""
        return self.runs_done >= self.runs_requested

    @property
    def fraction_done(self) -> float:
        """Progress in [0, 1]."""
        return self.runs_done / self.runs_requested if self.runs_requested else 1.0

    @property
    def cr_floor(self) -> float:
        """Cramér-Rao relative standard deviation ``sqrt(2/n)``."""
        return cramer_rao_floor(self.n)

    def summary(self) -> list[dict[str, Any]]:
        """Per-method statistics of the relative errors (rows, JSON-ready).

        Returns
        -------
        list of dict
            ``method, runs, failures, status, params, bias, sd, rmse, rmse_over_cr,
            within_10pct, max_abs, ms_per_run`` (:func:`~noisevar.estimators.mc_summary.
            summary_row`: no statistics when too few runs succeeded).
        """
        rows = []
        for m in self.methods:
            row = summary_row(
                m,
                self.relative_errors[m],
                self.failures.get(m, 0),
                self.runs_done,
                self.cr_floor,
                self.params.get(m),
            )
            done = max(self.runs_done, 1)
            row["ms_per_run"] = 1000.0 * self.seconds.get(m, 0.0) / done
            rows.append(row)
        return rows

    def to_csv(self) -> str:
        """Long-form CSV: one row per run and method (``run, seed, method, relative_error``)."""
        rows = [
            {"run": i, "seed": self.seed + i, "method": m, "relative_error": float(e[i])}
            for m, e in self.relative_errors.items()
            for i in range(e.size)
        ]
        return rows_to_csv(rows)


def monte_carlo(
    signal: str = "fast-slow",
    runs: int = 100,
    methods: Sequence[str] | None = None,
    params: Mapping[str, Mapping[str, Any]] | None = None,
    n: int = 6000,
    noise_std: float | None = None,
    seed: int = 0,
    signal_params: Mapping[str, Any] | None = None,
) -> Iterator[MonteCarloResult]:
    """Monte Carlo comparison of estimators over generated signals, yielding progress.

    Run ``i`` generates ``signal`` with seed ``seed + i`` (fresh noise; a new
    clean signal too for the random families) and runs every method on it.
    After each run a :class:`MonteCarloResult` snapshot is yielded; stop
    iterating (or ``close()`` the generator) to cancel, keeping the last
    snapshot as a partial result.

    Parameters
    ----------
    signal : str
        Signal family (:func:`noisevar.signal_names`).
    runs : int
        Number of runs (1 to 100000).
    methods : sequence of str, optional
        Methods (default ``default_methods(n, monte_carlo=True)``).
    params : mapping of str to mapping, optional
        Keyword parameters per method.
    n : int
        Samples per run.
    noise_std : float, optional
        Noise standard deviation (default: the family's).
    seed : int
        Seed of run 0.
    signal_params : mapping, optional
        Extra generator parameters (``channel``, ``factor``...).

    Yields
    ------
    MonteCarloResult
        The state after each run (the arrays hold the runs done so far).

    Raises
    ------
    NoisevarError
        Bad signal name, run count, length or methods (raised on the first
        ``next()``).

    Examples
    --------
    >>> last = None
    >>> for snap in monte_carlo("fast-slow", runs=3, methods=["diff2"], n=2000):
    ...     last = snap
    >>> last.runs_done, last.finished
    (3, True)
    """
    if signal not in signal_names():
        raise NoisevarError(f"unknown signal {signal!r}; choose one of {signal_names()}")
    runs = int(runs)
    if not 1 <= runs <= 100_000:
        raise NoisevarError(f"runs must be between 1 and 100000, got {runs}")
    n = int(n)
    names = _check_methods(methods, default_methods(n, monte_carlo=True))
    params = params or {}
    gen_kwargs: dict[str, Any] = dict(signal_params or {})
    if noise_std is not None:
        if not (noise_std > 0 and math.isfinite(noise_std)):
            raise NoisevarError(f"noise_std must be positive, got {noise_std}")
        gen_kwargs["noise_std"] = float(noise_std)
    first = generate(signal, n=n, seed=int(seed), **gen_kwargs)
    true_var = first.true_variance
    errors = {m: np.full(runs, np.nan) for m in names}
    failures = dict.fromkeys(names, 0)
    seconds = dict.fromkeys(names, 0.0)
    first_error: dict[str, str] = {}
    for i in range(runs):
        g = first if i == 0 else generate(signal, n=n, seed=int(seed) + i, **gen_kwargs)
        for m in names:
            t0 = time.perf_counter()
            try:
                v = estimate(g.measured, method=m, **dict(params.get(m, {}))).variance
                errors[m][i] = v / true_var - 1.0
            except NoisevarError as exc:
                failures[m] += 1
                first_error.setdefault(m, str(exc))
            seconds[m] += time.perf_counter() - t0
        yield MonteCarloResult(
            signal=signal,
            n=n,
            runs_requested=runs,
            runs_done=i + 1,
            seed=int(seed),
            true_variance=true_var,
            methods=list(names),
            relative_errors={m: errors[m][: i + 1] for m in names},
            failures=dict(failures),
            seconds=dict(seconds),
            first_error=dict(first_error),
            signal_params=dict(gen_kwargs),
            params={m: dict(params.get(m, {})) for m in names},
        )


def run_monte_carlo(
    *args: Any,
    callback: Callable[[MonteCarloResult], bool | None] | None = None,
    **kwargs: Any,
) -> MonteCarloResult:
    """Run :func:`monte_carlo` to the end (or until ``callback`` returns ``False``).

    Parameters
    ----------
    *args, **kwargs
        Passed to :func:`monte_carlo`.
    callback : callable, optional
        Called with each snapshot; returning ``False`` cancels.

    Returns
    -------
    MonteCarloResult
        The last snapshot (``finished`` is False when cancelled).
    """
    last = None
    gen = monte_carlo(*args, **kwargs)
    try:
        for snap in gen:
            last = snap
            if callback is not None and callback(snap) is False:
                break
    finally:
        gen.close()
    assert last is not None  # runs >= 1
    return last


# ----------------------------------------------------------- redundant sensors
def simulate_sensors(
    signal: str = "fast-slow",
    noise_stds: Sequence[float] = (1.0, 3.0),
    n: int = 6000,
    seed: int = 0,
    offsets: Sequence[float] | None = None,
    drift: float = 0.0,
) -> LoadedTable:
    """Several real sensors of one quantity: the same clean signal, independent noises.

    Sensor ``i`` reads ``clean + offset_i + drift_i(t) + noise_i`` with a slowly
    varying systematic error (a constant offset plus a slow sinusoid of
    amplitude ``drift`` over the record), as docs/algorithms.md §A1 assumes.

    Parameters
    ----------
    signal : str
        Signal family for the clean signal.
    noise_stds : sequence of float
        Noise standard deviation of each sensor (two or more).
    n : int
        Samples.
    seed : int
        Seed (sensor ``i`` uses noise seed ``seed + 1 + i``).
    offsets : sequence of float, optional
        Constant offsets (default 0).
    drift : float
        Amplitude of a slow systematic drift per sensor.

    Returns
    -------
    LoadedTable
        Columns ``time`` (when the family has a sample period) and
        ``sensor1..k``; the true variances are in the notes.
    """
    stds = [float(s) for s in noise_stds]
    if len(stds) < 2:
        raise NoisevarError("give two or more sensors (noise_stds)")
    if any(not (s > 0 and math.isfinite(s)) for s in stds):
        raise NoisevarError(f"noise standard deviations must be positive, got {stds}")
    offs = [0.0] * len(stds) if offsets is None else [float(o) for o in offsets]
    if len(offs) != len(stds):
        raise NoisevarError("give one offset per sensor")
    base = generate(signal, n=n, seed=seed, noise_std=1.0)
    u = np.linspace(0.0, 1.0, base.clean.size)
    timed = "sample_period" in signal_spec(signal).param_specs  # the family sets its period
    cols: dict[str, NDArray] = {"time": base.t} if timed else {}
    for i, (s, o) in enumerate(zip(stds, offs, strict=True)):
        rng = np.random.default_rng(seed + 1 + i)
        slow = drift * np.sin(2 * np.pi * (0.5 + 0.3 * i) * u + i)
        cols[f"sensor{i + 1}"] = base.clean + o + slow + rng.standard_normal(base.clean.size) * s
    table = table_from_arrays(
        f"{signal} seen by {len(stds)} sensors",
        cols,
        sample_period=base.sample_period,
        kind="generated",
        notes=[
            "true noise variances: "
            + ", ".join(f"sensor{i + 1} {s**2:.4g}" for i, s in enumerate(stds))
        ],
    )
    if "time" in cols:
        table.time_column = "time"
    return table
