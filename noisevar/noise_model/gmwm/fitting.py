"""Model choice and the public :func:`fit_imu_model` (docs/algorithms.md §E10)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from noisevar._arrays import check_exact_ints
from noisevar.errors import NoisevarError
from noisevar.estimators import check_rate, scale_back
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm.model import (
    HORIZON,
    MAX_GM,
    ONE_SIGMA,
    ORDER,
    FilterBias,
    ImuModel,
    ModelRow,
    Parameter,
    labels,
    name_of,
    parse_model,
)
from noisevar.noise_model.gmwm.processes import PROCESSES
from noisevar.noise_model.gmwm.scaling import bias_in_units, checked, internal_in_units
from noisevar.noise_model.gmwm.wavelet import dyadic_scales, haar_wv, robust_inflation

#: ``models=AUTO``: search the model (:func:`search`).
AUTO = "auto"
#: The model every automatic search starts from.
BASE = ("WN",)
#: Processes an automatic search may add (GM up to :data:`MAX_GM` times).
ADDABLE = ("QN", "FL", "GM", "RW", "DR")
#: Penalty per parameter of the wavelet variance information criterion (Guerrier et al.'s
#: WVIC in its asymptotic form: the objective's optimism is 2 per parameter).
PENALTY = 2.0
#: Criteria a model may be chosen by: the objective plus, per parameter, ``2 log log n``
#: (Hannan-Quinn's, consistent: the default), ``log n`` (BIC's) or 2 (WVIC), ``n`` the
#: samples.
CRITERIA = ("hq", "bic", "wvic")
DEFAULT_CRITERION = "hq"


def _merge(parts: list[tuple[str, NDArray]]) -> tuple[tuple[str, ...], NDArray]:
    """Processes sorted into :data:`ORDER` (GMs by correlation time), flattened."""
    parts = sorted(parts, key=lambda kp: (ORDER.index(kp[0]), kp[1][-1]))
    return tuple(k for k, _ in parts), np.concatenate([p for _, p in parts])


def _fresh_starts(keys: tuple[str, ...], wv: est.WaveletVariance) -> list[NDArray]:
    others = [(k, PROCESSES[k].start(wv.tau, wv.nu)[0]) for k in keys if k != "GM"]
    gm = PROCESSES["GM"].start(wv.tau, wv.nu)
    starts = []
    for combo in itertools.combinations(gm, keys.count("GM")):
        starts.append(_merge(others + [("GM", g) for g in combo])[1])
    return starts


def _grown(sol: est.Solution, new: str, wv: est.WaveletVariance):
    """The model ``sol`` plus the process ``new``, with warm starts."""
    prev = list(zip(sol.keys, est.split(sol.keys, np.exp(sol.log_params)), strict=True))
    candidates = PROCESSES[new].start(wv.tau, wv.nu)
    if new == "GM":
        # first, a GM that fills the current model's largest shortfall, where it peaks
        short = wv.nu - est.model_wv(sol.keys, np.exp(sol.log_params), wv.tau)
        j = int(np.argmax(short / wv.nu))
        if short[j] > 0:
            tc = wv.tau[j] / 2.0
            peak = float(PROCESSES["GM"].wv(np.array([1.0, tc]), wv.tau[j : j + 1])[0])
            candidates = [np.array([short[j] / peak, tc]), *candidates]
    starts = [_merge(prev + [(new, s)]) for s in candidates]
    return starts[0][0], [s for _, s in starts]


def _addable(keys: tuple[str, ...], n_scales: int) -> list[str]:
    out = []
    for k in ADDABLE:
        limit = MAX_GM if k == "GM" else 1
        size = len(PROCESSES[k].params)
        if keys.count(k) < limit and sum(est.sizes(keys)) + size < n_scales:
            out.append(k)
    return out


def penalty(criterion: str, n: float) -> float:
    """The criterion's price of one parameter: ``2 log log n`` (HQ), ``log n`` (BIC) or
    :data:`PENALTY` (WVIC), ``n`` the samples."""
    if criterion not in CRITERIA:
        raise NoisevarError(f"criterion must be one of {', '.join(CRITERIA)}; got {criterion!r}.")
    return {
        "hq": 2.0 * math.log(math.log(n)),
        "bic": math.log(n),
        "wvic": PENALTY,
    }[criterion]


def wvic(sol: est.Solution) -> float:
    """Wavelet variance information criterion: objective plus 2 per parameter."""
    return sol.objective + PENALTY * sol.n_params


def bic(sol: est.Solution, n: float) -> float:
    """The objective plus ``log(n)`` per parameter (``n`` samples)."""
    return sol.objective + penalty("bic", n) * sol.n_params


def hq(sol: est.Solution, n: float) -> float:
    """The objective plus ``2 log(log(n))`` per parameter (``n`` samples)."""
    return sol.objective + penalty("hq", n) * sol.n_params


def _score(criterion: str, n: float):  # noqa: ANN202
    price = penalty(criterion, n)
    return lambda s: s.objective + price * s.n_params


class Fits:
    """The fits of one search, each model fitted once: a model the search meets again
    (dropped, swapped or added back) keeps its first fit."""

    def __init__(self, wv: est.WaveletVariance) -> None:
        self.wv = wv
        self.done: dict[tuple[str, ...], est.Solution] = {}

    def __call__(self, keys: tuple[str, ...], starts: list[NDArray]) -> est.Solution:
        if keys not in self.done:
            self.done[keys] = est.fit(keys, starts, self.wv)
        return self.done[keys]


def _without(sol: est.Solution, drop: int, fit: Fits) -> est.Solution:
    parts = list(zip(sol.keys, est.split(sol.keys, np.exp(sol.log_params)), strict=True))
    keys, start = _merge(parts[:drop] + parts[drop + 1 :])
    return fit(keys, [start])


#: Processes the search adds only where they dominate some scale (:func:`identified`):
#: the power laws, whose wavelet variance is a line of fixed slope on log-log axes. A GM
#: is located by its correlation time and left to the criterion alone.
POWER_LAWS = ("QN", "WN", "FL", "RW", "DR")


def identified(sol: est.Solution, wv: est.WaveletVariance, key: str) -> bool:
    """Whether each process ``key`` of ``sol`` has a scale where its wavelet variance
    exceeds the sum of the other processes' there (always true for a GM).

    Notes
    -----
    A power law (:data:`POWER_LAWS`) under the sum of the others at every scale only
    bends that sum where the others cross (a flicker between a white noise and a random
    walk, a quantisation under the white noise): the data do not identify it. The
    search (:func:`search`) adds a process only where it is identified.
    """
    if key not in POWER_LAWS:
        return True
    parts = zip(sol.keys, est.split(sol.keys, np.exp(sol.log_params)), strict=True)
    comps = np.array([PROCESSES[k].wv(p, wv.tau) for k, p in parts])
    total = comps.sum(axis=0)
    own = [c for k, c in zip(sol.keys, comps, strict=True) if k == key]
    return all(np.any(c > total - c) for c in own)


def _better(trials: list, current: est.Solution, score, wv):  # noqa: ANN001, ANN202
    """The trials ``(added process, solution)`` that lower the criterion and whose added
    process is identified (:func:`identified`)."""
    return [t for new, t in trials if score(t) < score(current) and identified(t, wv, new)]


def _forward(current: est.Solution, fit: Fits, score, tried: list):  # noqa: ANN001, ANN202
    wv = fit.wv
    while True:
        trials = []
        for new in _addable(current.keys, wv.tau.size):
            keys, starts = _grown(current, new, wv)
            trials.append((new, fit(keys, starts)))
        tried += [t for _, t in trials]
        better = _better(trials, current, score, wv)
        if not better:
            return current
        current = min(better, key=score)


def _backward(current: est.Solution, fit: Fits, score, tried: list):  # noqa: ANN001, ANN202
    while len(current.keys) > 1:
        trials = [_without(current, i, fit) for i, k in enumerate(current.keys) if k != "WN"]
        tried += trials
        better = [t for t in trials if score(t) < score(current)]
        if not better:
            return current
        current = min(better, key=score)
    return current


def search(
    wv: est.WaveletVariance, criterion: str = DEFAULT_CRITERION
) -> tuple[est.Solution, list[est.Solution]]:
    """Stepwise search from :data:`BASE`: add the process that lowers the criterion most
    while one does, then drop the processes whose removal lowers it (a drift taken
    early for a random walk), swap a flicker or drift for a GM or random walk
    (:data:`SWAPS`) when that lowers it, and add again, until nothing helps. A power law
    is added (or swapped in) only where it dominates some scale (:func:`identified`).
    Each model is fitted once (:class:`Fits`)."""
    score = _score(criterion, wv.n_samples)
    fit = Fits(wv)
    current = fit(BASE, _fresh_starts(BASE, wv))
    tried = [current]
    for _ in range(3):
        grown = _forward(current, fit, score, tried)
        current = _swapped(_backward(grown, fit, score, tried), fit, score, tried)
        if current is grown:
            break
    return current, tried


#: Swaps the search tries: a flicker or a drift taken for a GM or a random walk.
SWAPS = {"FL": ("GM", "RW"), "DR": ("GM", "RW")}


def _swapped(current: est.Solution, fit: Fits, score, tried: list):  # noqa: ANN001, ANN202
    trials, wv = [], fit.wv
    for i, k in enumerate(current.keys):
        for new in SWAPS.get(k, ()):
            rest = _without(current, i, fit)
            if new in _addable(rest.keys, wv.tau.size):
                keys, starts = _grown(rest, new, wv)
                trials.append((new, fit(keys, starts)))
    tried += [t for _, t in trials]
    better = _better(trials, current, score, wv)
    return min(better, key=score) if better else current


def choose(
    wv: est.WaveletVariance, models: str | Sequence[str], criterion: str = DEFAULT_CRITERION
) -> tuple[est.Solution, list[est.Solution]]:
    """The chosen solution and every solution fitted (``models``: "auto" or a list)."""
    score = _score(criterion, wv.n_samples)
    if isinstance(models, str) and models == AUTO:
        return search(wv, criterion)
    specs = [models] if isinstance(models, str) else list(models)
    if not specs:
        raise NoisevarError("models must be 'auto' or a non-empty list of models.")
    fits = []
    for spec in specs:
        keys = parse_model(spec)
        if sum(est.sizes(keys)) >= wv.tau.size:
            raise NoisevarError(
                f"The model {spec!r} has more parameters than the {wv.tau.size} scales."
            )
        fits.append(est.fit(keys, _fresh_starts(keys, wv), wv))
    return min(fits, key=score), fits


def _parameters(sol: est.Solution, rate: float, unit: str, ci: float, e=0) -> list[Parameter]:
    """The parameters and intervals in the record's units (fitted on the record x 2**e)."""
    z = stats.norm.ppf(0.5 + ci / 2.0)
    se = np.sqrt(np.clip(np.diag(sol.log_cov), 0.0, 50.0**2))
    out = []
    logs = zip(
        est.split(sol.keys, sol.log_params),
        est.split(sol.keys, se),
        strict=True,
    )
    for label, key, (lp, s) in zip(labels(sol.keys), sol.keys, logs, strict=True):
        proc = PROCESSES[key]
        mid, lo, hi = (proc.convert(np.exp(lp + d * s), rate) for d in (0.0, -z, z))
        for i, (pub, u) in enumerate(zip(proc.public, proc.units, strict=True)):
            name = pub if key != "GM" else f"{label}.{pub}"
            mid_i, lo_i, hi_i = (scale_back(v[i], -e * ("{u}" in u), name) for v in (mid, lo, hi))
            out.append(Parameter(name, label, mid_i, (lo_i, hi_i), u.format(u=unit)))
    return out


#: The bias processes: the ones a filter holding one random-walk bias must cover.
BIAS = ("RW", "GM", "FL", "DR")


def _bias_avar(keys: tuple[str, ...], log_p: NDArray, tau: NDArray) -> float:
    """The bias processes' Allan variance at ``tau`` (samples; 2 x Haar at 2 tau)."""
    parts = zip(keys, est.split(keys, np.exp(log_p)), strict=True)
    return sum(2.0 * float(PROCESSES[k].wv(q, tau)[0]) for k, q in parts if k in BIAS)


def _k_eq_interval(
    keys: tuple[str, ...], log_p: NDArray, log_cov: NDArray, tau: NDArray, z: float
) -> tuple[float, float]:
    """K_eq's interval by the delta method on ``log K_eq = log(3 AVAR_bias(T) / T) / 2``,
    the gradient in the log-parameters by central differences."""
    avar = _bias_avar(keys, log_p, tau)
    if not avar > 0:
        return 0.0, 0.0
    grad = np.zeros(log_p.size)
    for j in range(log_p.size):
        d = np.zeros(log_p.size)
        d[j] = 1e-5
        up, down = _bias_avar(keys, log_p + d, tau), _bias_avar(keys, log_p - d, tau)
        grad[j] = 0.5 * (math.log(up) - math.log(down)) / 2e-5
    cov = np.clip(log_cov, -(50.0**2), 50.0**2)
    se = math.sqrt(max(float(grad @ cov @ grad), 0.0))
    return math.exp(-z * se), math.exp(z * se)


def filter_bias(
    keys: tuple[str, ...],
    p: NDArray,
    rate: float,
    horizon: float,
    log_cov: NDArray | None = None,
    ci: float = ONE_SIGMA,
) -> FilterBias:
    """The random walk of the same Allan variance as the bias processes at ``horizon``,
    with its interval at level ``ci`` from the fit's ``log_cov`` (the delta method;
    ``(K_eq, K_eq)`` without one)."""
    tau = np.array([2.0 * horizon * rate])
    log_p = np.log(np.asarray(p, dtype=float))
    k_eq = math.sqrt(3.0 * _bias_avar(keys, log_p, tau) / horizon)
    lo, hi = (1.0, 1.0)
    if log_cov is not None:
        lo, hi = _k_eq_interval(keys, log_p, log_cov, tau, stats.norm.ppf(0.5 + ci / 2.0))
    parts = zip(keys, est.split(keys, p), strict=True)
    gm = sorted(((math.sqrt(q[0]), q[1] / rate) for k, q in parts if k == "GM"), key=lambda g: g[1])
    note = (
        f"K_eq = sqrt(3 AVAR_bias(T) / T) at T = {horizon:g} s: the random walk with the "
        "same Allan variance as the bias processes (RW, GM, flicker, drift) at T. A GM "
        "(sigma, tau_c) alone gives sigma sqrt(2 / tau_c) for T << tau_c; the random walk "
        "covers the GM's bias change for horizons from T on and overstates it past tau_c."
    )
    return FilterBias(
        k_eq,
        (k_eq * lo, k_eq * hi),
        float(horizon),
        tuple(g[0] for g in gm),
        tuple(g[1] for g in gm),
        note,
    )


#: Processes that may hold a bias in a random walk's place (:func:`random_walk_note`).
RW_RIVALS = ("GM", "FL")


def random_walk_note(
    sol: est.Solution,
    tried: list[est.Solution],
    criterion: str,
    n: float,
    rate: float,
    unit: str,
    ci: float,
    e: int = 0,
) -> str | None:
    """A note when the chosen model holds a GM or flicker but no random walk, and a model
    with a random walk is within one parameter's price of it by the criterion.

    Returns
    -------
    str or None
        The rival model (the best by ``criterion`` among those ``tried`` with a random
        walk), its margin, and its K with the interval at level ``ci``; None otherwise.

    Notes
    -----
    Such a GM or flicker differs from the random walk only at the longest scales, where
    each wavelet variance has a few degrees of freedom; a margin under the price of one
    parameter (:func:`penalty`) is one the criterion itself does not count as evidence.
    The note gives K and its interval under the rival, so K = 0 never stands alone.
    """
    if "RW" in sol.keys or not set(RW_RIVALS) & set(sol.keys):
        return None
    score = _score(criterion, n)
    rivals = [t for t in tried if "RW" in t.keys]
    if not rivals:
        return None
    rival = min(rivals, key=score)
    margin, price = score(rival) - score(sol), penalty(criterion, n)
    if margin >= price:
        return None
    k = next(p for p in _parameters(rival, rate, unit, ci, e) if p.name == "K")
    held = "/".join(x for x in RW_RIVALS if x in sol.keys)
    return (
        f"{name_of(rival.keys)} is within {margin:.2g} of the chosen {name_of(sol.keys)} by "
        f"{criterion.upper()} (one parameter costs {price:.2g}): the data barely tell its "
        f"{held} from a random walk, which differ only at the longest scales; under "
        f"{name_of(rival.keys)}, K = {k.value:.4g} {k.unit} "
        f"[{k.interval[0]:.4g}, {k.interval[1]:.4g}] ({ci:.1%})"
    )


#: Level of the chi-square test past which the chosen model misfits (:func:`misfits`).
MISFIT_LEVEL = 0.999


def misfits(objective: float, n_scales: int, n_params: int) -> bool:
    """Whether a GMWM objective is past the chi-square's :data:`MISFIT_LEVEL` quantile on
    ``n_scales - n_params`` degrees of freedom (at least 1): a process is missing."""
    return bool(objective > stats.chi2.ppf(MISFIT_LEVEL, max(1, n_scales - n_params)))


def unexplained(fit: ImuModel) -> bool:
    """Whether a fit leaves the data unexplained: its model misfits (:func:`misfits`) or
    its N is at its bound (:func:`white_at_bound`)."""
    chosen = next(r for r in fit.table if r.chosen)
    at_bound = "WN" in fit.keys and fit.value("N") == 0.0
    return at_bound or misfits(chosen.objective, fit.scales.size, chosen.n_params)


#: Widest half-width of the wavelet variance's interval, in log units (``exp`` of it
#: stays finite; the parameters' standard errors are clipped alike in :func:`_parameters`).
MAX_LOG_HALF_WIDTH = 50.0


def wv_band(nu: NDArray, half: NDArray) -> tuple[NDArray, NDArray]:
    """``nu exp(-half)`` to ``nu exp(half)``, ``half`` clipped to :data:`MAX_LOG_HALF_WIDTH`.

    A model that misfits badly (motion) can give a scale a relative standard error whose
    ``exp`` overflows: the band is then as wide as finite numbers keep it, never inf.
    """
    h = np.minimum(half, MAX_LOG_HALF_WIDTH)
    return nu * np.exp(-h), nu * np.exp(h)


#: N under this fraction of the white level is at its lower bound (0): the white noise
#: holds under a millionth of the shortest scale's wavelet variance.
AT_BOUND = 1e-3


def white_level(wv: est.WaveletVariance, rate: float) -> float:
    """The N that alone makes the wavelet variance of the shortest scale (unit/√Hz).

    Notes
    -----
    With the Haar wavelet variance at 2 samples (``mean(diff²) / 4``) this is
    ``std(diff) / sqrt(2 fs)``, :func:`noisevar.noise_model.inertial.white_level`: the
    white level sigma/sqrt(fs), all of the shortest scale's variance taken as white.
    """
    wn = PROCESSES["WN"]
    unit_wv = float(wn.wv(np.ones(1), wv.tau[:1])[0])
    return float(wn.convert(np.array([wv.nu[0] / unit_wv]), rate)[0])


def white_at_bound(
    params: list[Parameter], wv: est.WaveletVariance, rate: float, unit: str, e: int = 0
) -> tuple[list[Parameter], list[str]]:
    """N at its lower bound said so: 0, its interval up to the white level, and a note.

    Returns
    -------
    list of Parameter, list of str
        ``params`` with N replaced when it is under :data:`AT_BOUND` x the white level
        (:func:`white_level`), and the note; else ``params`` and no note.

    Notes
    -----
    When other processes already exceed the shortest scale's wavelet variance (motion's
    smooth signal, a random walk fitted to it), the fit runs white noise down to its
    bound at 0. The delta-method interval of a parameter at its bound is not an
    interval (it has zero width); the data bound N only from above, by the white level.
    """
    white = scale_back(white_level(wv, rate), -e, "white level")  # as params: ``wv`` of z 2**e
    out, notes = [], []
    for p in params:
        if p.name == "N" and p.value < AT_BOUND * white:
            notes.append(
                f"N is at its lower bound (fitted {p.value:.3g}): the other processes hold "
                f"the shortest scale, so the data do not tell N from 0; its interval reaches "
                f"the white level {white:.4g} {p.unit}, as if all of the shortest scale's "
                "wavelet variance were white"
            )
            p = Parameter(p.name, p.process, 0.0, (0.0, white), p.unit)
        out.append(p)
    return out, notes


def build(
    sol: est.Solution,
    tried: list[est.Solution],
    wv: est.WaveletVariance,
    rate: float,
    unit: str,
    ci: float,
    robust: bool,
    horizon: float,
    criterion: str = DEFAULT_CRITERION,
    e: int = 0,
) -> ImuModel:
    """One axis's result from its chosen solution and all fitted (``wv``: of z x 2**e)."""
    sol = est.order_gm(sol)
    z = stats.norm.ppf(0.5 + ci / 2.0)
    rel = np.sqrt(np.diag(sol.cov)) / wv.nu
    rows, seen, n = [], set(), wv.n_samples
    for t in sorted(tried, key=lambda s: (s.n_params, wvic(s))):
        name = name_of(t.keys)
        if name in seen:
            continue
        seen.add(name)
        row = ModelRow(
            name, t.n_params, t.objective, wvic(t), hq(t, n), bic(t, n), t.keys == sol.keys
        )
        rows.append(row)
    p = np.exp(sol.log_params)
    notes = []
    if misfits(sol.objective, wv.tau.size, sol.n_params):
        notes.append(
            f"the chosen model {name_of(sol.keys)} misfits the wavelet variance "
            f"(objective {sol.objective:.3g} on {wv.tau.size} scales): a process is missing"
        )
    rw_note = random_walk_note(sol, tried, criterion, n, rate, unit, ci, e)
    if rw_note:
        notes.append(rw_note)
    params, n_note = white_at_bound(_parameters(sol, rate, unit, ci, e), wv, rate, unit, e)
    notes += n_note
    return ImuModel(
        name_of(sol.keys),
        tuple(params),
        float(rate),
        unit,
        float(ci),
        robust,
        wv.tau / rate,
        np.array(scale_back(wv.nu, -2 * e, "wavelet variance"), copy=True),
        tuple(scale_back(b, -2 * e, "wavelet variance") for b in wv_band(wv.nu, z * rel)),
        tuple(rows),
        bias_in_units(filter_bias(sol.keys, p, rate, horizon, sol.log_cov, ci), e),
        sol.keys,
        internal_in_units(sol.keys, p, e),
        tuple(notes),
    )


def _check(rate: float, ci: float, horizon: float) -> None:
    check_rate(rate)  # the range the other noise models take (RATE_RANGE)
    if not 0.0 < ci < 1.0:
        raise NoisevarError(f"ci must be in (0, 1); got {ci!r}.")
    if not (math.isfinite(horizon) and horizon > 0):
        raise NoisevarError(f"horizon must be a positive number of seconds; got {horizon!r}.")


def as_rows(x: ArrayLike, axis: int) -> NDArray:
    check_exact_ints(x, "x")
    arr = np.asarray(x, dtype=float)
    if arr.ndim not in (1, 2):
        raise NoisevarError(f"x must be 1-D or 2-D (time x axes); it has shape {arr.shape}.")
    rows = arr[None, :] if arr.ndim == 1 else np.moveaxis(arr, axis, -1)
    if not np.all(np.isfinite(rows)):
        raise NoisevarError("x holds NaN or inf: cut those samples out first.")
    if rows.shape[-1] < 8:
        raise NoisevarError(f"The record is too short for a noise model: {rows.shape[-1]} samples.")
    return rows


def wavelet_variances(rows: NDArray, robust: bool) -> list[est.WaveletVariance]:
    """The (robust) Haar wavelet variance of each row, vectorised over the rows."""
    tau = dyadic_scales(rows.shape[-1])
    nu, m = haar_wv(rows, tau, robust=robust)
    inflation = robust_inflation() if robust else 1.0
    if np.any(nu <= 0):
        raise NoisevarError("A column is constant at some scale: there is no noise to model.")
    return [est.WaveletVariance(tau, v, m, inflation) for v in nu]


def pooled(wvs: list[est.WaveletVariance]) -> est.WaveletVariance:
    """One wavelet variance of several records: each scale's average weighted by its
    coefficients, over the records long enough for it."""
    longest = max(wvs, key=lambda w: w.tau.size)
    nu_sum, m_sum = np.zeros(longest.tau.size), np.zeros(longest.tau.size)
    for w in wvs:
        k = w.tau.size
        nu_sum[:k] += w.nu * w.m
        m_sum[:k] += w.m
    return est.WaveletVariance(longest.tau, nu_sum / m_sum, m_sum, longest.inflation)


def fit_wv(
    wv: est.WaveletVariance,
    rate: float,
    *,
    models: str | Sequence[str] = "auto",
    robust: bool = False,
    unit: str = "u",
    ci: float = ONE_SIGMA,
    criterion: str = DEFAULT_CRITERION,
    horizon: float = HORIZON,
    e: int = 0,
) -> ImuModel:
    """Fit and choose a model on the wavelet variance of z x 2**e, in the units of z."""
    _check(rate, ci, horizon)
    if horizon * rate < 1.0:
        raise NoisevarError(f"horizon must be at least one sample (1/rate); got {horizon!r} s.")
    if wv.tau.size < 3:
        raise NoisevarError(
            f"The record is too short: {wv.tau.size} wavelet scales (a model needs 3)."
        )
    sol, tried = choose(wv, models, criterion)
    return checked(build(sol, tried, wv, rate, unit, ci, robust, horizon, criterion, e))
