"""The numerics behind :mod:`noisevar.noise_model.temperature` (docs/algorithms.md §E9).

Block means, the separable least-squares fit of ``poly(T - T_ref) + A exp(-t/tau)`` with
tau profiled on a log grid (vectorised over many right-hand sides: the data and the
bootstrap replicates), BIC model choice, the moving-block bootstrap, the white level in
temperature bins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import cholesky_banded, solve_banded
from scipy.stats import chi2

from noisevar.errors import NoisevarError

#: Ratios q/s2 (random-walk increment over white variance of the block means) searched by
#: the profile likelihood; 0 is ordinary least squares on the levels.
RW_RATIOS = np.concatenate([[0.0], np.geomspace(1e-6, 1e2, 9)])


@dataclass(frozen=True, eq=False)
class Blocks:
    """Block means of one record: time centres (s), temperature, the linear regressors.

    ``linear`` holds, per axis, the block means of ``(T - T_ref)^k`` for k = 0..max order,
    then (with a known input rate) those of ``w`` and ``(T - T_ref) w``.
    """

    length: int
    rate: float
    time: NDArray
    temperature: NDArray
    powers: NDArray  # (nb, max_order + 1)

    @property
    def duration(self) -> float:
        """Seconds covered by the blocks."""
        return self.time.size * self.length / self.rate

    def exponential(self, tau: NDArray) -> NDArray:
        """Block means of ``exp(-t/tau)``, t = k/rate from the first sample; shape (taus, nb).

        Exact for the discrete samples: ``q^(jL) (1 - q^L) / (L (1 - q))``,
        ``q = exp(-1/(fs tau))``.
        """
        s = 1.0 / (self.rate * np.atleast_1d(np.asarray(tau, dtype=float)))[:, None]
        j = np.arange(self.time.size)[None, :]
        mean = np.expm1(-s * self.length) / (self.length * np.expm1(-s))
        return np.exp(-s * self.length * j) * mean


def block_means(x: NDArray, length: int) -> NDArray:
    """Means of consecutive blocks of ``length`` samples along axis 0 (the tail dropped)."""
    nb = x.shape[0] // length
    return x[: nb * length].reshape(nb, length, *x.shape[1:]).mean(axis=1)


def make_blocks(temperature: NDArray, rate: float, length: int, ref: float, order: int) -> Blocks:
    """The blocks of a record and the block means of the powers of ``T - ref``."""
    d = temperature - ref
    powers = np.column_stack([block_means(d**k, length) for k in range(order + 1)])
    nb = powers.shape[0]
    time = (np.arange(nb) * length + (length - 1) / 2.0) / rate
    return Blocks(length, rate, time, block_means(temperature, length), powers)


def tau_grid(blocks: Blocks, min_blocks: int, span: float, points: int) -> NDArray:
    """Log grid of warm-up time constants (s): ``min_blocks`` blocks to duration/``span``."""
    lo = min_blocks * blocks.length / blocks.rate
    hi = blocks.duration / span
    return np.geomspace(lo, max(hi, 2.0 * lo), points)


def rss_profile(x: NDArray, e: NDArray, y: NDArray) -> NDArray:
    """Residual sums of squares of ``y ~ [x, e_g]`` for each row ``e_g``; shape (grid, cols).

    With ``r_y``, ``r_e`` the residuals of ``y`` and ``e_g`` on ``x``:
    ``RSS = |r_y|² - (r_e · r_y)² / |r_e|²`` (one projection for the whole grid).
    """
    q = np.linalg.qr(x)[0] if x.shape[1] else np.zeros((x.shape[0], 0))
    ry = y - q @ (q.T @ y)
    re = e.T - q @ (q.T @ e.T)
    ee = np.einsum("ij,ij->j", re, re)
    cross = re.T @ ry
    with np.errstate(divide="ignore", invalid="ignore"):
        drop = np.where(ee[:, None] > 0, cross**2 / ee[:, None], 0.0)
    return np.maximum(np.einsum("ij,ij->j", ry, ry)[None, :] - drop, 0.0)


def refine(log_tau: NDArray, rss: NDArray) -> tuple[NDArray, NDArray]:
    """Each column's minimum over the grid, refined by a parabola in log tau.

    Returns the log tau of each column and whether its minimum is on the grid's edge.
    """
    i = np.argmin(rss, axis=0)
    edge = (i == 0) | (i == log_tau.size - 1)
    k = np.clip(i, 1, log_tau.size - 2)
    cols = np.arange(rss.shape[1])
    r0, r1, r2 = rss[k - 1, cols], rss[k, cols], rss[k + 1, cols]
    curv = r0 - 2.0 * r1 + r2
    step = log_tau[1] - log_tau[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.where(curv > 0, 0.5 * (r0 - r2) / curv, 0.0)
    off = np.where(edge, 0.0, np.clip(off, -1.0, 1.0))
    return log_tau[i] + off * step, edge


def lstsq(x: NDArray, y: NDArray) -> tuple[NDArray, float]:
    """Least-squares coefficients and residual sum of squares of one column ``y``."""
    coef = np.linalg.lstsq(x, y, rcond=None)[0] if x.shape[1] else np.zeros(0)
    r = y - x @ coef
    return coef, float(r @ r)


def effective_n(resid: NDArray) -> float:
    """``n (1 - rho) / (1 + rho)``: the AR(1)-equivalent count of a residual (rho >= 0)."""
    r = resid - resid.mean()
    den = float(r @ r)
    rho = float(r[1:] @ r[:-1]) / den if den > 0 else 0.0
    rho = min(max(rho, 0.0), 0.999)
    return r.size * (1.0 - rho) / (1.0 + rho)


def bic(rss: float, n: int, n_eff: float, k: int) -> float:
    """BIC of a Gaussian fit with ``k`` parameters, its likelihood counted on ``n_eff``."""
    return n_eff * math.log(max(rss, np.finfo(float).tiny) / n) + k * math.log(n_eff)


def block_length(resid: NDArray) -> int:
    """Moving-block bootstrap block: ``n^(1/3)``, or 3 correlation times if longer."""
    n = resid.size
    r = resid - resid.mean()
    den = float(r @ r)
    rho = float(r[1:] @ r[:-1]) / den if den > 0 else 0.0
    length = math.ceil(n ** (1.0 / 3.0))
    if 0.0 < rho < 1.0:
        length = max(length, math.ceil(-3.0 / math.log(rho)))
    return int(min(length, max(1, n // 5)))


def resample(fitted: NDArray, resid: NDArray, replicates: int, rng) -> NDArray:
    """Moving-block bootstrap series ``fitted + resid*``; shape (n, replicates)."""
    n = resid.size
    length = block_length(resid)
    count = -(-n // length)
    starts = rng.integers(0, n - length + 1, size=(replicates, count))
    idx = (starts[:, :, None] + np.arange(length)).reshape(replicates, -1)[:, :n]
    return fitted[:, None] + resid[idx].T


def basic_interval(value: NDArray, draws: NDArray, ci: float) -> tuple[NDArray, NDArray]:
    """The replicates' spread about their median placed on the estimate (per column)."""
    lo, med, hi = np.quantile(draws, [(1.0 - ci) / 2.0, 0.5, (1.0 + ci) / 2.0], axis=0)
    return value - (med - lo), value + (hi - med)


def white_levels(
    y: NDArray, temperature: NDArray, rate: float, edges: NDArray, ci: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """White level ``sqrt(mean(diff²) / (2 fs))`` of each column in each temperature bin.

    A first difference belongs to a bin when both its samples do. Interval: chi-square
    with ``count / 1.5`` degrees of freedom (first differences of white noise have
    ``sum rho² = 1.5``). Returns level, lo, hi (bins x columns) and the counts.
    """
    d2 = np.diff(y, axis=0) ** 2
    b = np.clip(np.searchsorted(edges, temperature, side="right") - 1, 0, edges.size - 2)
    same = b[1:] == b[:-1]
    nbins = edges.size - 1
    count = np.bincount(b[1:][same], minlength=nbins).astype(float)
    sums = np.stack(
        [np.bincount(b[1:][same], weights=col[same], minlength=nbins) for col in d2.T], axis=1
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        level = np.sqrt(sums / count[:, None] / 2.0 / rate)
        dof = np.maximum(count / 1.5, 1.0)[:, None]
        lo = level * np.sqrt(dof / chi2.ppf((1.0 + ci) / 2.0, dof))
        hi = level * np.sqrt(dof / chi2.ppf((1.0 - ci) / 2.0, dof))
    return level, lo, hi, count


@dataclass(frozen=True, eq=False)
class Fit:
    """One candidate's least-squares fit on the block means."""

    order: int
    warmup: bool
    x: NDArray  # the linear regressors used (nb, k)
    coef: NDArray  # linear coefficients, then the warm-up amplitude
    tau: float  # NaN without warm-up
    rss: float
    edge: bool  # the time constant is on the grid's edge

    @property
    def parameters(self) -> int:
        return self.x.shape[1] + 2 * self.warmup

    def fitted(self, blocks: Blocks) -> NDArray:
        if not self.warmup:
            return self.x @ self.coef
        return np.column_stack([self.x, blocks.exponential(self.tau)[0]]) @ self.coef


@dataclass(frozen=True, eq=False)
class Whitener:
    """First differences, then the inverse Cholesky factor of their covariance.

    Block means ``y = f + u + e`` with ``u`` a random walk (increments of variance ``q``)
    and ``e`` white (variance ``s2``): ``diff(y) - diff(f)`` is MA(1) with covariance
    ``tridiag(-s2, q + 2 s2, -s2)``. ``chol`` is its banded lower Cholesky factor (scaled by
    ``q + s2``). With ``q = 0`` the fit equals ordinary least squares on the levels.
    """

    chol: NDArray
    q: float
    s2: float

    @property
    def logdet(self) -> float:
        """``log det`` of the (scaled) covariance that ``chol`` factors."""
        return 2.0 * float(np.sum(np.log(self.chol[0])))

    def scaled(self, c: float) -> Whitener:
        """The same factor with ``q``, ``s2`` set from the whitened residual variance ``c``."""
        ratio = self.q / self.s2 if self.s2 > 0 else 0.0
        s2 = c / (1.0 + ratio)
        return Whitener(self.chol, ratio * s2, s2)

    @classmethod
    def make(cls, q: float, s2: float, m: int) -> Whitener:
        scale = q + s2 if q + s2 > 0 else 1.0
        ab = np.zeros((2, m))
        ab[0] = (q + 2.0 * s2) / scale if q + s2 > 0 else 2.0
        ab[1, :-1] = -s2 / scale if q + s2 > 0 else -1.0
        return cls(cholesky_banded(ab, lower=True), q, s2)

    def __call__(self, v: NDArray) -> NDArray:
        """Whitened differences of ``v`` (along axis 0)."""
        return solve_banded((1, 0), self.chol, np.diff(v, axis=0))

    def levels(self, first: float, w: NDArray) -> NDArray:
        """Levels starting at ``first`` whose whitened differences are ``w`` (m, cols)."""
        d = self.chol[0][:, None] * w
        d[1:] += self.chol[1][:-1, None] * w[:-1]
        return first + np.vstack([np.zeros((1, w.shape[1])), np.cumsum(d, axis=0)])


@dataclass(frozen=True, eq=False)
class Axis:
    """One axis's block means, its whitener and the whitened regressors.

    Fits run on whitened differences (no constant column there); the intercept is then
    the mean of the levels less the rest of the model.
    """

    y: NDArray  # block means of the data
    linear: NDArray  # powers of T - T_ref (the constant first), then the input-rate columns
    inputs: int  # input-rate columns at the end of ``linear``
    blocks: Blocks
    grid: NDArray
    exps: NDArray  # block means of exp(-t/tau) on the grid (grid, nb)
    white: Whitener
    wy: NDArray
    wlin: NDArray  # whitened non-constant columns of ``linear``
    wexps: NDArray  # (grid, m)

    @classmethod
    def make(cls, y, linear, inputs, blocks, grid, exps, white: Whitener | None = None) -> Axis:
        white = white or Whitener.make(0.0, 1.0, y.size - 1)
        return cls(
            y,
            linear,
            inputs,
            blocks,
            grid,
            exps,
            white,
            white(y),
            white(linear[:, 1:]),
            white(exps.T).T,
        )

    def with_white(self, white: Whitener) -> Axis:
        """The same axis whitened by ``white``."""
        return Axis.make(self.y, self.linear, self.inputs, self.blocks, self.grid, self.exps, white)

    def estimate_white(self, order: int, warm: bool) -> Axis:
        """The ratio ``q/s2`` maximising the Gaussian profile likelihood of the model.

        ``-2 log L = m log(RSS/m) + log det`` over :data:`RW_RATIOS` (0 included), the
        minimum refined by a parabola in log ratio.
        """
        m = self.y.size - 1

        def crit(ratio: float) -> tuple[float, Axis, float]:
            ax = self.with_white(Whitener.make(ratio, 1.0, m))
            rss = ax.fit(order, warm).rss
            return m * math.log(max(rss, np.finfo(float).tiny) / m) + ax.white.logdet, ax, rss

        runs = [crit(r) for r in RW_RATIOS]
        values = np.array([c[0] for c in runs])
        i = int(np.argmin(values))
        best = runs[i]
        if 1 < i < values.size - 1:
            logs = np.log(RW_RATIOS[i - 1 : i + 2])
            log_r, _ = refine(logs, values[i - 1 : i + 2, None])
            trial = crit(float(np.exp(log_r[0])))
            best = trial if trial[0] < best[0] else best
        _, ax, rss = best
        return Axis(**{**ax.__dict__, "white": ax.white.scaled(rss / m)})

    def cols(self, order: int) -> list[int]:
        k = self.linear.shape[1]
        return list(range(order + 1)) + list(range(k - self.inputs, k))

    def _intercept(self, cols: list[int], beta: NDArray, ys: NDArray, e: NDArray | None):
        """``a = mean(y - X beta - A e)`` for each column of ``ys`` (levels)."""
        rest = self.linear[:, cols[1:]] @ beta[: len(cols) - 1]
        if e is not None:
            rest = rest + e * beta[len(cols) - 1]
        return np.mean(ys - rest, axis=0)

    def fit(self, order: int, warm: bool) -> Fit:
        cols = self.cols(order)
        wx = self.wlin[:, [c - 1 for c in cols[1:]]]
        x = self.linear[:, cols]
        if not warm:
            beta, rss = lstsq(wx, self.wy)
            a = self._intercept(cols, beta[:, None], self.y[:, None], None)[0]
            return Fit(order, False, x, np.r_[a, beta], math.nan, rss, False)
        log_tau, edge = refine(np.log(self.grid), rss_profile(wx, self.wexps, self.wy[:, None]))
        tau = float(np.exp(log_tau[0]))
        e = self.blocks.exponential(tau)[0]
        beta, rss = lstsq(np.column_stack([wx, self.white(e)]), self.wy)
        a = self._intercept(cols, beta[:, None], self.y[:, None], e[:, None])[0]
        return Fit(order, True, x, np.r_[a, beta], tau, rss, bool(edge[0]))

    def replicates(self, fit: Fit, wys: NDArray, rng) -> tuple[NDArray, NDArray]:
        """Each whitened bootstrap series' coefficients (replicates, k) and log tau.

        The intercept of a replicate is the data's levels less the replicate's model, plus
        a draw of the mean of the level noise: variance ``s2/n + q (n+1)(2n+1)/(6n)`` (white,
        and a random walk from 0 at the first block).
        """
        cols = self.cols(fit.order)
        wx = self.wlin[:, [c - 1 for c in cols[1:]]]
        n = self.y.size
        sd = math.sqrt((self.white.s2 + self.white.q * (n + 1) * (2 * n + 1) / 6.0) / n)
        noise = sd * rng.standard_normal(wys.shape[1])
        if not fit.warmup:
            if wx.shape[1]:
                beta = np.linalg.lstsq(wx, wys, rcond=None)[0]
            else:
                beta = np.zeros((0, wys.shape[1]))
            a = self._intercept(cols, beta, self.y[:, None], None) + noise
            return np.vstack([a, beta]).T, np.full(wys.shape[1], np.nan)
        log_tau, _ = refine(np.log(self.grid), rss_profile(wx, self.wexps, wys))
        out = []
        for i, lt in enumerate(log_tau):
            e = self.blocks.exponential(math.exp(lt))[0]
            beta = lstsq(np.column_stack([wx, self.white(e)]), wys[:, i])[0]
            a = self._intercept(cols, beta[:, None], self.y[:, None], e[:, None])[0]
            out.append(np.r_[a + noise[i], beta])
        return np.array(out), log_tau


def choose(
    axis: Axis, orders: tuple[int, ...], warmups: tuple[bool, ...]
) -> tuple[Axis, list[Fit], list[float], int, list[str]]:
    """The whitener (from the largest model), every candidate fitted, their BIC, the best."""
    axis = axis.estimate_white(max(orders), max(warmups))
    fits = [axis.fit(p, w) for p in orders for w in warmups]
    big = max(fits, key=lambda f: f.parameters)
    n = axis.wy.size
    n_eff = effective_n(axis.wy - axis.white(big.fitted(axis.blocks)))
    scores = [bic(f.rss, n, n_eff, f.parameters) for f in fits]
    notes = []
    usable = [i for i, f in enumerate(fits) if not f.edge] or list(range(len(fits)))
    if len(usable) < len(fits):
        notes.append(
            "a warm-up time constant at the edge of the searched range "
            f"({axis.grid[0]:.3g}-{axis.grid[-1]:.3g} s) is not a warm-up: not offered"
        )
    return axis, fits, scores, min(usable, key=scores.__getitem__), notes


def intervals(
    axis: Axis, fit: Fit, replicates: int, ci: float, seed: int
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Moving-block bootstrap of the whitened residuals: replicates and intervals."""
    rng = np.random.default_rng(seed)
    wf = axis.white(fit.fitted(axis.blocks))
    wys = resample(wf, axis.wy - wf, replicates, rng)
    coefs, log_tau = axis.replicates(fit, wys, rng)
    lo, hi = basic_interval(fit.coef, coefs, ci)
    if fit.warmup:
        tlo, thi = basic_interval(np.array([math.log(fit.tau)]), log_tau[:, None], ci)
        lo, hi = np.append(lo, math.exp(tlo[0])), np.append(hi, math.exp(thi[0]))
    return lo, hi, coefs, log_tau


def curve(blocks: Blocks, fit: Fit, coefs: NDArray, ref: float, ci: float):
    t = np.linspace(blocks.temperature.min(), blocks.temperature.max(), 101)
    poly = np.polynomial.polynomial
    value = poly.polyval(t - ref, fit.coef[: fit.order + 1])
    draws = poly.polyval(t - ref, coefs[:, : fit.order + 1].T)
    lo, hi = basic_interval(value, draws, ci)
    return t, value, lo, hi


def slope(fit: Fit, t: NDArray, ref: float) -> NDArray:
    poly = np.polynomial.polynomial
    return poly.polyval(t - ref, poly.polyder(fit.coef[: fit.order + 1]))


def bin_edges(temperature: NDArray, bins: int) -> NDArray:
    """Equal-count temperature bins (ties merged)."""
    return np.unique(np.quantile(temperature, np.linspace(0.0, 1.0, bins + 1)))


@dataclass(frozen=True, eq=False)
class Options:
    """The checked options of one call, shared by its axes."""

    orders: tuple[int, ...]
    warmups: tuple[bool, ...]
    reference: float
    ci: float
    bootstrap: int
    seed: int
    unit: str
    bins: int
    temperature_range: tuple[float, float] | None
    temperature_rate: float | None


def check_array(name: str, a: ArrayLike, need: str) -> NDArray:
    arr = np.asarray(a, dtype=float)
    if arr.size == 0 or not np.all(np.isfinite(arr)):
        raise NoisevarError(f"{name} must be finite numbers (no NaN or inf, not empty): {need}.")
    return arr


def options(  # noqa: PLR0913
    order, warmup, reference, ci, bootstrap, seed, unit, bins, t_range, t_rate, max_order
) -> Options:
    """The checked options (``max_order``: the highest order BIC chooses from)."""
    if order is None:
        orders = tuple(range(1, max_order + 1))
    elif isinstance(order, (int, np.integer)) and 0 <= int(order) <= max_order:
        orders = (int(order),)
    else:
        raise NoisevarError(
            f"order must be None (by BIC) or an integer 0-{max_order}; got {order!r}."
        )
    choices = {None: (False, True), True: (True,), False: (False,)}
    if not (warmup is None or isinstance(warmup, bool)):
        raise NoisevarError(f"warmup must be None (by BIC), True or False; got {warmup!r}.")
    if not (0.0 < ci < 1.0) or not math.isfinite(reference) or bootstrap < 10 or bins < 1:
        raise NoisevarError(
            "ci must be in (0, 1), reference_temperature finite, bootstrap >= 10 and bins >= 1."
        )
    if t_range is not None:
        t_range = (float(t_range[0]), float(t_range[1]))
        if not (
            math.isfinite(t_range[0]) and t_range[1] > t_range[0] and math.isfinite(t_range[1])
        ):
            raise NoisevarError("temperature_range must be (low, high) in °C with high > low.")
    if t_rate is not None and not (math.isfinite(t_rate) and t_rate > 0):
        raise NoisevarError("temperature_rate must be a positive rate of change in °C/s.")
    return Options(
        orders,
        choices[warmup],
        float(reference),
        float(ci),
        int(bootstrap),
        int(seed),
        unit,
        int(bins),
        t_range,
        t_rate,
    )


def inputs(input_rate: ArrayLike | None, shape: tuple[int, int]) -> NDArray | None:
    """The known input rate per axis, shape (axes, n), or None."""
    if input_rate is None:
        return None
    w = check_array("input_rate", input_rate, "the known applied rate, one per sample")
    if w.ndim == 1 and w.size == shape[1]:
        return np.broadcast_to(w, shape)
    if w.shape == shape:
        return w
    raise NoisevarError(f"input_rate must have {shape[1]} samples (or the data's shape {shape}).")


def prepare(z: ArrayLike, temperature: ArrayLike, rate: float, axis: int):
    arr = check_array("The data", z, "rate samples (gyro, accelerometer)")
    temp = check_array("The temperature column", temperature, "°C, one value per sample")
    if not (math.isfinite(rate) and rate > 0):
        raise NoisevarError(f"The sample rate must be positive (Hz); got {rate!r}.")
    if arr.ndim not in (1, 2):
        raise NoisevarError(f"z must be 1-D or 2-D (time x axes); it has shape {arr.shape}.")
    cols = arr[None, :] if arr.ndim == 1 else np.moveaxis(arr, axis, -1)
    if temp.ndim != 1 or temp.size != cols.shape[1]:
        raise NoisevarError(
            f"The temperature column needs one value per sample ({cols.shape[1]}); "
            f"it has shape {temp.shape}."
        )
    return arr.ndim == 1, cols, temp
