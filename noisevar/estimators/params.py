"""Every estimator parameter, stated once, and the :class:`MethodSpec` of a registered method.

:func:`noisevar.estimate`, :mod:`noisevar.config` and the CLI all read these specs: the
range of ``window`` or the flag ``--gamma-ang`` is written here and nowhere else.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.filters.abg import check_h
from noisevar.filters.selection import ANGLES
from noisevar.params import ParamSpec, by_name

#: The method :func:`noisevar.estimate`, the CLI and the batch use when none is named.
DEFAULT_METHOD = "auto"
PAPER_H_SMOOTH = 1.5e-5
PAPER_WINDOW = 40
AUTO_ORDER = 3
AUTO_TRIM = 5.0


def _check_h_smooth(value: float | tuple[float, ...]) -> float | tuple[float, ...]:
    if isinstance(value, tuple):
        return tuple(check_h(h, "h_smooth") for h in value)
    return check_h(value, "h_smooth")


def _check_window(window: int) -> int:
    if window < 8:
        raise NoisevarError(f"window must be an integer of at least 8 samples, got {window}")
    return window


def _check_span(span: int) -> int:
    if span % 2 == 0:
        raise NoisevarError(f"span must be odd (a centred fit), got {span}")
    return span


#: The parameters of the built-in estimators, in the order the CLI lists them.
PARAMS: dict[str, ParamSpec] = by_name(
    [
        ParamSpec(
            "h_smooth",
            "floats",
            PAPER_H_SMOOTH,
            "smoothing h (one or several)",
            check=_check_h_smooth,
        ),
        ParamSpec(
            "h_track",
            "float",
            None,
            "tracking h (default track-ratio x h-smooth)",
            check=lambda h: check_h(h, "h_track"),
        ),
        ParamSpec("track_ratio", "float", 30.0, "h_track / h_smooth (10 to 100)", lo=1.0, hi=1e4),
        ParamSpec("window", "int", PAPER_WINDOW, "window length m (samples)", check=_check_window),
        ParamSpec("gamma_amp", "float", 0.5, "amplitude threshold, in (0, 1]", lo=0.0, hi=1.0),
        ParamSpec("gamma_ang", "float", 10.0, "angle threshold, degrees", lo=0.0, hi=90.0),
        ParamSpec("angle", "str", None, "slope convention of the angle test", choices=ANGLES),
        ParamSpec("select", "bool", True, "window selection (SOMD; --no-select skips it)"),
        ParamSpec("reference", "array", None, "the second sensor's samples", cli=False),
        ParamSpec(
            "reference_variance",
            "float",
            0.0,
            "known variance of the reference",
            lo=0.0,
            hi=math.inf,
            lo_closed=True,
        ),
        ParamSpec(
            "span",
            "int",
            None,
            "auto: fixed span (odd; default chosen per block)",
            lo=3,
            lo_closed=True,
            check=_check_span,
        ),
        ParamSpec(
            "order",
            "int",
            AUTO_ORDER,
            "auto: polynomial degree (1 to 6)",
            lo=1,
            hi=6,
            lo_closed=True,
        ),
        ParamSpec(
            "trim",
            "float",
            AUTO_TRIM,
            "auto: outlier threshold, local SDs (inf: none)",
            lo=1.0,
            finite=False,
        ),
        ParamSpec("wavelet", "str", "db4", "wavelet-mad: PyWavelets name (db4, sym8, ...)"),
        ParamSpec("drop_nonfinite", "bool", False, "drop NaN/Inf and say how many"),
    ]
)

#: Parameters of SOMD with a virtual sensor (``somd``, ``somd-paper``).
SOMD_PARAMS = (
    "h_smooth",
    "h_track",
    "track_ratio",
    "window",
    "gamma_amp",
    "gamma_ang",
    "angle",
    "select",
)

#: Accepted by every method.
COMMON_PARAMS = ("drop_nonfinite",)


@dataclass(frozen=True)
class MethodSpec:
    """A registered estimator, declared once.

    Parameters
    ----------
    name : str
        Method name, as in ``estimate(z, method=name)``.
    description : str
        One line for ``noisevar methods`` and the dashboard.
    kind : {"ours", "somd", "peer"}
        Family.
    func : callable
        ``func(z, notes, **params)``. With ``vectorised=False``, ``z`` is one validated
        signal, shape ``(n,)``, and it returns one
        :class:`~noisevar.estimators.results.VarianceEstimate`; with ``vectorised=True``,
        ``z`` has shape ``(k, n)`` (``k`` validated channels) and it returns a list of ``k``.
    params : tuple of (str or ParamSpec)
        The parameters it takes: names in :data:`PARAMS`, or new specs.
        ``drop_nonfinite`` is always accepted.
    vectorised : bool
        Whether ``func`` takes many channels at once.
    assumes : tuple of str
        What the method needs of the noise, as keys of
        :data:`noisevar.diagnostics.ASSUMPTIONS`; each estimate says which hold.
    coloured_params : dict, optional
        Parameters to use instead of the defaults when the noise is not white (``auto``:
        its shortest span, which lets the least of a coloured part in).
    moment : bool
        The estimate is a mean of squared residuals, whose interval
        :func:`~noisevar.estimators.estimate` widens for the measured kurtosis and
        correlation (docs/algorithms.md §E1).
    needs_reference : bool
        The method takes a second sensor's record as ``reference=`` (one channel at a
        time; the CLI asks for ``--reference-column``).
    chunked : callable, optional
        ``chunked(source, **params)``: the method's own path for a record read in chunks
        (larger than memory, or long enough to gain from threads); ``None`` when it has
        none. Who streams asks the spec, never the method's name.
    finish : callable, optional
        ``finish(result, record, params)``: a finishing step applied to the method's
        result on one record (``auto``: the rounding correction of a quantised record).
    slow : bool
        Seconds on a long record: a comparison of methods leaves it out of its defaults
        there (:func:`noisevar.estimators.compare.default_methods`).
    """

    name: str
    description: str
    kind: str
    func: Callable[..., Any]
    params: tuple[str | ParamSpec, ...] = ()
    vectorised: bool = False
    assumes: tuple[str, ...] = ("white", "identifiable")
    moment: bool = True
    coloured_params: Mapping[str, Any] | None = None
    needs_reference: bool = False
    chunked: Callable[..., Any] | None = None
    finish: Callable[..., Any] | None = None
    slow: bool = False

    @property
    def param_specs(self) -> dict[str, ParamSpec]:
        """Name to spec of every parameter this method takes (``drop_nonfinite`` included)."""
        specs = [p if isinstance(p, ParamSpec) else PARAMS[p] for p in self.params]
        names = {s.name for s in specs}
        specs += [PARAMS[c] for c in COMMON_PARAMS if c not in names]
        return by_name(specs)

    def validate(self, params: Mapping[str, Any]) -> dict[str, Any]:
        """Validated parameters; a name this method does not take is a :class:`NoisevarError`."""
        specs = self.param_specs
        foreign = sorted(set(params) - set(specs))
        if foreign:
            raise NoisevarError(
                f"method {self.name!r} does not take parameter(s) {', '.join(foreign)}; "
                f"its parameters: {', '.join(specs)}"
            )
        return {k: specs[k].validate(v) for k, v in params.items()}
