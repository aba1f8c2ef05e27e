"""Result types of the variance estimators, and the one row schema of an estimate.

:meth:`VarianceEstimate.to_row` is an estimate as one flat table row (the columns
:data:`ROW_COLUMNS`, with a ``flag_<name>`` column per diagnostic flag) and
:meth:`VarianceEstimate.to_dict` the same fields nested, for JSON. Every table of
estimates is made from them: :meth:`VarianceEstimates.to_frame`, the CLI's csv,
``noisevar batch`` and the comparison of methods, through :func:`rows_frame` and
:func:`row_columns`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf
from noisevar.filters.selection import WindowSelection

if TYPE_CHECKING:
    import pandas as pd

    from noisevar.diagnostics import NoiseDiagnostics

#: The columns of one estimate's row (:meth:`VarianceEstimate.to_row`), in table order.
#: One ``flag_<name>`` column per diagnostic flag (``flag_white``, ``flag_heavy_tailed``,
#: ...) comes after ``still_note``, in name order.
ROW_COLUMNS: tuple[str, ...] = (
    "method",
    "variance",
    "std",
    "ci95_low",
    "ci95_high",
    "n_used",
    "n_total",
    "dof",
    "core_variance",
    "outlier_fraction",
    "still_variance",
    "still_ci95_low",
    "still_ci95_high",
    "still_note",
    "other_still_levels",
    "verdict",
    "params",
    "notes",
)

#: Human labels of the row keys (reports, tables shown to people); prefixed keys
#: (``param_``, ``windows_``, ``flag_``) are labelled by :func:`row_label`.
ROW_LABELS: dict[str, str] = {
    "method": "method",
    "variance": "noise variance R",
    "std": "noise standard deviation",
    "ci95_low": "95 % interval, low",
    "ci95_high": "95 % interval, high",
    "n_used": "samples used",
    "n_total": "samples in the record",
    "dof": "degrees of freedom",
    "core_variance": "variance without outliers",
    "outlier_fraction": "fraction of outliers",
    "still_variance": "noise variance R of the still regimes",
    "still_ci95_low": "still regimes: 95 % interval, low",
    "still_ci95_high": "still regimes: 95 % interval, high",
    "still_note": "why there is no still R",
    "other_still_levels": "other still levels (stretches above the still R, over it)",
    "verdict": "verdict",
    "params": "parameters",
    "notes": "notes",
    "true_variance": "true noise variance",
    "relative_error": "relative error (estimate / true - 1)",
    "windows_windows": "windows tested",
    "windows_kept": "windows kept",
    "windows_failed_amplitude": "windows refused by the amplitude test",
    "windows_failed_angle": "windows refused by the angle test",
}
#: Row keys whose value carries the variance's unit (squared) or the signal's.
_SQUARED = {"variance", "ci95_low", "ci95_high", "core_variance", "true_variance"} | {
    "still_variance",
    "still_ci95_low",
    "still_ci95_high",
}


def row_label(key: str, unit: str = "") -> str:
    """The human label of a row key: ``"ci95_low"`` -> ``"95 % interval, low"``.

    Parameters
    ----------
    key : str
        A row key (:data:`ROW_COLUMNS`, ``param_<name>``, ``windows_<name>``,
        ``flag_<name>``, or :data:`ROW_LABELS`).
    unit : str
        The signal's unit: variances are labelled with its square, the std with it.

    Returns
    -------
    str
    """
    from noisevar.format import squared

    if key in ROW_LABELS:
        label = ROW_LABELS[key]
    elif key.startswith("param_"):
        from noisevar.estimators.params import PARAMS

        name = key.removeprefix("param_")
        spec = PARAMS.get(name)
        label = f"parameter {name}" + (f": {spec.help}" if spec is not None else "")
    elif key.startswith("flag_"):
        label = "flag: " + key.removeprefix("flag_").replace("_", " ")
    else:
        label = key.replace("_", " ")
    u = squared(unit) if key in _SQUARED else unit if key == "std" else ""
    return f"{label} [{u}]" if u else label


def _still_fields(est: VarianceEstimate) -> dict[str, float | str | None]:
    """``still_variance``, its interval and ``still_note`` (why they are empty:
    ``still_set.still_note``); R there when the level varies and R is the R to use (its still
    stretches read R's level: ``still_gap`` None), as ``regimes="still"`` quotes it; empty
    where ``regimes="still"`` refuses (``still_set.still_refusal``)."""
    from noisevar.estimators.still_set import still_gap, still_note, still_refusal

    still, diag = est.still, est.diagnostics
    note = still_note(diag, est.variance, still)
    if still is None and diag is not None and diag.level_varies:
        still = est if still_gap(diag, est.variance, None) is None else None
    if still is not None and still_refusal(diag, est.variance, est.still) is not None:
        still = None  # a smoothed output's: measured, no R to use (still_note says so)
    cells = (None, None, None) if still is None else (still.variance, *still.ci95)
    keys = ("still_variance", "still_ci95_low", "still_ci95_high")
    return {k: None if v is None else _finite(v) for k, v in zip(keys, cells, strict=True)} | {
        "still_note": note
    }


#: Prefix of the diagnostic flags' columns.
FLAG_PREFIX = "flag_"
#: The flag columns follow this column.
_FLAGS_AFTER = "still_note"
#: Count columns: nullable integers in a frame (a row without an estimate has none).
COUNT_COLUMNS = ("n_used", "n_total")
#: Number columns: floats in a frame (NaN where a row has none).
FLOAT_COLUMNS = (
    "variance",
    "std",
    "ci95_low",
    "ci95_high",
    "dof",
    "core_variance",
    "outlier_fraction",
    "still_variance",
    "still_ci95_low",
    "still_ci95_high",
)
#: Fields of :meth:`VarianceEstimate.to_row` that :meth:`~VarianceEstimate.to_dict` nests.
_NESTED = ("other_still_levels", "verdict", "params", "notes")


def _other_still(diag: NoiseDiagnostics | None, still: VarianceEstimate | None) -> str | None:
    """The row's ``other_still_levels``: JSON text of ``NoiseDiagnostics.other_still`` (each
    ``start``, ``stop``, ``ratio``, ``ci95_low``, ``ci95_high``, over the still R); None
    when there is none."""
    if diag is None or still is None or not diag.other_still:
        return None
    return json.dumps([x.to_dict() for x in diag.other_still])


def _flag(value: bool | None) -> bool | None:
    """A flag's cell: None where the record was too short to check it."""
    return None if value is None else bool(value)


def _finite(value: Any) -> float | None:
    """A float, or None for a missing or non-finite value (rows are strict-JSON safe)."""
    if value is None:
        return None
    v = float(value)
    return v if math.isfinite(v) else None


def _json_value(obj: Any) -> Any:
    """NumPy scalars and arrays of ``params`` as plain JSON values."""
    if hasattr(obj, "item"):
        return obj.item()
    if hasattr(obj, "tolist"):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def row_columns(
    columns: Iterable[str], lead: Sequence[str] = (), tail: Sequence[str] = ()
) -> list[str]:
    """The order of a table of estimate rows: ``lead``, the schema, ``tail``, then the rest.

    Parameters
    ----------
    columns : iterable of str
        The columns the rows have.
    lead : sequence of str
        What the rows are of, before the estimate (``file``, ``channel``, ...).
    tail : sequence of str
        Columns of the caller after the estimate (``error``, timings, ...).

    Returns
    -------
    list of str
        Every column of ``lead``, :data:`ROW_COLUMNS` and ``tail`` (present or not), the
        ``flag_*`` columns present after ``still_note``, then any other column.
    """
    cols = list(dict.fromkeys(columns))
    own = {*lead, *tail}
    flags = sorted(c for c in cols if c.startswith(FLAG_PREFIX) and c not in own)
    schema: list[str] = []
    for c in ROW_COLUMNS:
        if c not in own:
            schema.append(c)
        if c == _FLAGS_AFTER:
            schema.extend(flags)
    order = [*lead, *schema, *tail]
    return order + [c for c in cols if c not in set(order)]


def row_dtypes(columns: Iterable[str]) -> dict[str, str]:
    """The pandas dtypes of the schema's number, count and flag columns among ``columns``.

    A row without an estimate (an error) has no number, count or flag: ``float64``
    (NaN), ``Int64`` and ``boolean`` keep the others' type, and read back the same from
    Parquet and CSV.
    """
    out = {}
    for c in columns:
        if c in FLOAT_COLUMNS:
            out[c] = "float64"
        elif c in COUNT_COLUMNS:
            out[c] = "Int64"
        elif c.startswith(FLAG_PREFIX):
            out[c] = "boolean"
    return out


def rows_frame(
    rows: Sequence[dict[str, Any]], lead: Sequence[str] = (), tail: Sequence[str] = ()
) -> pd.DataFrame:
    """Estimate rows (:meth:`VarianceEstimate.to_row` and context) as a DataFrame.

    Parameters
    ----------
    rows : sequence of dict
        One dict per row; a key missing from a row is a missing value.
    lead, tail : sequence of str
        The caller's columns before and after the estimate (:func:`row_columns`).

    Returns
    -------
    pandas.DataFrame
        Columns in :func:`row_columns` order, counts and flags nullable
        (:func:`row_dtypes`).
    """
    import pandas as pd

    frame = pd.DataFrame(list(rows))
    frame = frame.reindex(columns=row_columns(frame.columns, lead, tail))
    return frame.astype(row_dtypes(frame.columns))


def chi2_interval(variance: float, dof: float, level: float = 0.95) -> tuple[float, float]:
    """Confidence interval of a variance estimate with ``dof`` effective degrees of freedom.

    ``(ν v / χ²_{1-a/2,ν}, ν v / χ²_{a/2,ν})`` (docs/algorithms.md §F4).

    Parameters
    ----------
    variance : float
        The estimate.
    dof : float
        Effective degrees of freedom (> 0).
    level : float
        Confidence level.

    Returns
    -------
    (low, high) : tuple of float
    """
    if not (dof > 0 and np.isfinite(variance)):
        return (float("nan"), float("nan"))
    a = 1.0 - level
    # (ν v / χ²_{1-a/2,ν}, ν v / χ²_{a/2,ν})
    lo = dof * variance / chi2_ppf(1.0 - a / 2.0, dof)
    hi = dof * variance / chi2_ppf(a / 2.0, dof)
    return (float(lo), float(hi))


@dataclass
class SomdDetails:
    """What the dashboard draws for a SOMD estimate.

    Attributes
    ----------
    h_smooth : tuple of float
        Smoothing filter parameters ``h_S`` (several: docs/algorithms.md §A6).
    h_track : float
        Tracking filter parameter ``h_T``.
    smooth_output : ndarray, shape (n_h, n)
        One-step predictions of each smoothing filter (the virtual sensors).
    track_output : ndarray, shape (n,)
        Tracking filter output.
    selection : WindowSelection or None
        Per-window tests (None when selection is off).
    kept_windows : ndarray of bool, shape (n_windows,)
        Windows used (any smoothing ``h`` passing, §A6).
    window_variance : ndarray, shape (n_windows,)
        Variance estimate of each window (NaN where not kept).
    sample_mask : ndarray of bool, shape (n,)
        Samples whose mutual differences entered the estimate.
    bias_factor : tuple of float
        The divisor used for each ``h`` (2 for the paper, ``c(h)`` otherwise).
    skip : int
        Leading samples discarded as the filters' start-up transient.
    """

    h_smooth: tuple[float, ...]
    h_track: float
    smooth_output: NDArray
    track_output: NDArray
    selection: WindowSelection | None
    kept_windows: NDArray
    window_variance: NDArray
    sample_mask: NDArray
    bias_factor: tuple[float, ...]
    skip: int


@dataclass
class VarianceEstimate:
    """One noise-variance estimate.

    Attributes
    ----------
    method : str
        Method name (see :func:`noisevar.methods`).
    variance : float
        Estimated noise variance (signal units squared).
    ci95 : (float, float)
        95 % confidence interval of the variance.
    n_used : int
        Samples that entered the estimate.
    n_total : int
        Samples given (after any dropped non-finite ones).
    dof : float
        Effective degrees of freedom behind ``ci95``.
    params : dict
        The parameters that define the estimate (the JSON config form).
    notes : list of str
        Plain-language remarks (dropped samples, fallbacks taken).
    details : SomdDetails or None
        Arrays for figures (SOMD methods only).
    core_variance : float or None
        Gaussian-equivalent variance of the bulk, outliers left out (for a robust
        filter); None when the method does not separate them.
    outlier_fraction : float
        Share of samples outside the bulk.
    diagnostics : NoiseDiagnostics or None
        What the record's noise looks like (docs/algorithms.md §E1-§E3), with a
        one-sentence verdict.
    assumptions : dict of str to bool
        What the method assumes of the noise, and whether this record satisfies it.
    jumps : ndarray of bool or None
        Samples left out around persistent level jumps (signal, not noise); None for
        methods that do not look for jumps.
    still : VarianceEstimate or None
        The same method on the record's still regimes alone (the sensor's own noise,
        docs/algorithms.md §E1 Regimes), when the level varies along the record; None
        when the record is one regime or the still regimes are too short to estimate.
    kurtosis : float or None
        The noise kurtosis the method read off its own residual, which its interval is
        widened for (docs/algorithms.md §E1); None: the diagnostics' is used.
    outliers : ndarray of int or None
        The outlying samples the method found, one per spike (record indices): those in
        R (not in the core) and those left out with a jump's neighbourhood; None for
        methods that do not look for them.
    stretches : tuple of (int, int) or None
        A still R's sample ranges, whence ``regimes="still"`` fits take theirs; else None.
    """

    method: str
    variance: float
    ci95: tuple[float, float]
    n_used: int
    n_total: int
    dof: float
    params: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    details: SomdDetails | None = None
    core_variance: float | None = None
    outlier_fraction: float = 0.0
    diagnostics: NoiseDiagnostics | None = None
    assumptions: dict[str, bool] = field(default_factory=dict)
    jumps: NDArray | None = field(default=None, repr=False)
    still: VarianceEstimate | None = field(default=None, repr=False)
    kurtosis: float | None = field(default=None, repr=False)
    outliers: NDArray | None = field(default=None, repr=False)
    stretches: tuple[tuple[int, int], ...] | None = field(default=None, repr=False)

    @property
    def std(self) -> float:
        """Noise standard deviation, ``sqrt(variance)``."""
        return float(np.sqrt(self.variance)) if self.variance >= 0 else float("nan")

    @property
    def verdict(self) -> str:
        """The verdict sentence: the diagnostics', or a short record's without them
        (:func:`~noisevar.diagnostics.verdict.verdict_of`); empty when there is none."""
        from noisevar.diagnostics.verdict import verdict_of

        return verdict_of(self.diagnostics, int(self.n_total), float(self.variance))

    @property
    def relative_halfwidth(self) -> float:
        """Half the CI width over the estimate (a quick precision figure)."""
        return float((self.ci95[1] - self.ci95[0]) / 2.0 / self.variance)

    def to_row(self) -> dict[str, Any]:
        """The estimate as one flat table row: the one row schema of an estimate.

        Returns
        -------
        dict
            Keyed by :data:`ROW_COLUMNS` (in that order, ``flag_<name>`` for each
            diagnostic flag after ``still_note``): numbers as floats (None when
            missing or not finite), counts as ints, flags as bools (None: not checked,
            the record too short), ``params`` and
            ``other_still_levels`` (the near-still stretches above the still R, as
            :meth:`~noisevar.diagnostics.regimes.StillLevel.to_dict`) as JSON text and
            ``notes`` joined by ``" | "`` (None when there is none).

        Notes
        -----
        :meth:`to_dict` holds the same fields nested (for JSON); every table of
        estimates is made of these rows (:func:`rows_frame`).
        """
        diag = self.diagnostics
        flags = {} if diag is None else dict(diag.flags)
        return {
            "method": self.method,
            "variance": _finite(self.variance),
            "std": _finite(self.std),
            "ci95_low": _finite(self.ci95[0]),
            "ci95_high": _finite(self.ci95[1]),
            "n_used": int(self.n_used),
            "n_total": int(self.n_total),
            "dof": _finite(self.dof),
            "core_variance": _finite(self.core_variance),
            "outlier_fraction": _finite(self.outlier_fraction),
            **_still_fields(self),
            **{FLAG_PREFIX + k: _flag(flags[k]) for k in sorted(flags)},
            "other_still_levels": _other_still(diag, self.still),
            "verdict": self.verdict or None,
            "params": json.dumps(self.params, sort_keys=True, default=_json_value),
            "notes": " | ".join(self.notes) if self.notes else None,
        }

    def to_dict(self) -> dict[str, Any]:
        """The estimate for JSON: the fields of :meth:`to_row`, nested (no arrays).

        Returns
        -------
        dict
            The numbers and counts of :meth:`to_row` under the same names, then
            ``params`` (dict), ``notes`` (list), ``assumptions`` and ``diagnostics``
            (its dict holds the verdict and the flags).
        """
        row = self.to_row()
        return {
            **{k: v for k, v in row.items() if k not in _NESTED and not k.startswith(FLAG_PREFIX)},
            "verdict": row["verdict"],
            "params": dict(self.params),
            "notes": list(self.notes),
            "assumptions": dict(self.assumptions),
            "diagnostics": None if self.diagnostics is None else self.diagnostics.to_dict(),
        }


@dataclass
class RedundantEstimate:
    """Noise variances of several real sensors of the same quantity (docs/algorithms.md §A1).

    Attributes
    ----------
    variances : ndarray, shape (k,)
        Each sensor's noise variance (three-cornered hat for k >= 3).
    ci95 : ndarray, shape (k, 2)
        Approximate 95 % intervals.
    pair_sums : ndarray, shape (k, k)
        ``1/2 E[(ΔZi - ΔZj)²] = var_i + var_j`` for each pair (eq. [8]).
    n_used : int
        Samples per sensor.
    notes : list of str
        Remarks (e.g. a negative solution clipped to zero).
    """

    variances: NDArray
    ci95: NDArray
    pair_sums: NDArray
    n_used: int
    notes: list[str] = field(default_factory=list)

    @property
    def stds(self) -> NDArray:
        """Each sensor's noise standard deviation, ``sqrt(variances)``."""
        return np.sqrt(self.variances)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        return {
            "variances": self.variances.tolist(),
            "ci95": self.ci95.tolist(),
            "pair_sums": self.pair_sums.tolist(),
            "n_used": self.n_used,
            "notes": list(self.notes),
        }


@dataclass
class VarianceEstimates:
    """Noise-variance estimates of many channels (``estimate(Z, axis=...)`` on N-D input).

    Attributes
    ----------
    method : str
        Method name.
    shape : tuple of int
        Channel shape: the input's shape without the sample axis.
    estimates : list of VarianceEstimate
        One per channel, in C order (index with ``result[i, j]`` or iterate).
    params : dict
        The parameters shared by every channel (the config form).
    """

    method: str
    shape: tuple[int, ...]
    estimates: list[VarianceEstimate]
    params: dict[str, Any] = field(default_factory=dict)

    def _array(self, values: list[Any]) -> NDArray:
        arr = np.asarray(values, dtype=float)
        return arr.reshape(self.shape + arr.shape[1:])

    @property
    def variance(self) -> NDArray:
        """Variances, shape ``shape``."""
        return self._array([e.variance for e in self.estimates])

    @property
    def std(self) -> NDArray:
        """Standard deviations, shape ``shape``."""
        return self._array([e.std for e in self.estimates])

    @property
    def ci95(self) -> NDArray:
        """95 % intervals of the variance, shape ``shape + (2,)``."""
        return self._array([e.ci95 for e in self.estimates])

    @property
    def n_used(self) -> NDArray:
        """Samples used per channel, shape ``shape``."""
        return self._array([e.n_used for e in self.estimates]).astype(int)

    def __len__(self) -> int:
        return len(self.estimates)

    def __iter__(self) -> Iterator[VarianceEstimate]:
        return iter(self.estimates)

    def __getitem__(self, index: int | tuple[int, ...]) -> VarianceEstimate:
        """The estimate of one channel (a flat index, or one index per channel axis)."""
        if isinstance(index, tuple):
            index = int(np.ravel_multi_index(index, self.shape))
        return self.estimates[index]

    def to_frame(self) -> pd.DataFrame:
        """One row per channel: ``channel``, then each estimate's :meth:`~VarianceEstimate.to_row`.

        The channel is its index (an int for one channel axis, a tuple for several).
        """
        idx = list(np.ndindex(*self.shape)) if self.shape else [()]
        rows = [
            {"channel": i if len(i) != 1 else i[0], **e.to_row()}
            for i, e in zip(idx, self.estimates, strict=True)
        ]
        return rows_frame(rows, lead=("channel",))
