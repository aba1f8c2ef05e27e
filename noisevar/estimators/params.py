"""Every estimator parameter, stated once.

:func:`noisevar.estimate`, :mod:`noisevar.config` and the CLI all read these specs: the
range of ``window`` or the flag ``--gamma-ang`` is written here and nowhere else. A
method's declaration is a :class:`~noisevar.estimators.spec.MethodSpec`.
"""

from __future__ import annotations

import math

from noisevar.errors import NoisevarError
from noisevar.filters.abg import check_h
from noisevar.filters.selection import ANGLES
from noisevar.params import ParamSpec, by_name

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
