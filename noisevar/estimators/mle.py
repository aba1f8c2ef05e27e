"""State-space maximum-likelihood peers (docs/algorithms.md §F3): local level and trend."""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate
from noisevar.estimators.spec import MethodSpec

#: Noise variance, as a fraction of the variance of the differences, below which the fit
#: sits at the boundary 0 (statsmodels' optimiser stops near 1e-12 there).
BOUNDARY = 1e-8
#: Smallest starting variance, as a fraction of the variance of the differences
#: (:func:`level_start`: a moment that comes out negative starts here, inside the box).
START_FLOOR = 1e-3


def level_start(y: NDArray) -> NDArray | None:
    """The local level fit's starting variances (irregular, level), from the differences.

    Parameters
    ----------
    y : ndarray
        The standardised signal.

    Returns
    -------
    ndarray or None
        ``[-g1, g0 + 2 g1]`` from the differences' autocovariances ``g0, g1`` (F3.2), each
        at least :data:`START_FLOOR` ``g0``; None (statsmodels' own start) for fewer than
        8 samples or differences of no variance.

    Notes
    -----
    The start of the fit, not its answer: the local level likelihood has one maximum on
    the records measured (docs/algorithms.md §F3), reached in about half the evaluations.
    The local linear trend keeps statsmodels' start: its likelihood has two maxima on the
    fast-slow records, and a moment start reaches the other one on 8 of 20.
    """
    if y.size < 8:
        return None
    d = np.diff(y)
    g0, g1 = float(d @ d) / d.size, float(d[1:] @ d[:-1]) / d.size
    if not (np.isfinite(g0) and np.isfinite(g1) and g0 > 0):
        return None
    eps = max(-g1, START_FLOOR * g0)
    return np.array([eps, max(g0 - 2.0 * eps, START_FLOOR * g0)])


def mle_estimate(z: NDArray, trend: bool, notes: list[str]) -> VarianceEstimate:
    """Irregular variance of a statsmodels ``UnobservedComponents`` model, by ML.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    trend : bool
        Local linear trend (True) or local level (False).
    notes : list of str
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
        CI from the Hessian-based standard error, on the log-variance scale.
    """
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    scale = float(np.std(np.diff(z))) or 1.0
    y = (z - z.mean()) / scale
    level = "local linear trend" if trend else "local level"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            model = UnobservedComponents(y, level=level)
            start = None if trend else level_start(y)
            res = model.fit(start_params=start, disp=False, maxiter=200)
        except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            first = (str(exc).splitlines() or [type(exc).__name__])[0][:200]
            raise NoisevarError(
                f"the {level} likelihood fit failed on this record ({first}): try another method"
            ) from None
    retvals = getattr(res, "mle_retvals", None) or {}
    if not retvals.get("converged", True):
        notes.append(
            "the likelihood optimiser stopped without converging "
            f"(after {retvals.get('iterations', '?')} iterations): this estimate may be far off"
        )
    names = list(model.param_names)
    idx = names.index("sigma2.irregular")
    var_scaled = float(res.params[idx])
    # y has unit difference variance: a noise variance this far below it is the boundary 0
    if not var_scaled > BOUNDARY:
        raise NoisevarError(
            f"the {level} likelihood puts the noise variance at its boundary 0 "
            f"({var_scaled:.3g} of the differences' variance): the model does not identify "
            "the noise on this record; use another method (rice, hkt3, auto)"
        )
    var = var_scaled * scale**2
    try:
        se = float(res.bse[idx]) * scale**2
    except Exception:  # noqa: BLE001 - statsmodels may fail to invert the Hessian
        se = float("nan")
    if np.isfinite(se) and var > 0:
        rel = se / var
        # log-normal interval; a fit that barely identifies the noise (rel of hundreds)
        # gives (0, inf) instead of an overflow warning
        with np.errstate(over="ignore"):
            ci = (var * float(np.exp(-1.96 * rel)), var * float(np.exp(1.96 * rel)))
        dof = 2.0 / rel**2
    else:
        ci, dof = (float("nan"), float("nan")), float("nan")
    method = "mle-trend" if trend else "mle-level"
    return VarianceEstimate(method, var, ci, z.size, z.size, dof, {}, notes)


def _mle_level(z: NDArray, notes: list[str]) -> VarianceEstimate:
    return mle_estimate(z, False, notes)


def _mle_trend(z: NDArray, notes: list[str]) -> VarianceEstimate:
    return mle_estimate(z, True, notes)


_MLE_ASSUMES = ("white", "identifiable", "gaussian")
MLE_LEVEL = MethodSpec(
    "mle-level",
    "state-space ML, local level (statsmodels)",
    "peer",
    _mle_level,
    assumes=_MLE_ASSUMES,
    moment=False,
    slow=True,
)
MLE_TREND = MethodSpec(
    "mle-trend",
    "state-space ML, local linear trend (statsmodels)",
    "peer",
    _mle_trend,
    assumes=_MLE_ASSUMES,
    moment=False,
    slow=True,
)
