"""Seeded measurement noise of the kinds real sensors have: heavy tails, colour, steps, gaps.

:func:`noise` draws one kind of :data:`KINDS` and returns it with the variance an estimate
should be compared with (:attr:`Noise.variance`). :func:`quantise` and :func:`remove_blocks`
turn any record into a quantised or a gapped one. Used by ``benchmarks/real_noise.py``, the
tests and the dashboard's demonstration records.

Kinds, their parameters and the variance each is compared with (``std`` is 1 by default):

``gauss`` (std)
    White Gaussian noise; variance ``std²``.
``student_t`` (dof, std)
    Student-t with ``dof > 2`` degrees of freedom, scaled to variance ``std²``.
``laplace`` (std)
    Laplace (double exponential), scaled to variance ``std²``.
``contaminated`` (fraction, factor, std)
    Gaussian ``std``, except a share ``fraction`` of samples drawn with ``factor * std``.
    Variance: the total, ``std² (1 - fraction + fraction factor²)``; ``core_variance`` is
    ``std²``, the bulk's.
``ar1`` (phi, std)
    Stationary AR(1), ``x_k = phi x_(k-1) + e_k``, with marginal variance ``std²`` (the
    total variance a Kalman filter would see at any one sample).
``flicker`` (qd)
    Flicker (1/f) noise by Kasdin and Walter's method (``allantools.noise_kasdin``, power
    law exponent -1) driven by white noise of variance ``qd``. It is not stationary: its
    variance grows like the logarithm of the time since its start. Variance: the expected
    mean square over the record.
``white+flicker`` (std, ratio)
    White Gaussian ``std`` plus flicker driven by ``qd = ratio std²``. Variance: ``std²``,
    the white part (the flicker is a slow process a filter should model as a state).
``white+rw`` (std, ratio)
    White Gaussian ``std`` plus a random walk of step variance ``ratio std²`` (the record is
    dominated by the walk). Variance: ``std²``, the white part.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from allantools.noise_kasdin import Noise as KasdinNoise
from numpy.typing import ArrayLike, NDArray
from scipy import signal, special

from noisevar.errors import NoisevarError

#: What a generator returns: samples, the variance to compare with, the core variance.
Draw = tuple[NDArray, float, float | None]


@dataclass(frozen=True)
class Noise:
    """One draw of :func:`noise`.

    Attributes
    ----------
    kind : str
        A key of :data:`KINDS`.
    values : ndarray, shape (n,) or (runs, n)
        The noise samples (add a clean signal to make a record).
    variance : float
        The variance an estimate of this noise should be compared with (module docstring).
    core_variance : float or None
        The bulk's variance where it differs from ``variance`` (``contaminated``), else None.
    params : dict
        The kind's parameters, defaults filled in.
    """

    kind: str
    values: NDArray
    variance: float
    core_variance: float | None = None
    params: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (no samples)."""
        return {
            "kind": self.kind,
            "shape": list(self.values.shape),
            "variance": float(self.variance),
            "core_variance": None if self.core_variance is None else float(self.core_variance),
            "params": dict(self.params),
        }


def _gauss(shape: tuple[int, ...], rng: np.random.Generator, std: float = 1.0) -> Draw:
    return rng.standard_normal(shape) * std, std**2, None


def _student_t(
    shape: tuple[int, ...], rng: np.random.Generator, dof: float = 5.0, std: float = 1.0
) -> Draw:
    if not dof > 2:
        raise NoisevarError(f"dof must be above 2 for a finite variance, got {dof}")
    # var(t_ν) = ν / (ν - 2)
    return rng.standard_t(dof, shape) * std * np.sqrt((dof - 2.0) / dof), std**2, None


def _laplace(shape: tuple[int, ...], rng: np.random.Generator, std: float = 1.0) -> Draw:
    # var = 2 b²
    return rng.laplace(0.0, std / np.sqrt(2.0), shape), std**2, None


def _contaminated(
    shape: tuple[int, ...],
    rng: np.random.Generator,
    fraction: float = 0.01,
    factor: float = 10.0,
    std: float = 1.0,
) -> Draw:
    if not 0.0 <= fraction < 1.0:
        raise NoisevarError(f"fraction must be in [0, 1), got {fraction}")
    scale = np.where(rng.random(shape) < fraction, factor * std, std)
    # var = σ² (1 - f + f k²)
    total = std**2 * (1.0 - fraction + fraction * factor**2)
    return rng.standard_normal(shape) * scale, total, std**2


def _ar1(
    shape: tuple[int, ...], rng: np.random.Generator, phi: float = 0.7, std: float = 1.0
) -> Draw:
    if not -1.0 < phi < 1.0:
        raise NoisevarError(f"phi must be in (-1, 1) for a stationary AR(1), got {phi}")
    # x_k = φ x_(k-1) + e_k, var(e) = σ² (1 - φ²)
    e = rng.standard_normal(shape) * std * np.sqrt(1.0 - phi**2)
    start = rng.standard_normal(shape[:-1] + (1,)) * std
    x = signal.lfilter([1.0], [1.0, -phi], e, axis=-1, zi=phi * start)[0]
    return x, std**2, None


def _kasdin_flicker(shape: tuple[int, ...], rng: np.random.Generator, qd: float) -> NDArray:
    """Kasdin's flicker noise; allantools draws from NumPy's global generator, seeded here."""
    state = np.random.get_state()  # noqa: NPY002 - allantools uses it
    np.random.seed(int(rng.integers(2**32)))  # noqa: NPY002
    try:
        rows = []
        for _ in range(int(np.prod(shape[:-1]))):
            gen = KasdinNoise(nr=shape[-1], qd=qd, b=-1)
            gen.generateNoise()
            rows.append(gen.time_series)
    finally:
        np.random.set_state(state)  # noqa: NPY002
    return np.reshape(rows, shape)


def flicker_variance(n: int, qd: float = 1.0) -> float:
    """Expected mean square of ``n`` samples of Kasdin flicker noise driven by variance ``qd``.

    Sample ``k`` is ``sum_(j<=k) h_j w_(k-j)`` with ``h_j = Γ(j + 1/2) / (Γ(1/2) j!)``.
    """
    j = np.arange(n)
    # h_j = Γ(j + α) / (Γ(α) Γ(j + 1)), α = 1/2
    h = np.exp(special.gammaln(j + 0.5) - special.gammaln(0.5) - special.gammaln(j + 1.0))
    return float(qd * np.mean(np.cumsum(h**2)))


def _flicker(shape: tuple[int, ...], rng: np.random.Generator, qd: float = 1.0) -> Draw:
    return _kasdin_flicker(shape, rng, qd), flicker_variance(shape[-1], qd), None


def _white_flicker(
    shape: tuple[int, ...], rng: np.random.Generator, std: float = 1.0, ratio: float = 1.0
) -> Draw:
    white = rng.standard_normal(shape) * std
    return white + _kasdin_flicker(shape, rng, ratio * std**2), std**2, None


def _white_rw(
    shape: tuple[int, ...], rng: np.random.Generator, std: float = 1.0, ratio: float = 1.0
) -> Draw:
    white = rng.standard_normal(shape) * std
    walk = np.cumsum(rng.standard_normal(shape) * std * np.sqrt(ratio), axis=-1)
    return white + walk, std**2, None


#: Noise kinds: name -> generator ``(shape, rng, **params) -> (values, variance, core)``.
KINDS: dict[str, Callable[..., Draw]] = {
    "gauss": _gauss,
    "student_t": _student_t,
    "laplace": _laplace,
    "contaminated": _contaminated,
    "ar1": _ar1,
    "flicker": _flicker,
    "white+flicker": _white_flicker,
    "white+rw": _white_rw,
}


def _rng(rng: np.random.Generator | int | None) -> np.random.Generator:
    return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)


def noise(
    kind: str, n: int, rng: np.random.Generator | int | None = None, runs: int = 1, **params: Any
) -> Noise:
    """Draw ``n`` samples (``runs`` independent rows when ``runs > 1``) of one noise kind.

    Parameters
    ----------
    kind : str
        A key of :data:`KINDS` (module docstring).
    n : int
        Samples per record.
    rng : numpy.random.Generator or int, optional
        The generator, or a seed for one.
    runs : int
        Independent records; the result has shape ``(runs, n)`` when ``runs > 1``.
    **params
        The kind's parameters (``std``, ``dof``, ``fraction``, ``factor``, ``phi``, ``qd``,
        ``ratio``).

    Returns
    -------
    Noise
    """
    if kind not in KINDS:
        raise NoisevarError(f"unknown noise kind {kind!r}; choose one of {', '.join(KINDS)}")
    if n < 2 or runs < 1:
        raise NoisevarError(f"need n >= 2 and runs >= 1, got n={n}, runs={runs}")
    shape = (runs, n) if runs > 1 else (n,)
    try:
        values, variance, core = KINDS[kind](shape, _rng(rng), **params)
    except TypeError as exc:
        raise NoisevarError(f"bad parameter for noise {kind!r}: {exc}") from None
    return Noise(kind, values, float(variance), core, dict(params))


def quantise(
    x: ArrayLike, lsb: float, variance: float, clean: ArrayLike | None = None
) -> tuple[NDArray, float]:
    """Round ``x`` to a grid of step ``lsb``.

    Parameters
    ----------
    x : array_like
        A record: clean signal plus Gaussian noise of variance ``variance``.
    lsb : float
        The quantisation step (> 0).
    variance : float
        The noise variance before rounding.
    clean : array_like, optional
        The clean signal, for the exact error variance of this record.

    Returns
    -------
    xq : ndarray
        ``lsb * round(x / lsb)``.
    error_variance : float
        The expected mean square of ``xq`` minus the clean signal: ``variance + lsb² / 12``,
        or with ``clean`` given, that expectation computed sample by sample.

    Notes
    -----
    ``variance + lsb² / 12`` holds when the clean signal sweeps many steps evenly; with noise
    well under one step and a slow signal the rounding error follows the signal (it is not
    white) and the exact value can differ by several per cent.
    """
    if not lsb > 0:
        raise NoisevarError(f"lsb must be positive, got {lsb}")
    xq = lsb * np.round(np.asarray(x, dtype=float) / lsb)
    if clean is None:
        # e_q ~ U(-q/2, q/2): var = q² / 12
        return xq, float(variance + lsb**2 / 12.0)
    return xq, quantised_error_variance(clean, lsb, variance)


def quantised_error_variance(clean: ArrayLike, lsb: float, variance: float) -> float:
    """Expected mean square of ``Q(clean + e) - clean``, ``e ~ N(0, variance)``, over samples.

    Sums ``P(Q = j lsb) (j lsb - c)²`` over the grid points within 8 standard deviations.
    """
    c = np.ravel(np.asarray(clean, dtype=float))
    std = np.sqrt(variance)
    m = np.arange(-int(np.ceil(8.0 * std / lsb)) - 1, int(np.ceil(8.0 * std / lsb)) + 2)
    grid = (np.round(c / lsb)[:, None] + m[None, :]) * lsb
    # P(Q = g) = Φ((g + q/2 - c) / σ) - Φ((g - q/2 - c) / σ)
    p = special.ndtr((grid + lsb / 2 - c[:, None]) / std) - special.ndtr(
        (grid - lsb / 2 - c[:, None]) / std
    )
    return float(np.mean(np.sum(p * (grid - c[:, None]) ** 2, axis=1)))


@dataclass(frozen=True)
class Gapped:
    """A record with blocks of samples removed (:func:`remove_blocks`).

    Attributes
    ----------
    values : ndarray, shape (..., n_kept)
        The samples left.
    t : ndarray, shape (n_kept,)
        Their times: gaps where blocks were removed.
    keep : ndarray of bool, shape (n,)
        Which samples of the full record were kept (``~keep`` marks the gaps).
    """

    values: NDArray
    t: NDArray
    keep: NDArray


def remove_blocks(
    x: ArrayLike,
    rng: np.random.Generator | int | None = None,
    fraction: float = 0.05,
    blocks: int = 10,
    t: ArrayLike | None = None,
) -> Gapped:
    """Remove ``fraction`` of the samples in ``blocks`` equal blocks at random places.

    The same blocks are removed from every row of 2-D ``x``. The noise variance is unchanged.

    Parameters
    ----------
    x : array_like, shape (..., n)
        A record (or records along the last axis).
    rng : numpy.random.Generator or int, optional
        The generator, or a seed for one.
    fraction : float
        Share of samples removed, in (0, 0.5).
    blocks : int
        Number of blocks.
    t : array_like, shape (n,), optional
        Sample times; default ``0, 1, ..., n-1``.

    Returns
    -------
    Gapped
    """
    arr = np.asarray(x, dtype=float)
    n = arr.shape[-1]
    size = int(round(fraction * n / blocks))
    if not 0 < fraction < 0.5 or blocks < 1 or size < 1:
        raise NoisevarError(
            f"cannot remove {fraction:.0%} of {n} samples in {blocks} blocks: "
            "give 0 < fraction < 0.5 and fewer, larger blocks"
        )
    # distinct sorted starts in the shortened record, spread out by one block each
    starts = np.sort(_rng(rng).choice(np.arange(1, n - blocks * size), blocks, replace=False))
    starts = starts + size * np.arange(blocks)
    keep = np.ones(n, dtype=bool)
    for s in starts:
        keep[s : s + size] = False
    times = np.arange(n, dtype=float) if t is None else np.asarray(t, dtype=float)
    return Gapped(arr[..., keep], times[keep], keep)


def _motion(length: int, rng: np.random.Generator) -> NDArray:
    """One burst: a fast oscillation, jerky steps (a random walk) or taps that ring."""
    k = np.arange(length)
    kind = rng.integers(3)
    if kind == 0:
        window = np.sin(np.pi * k / length) ** 2
        return rng.uniform(2, 30) * window * np.sin(2 * np.pi * k / rng.uniform(3.0, 40.0))
    if kind == 1:
        return np.cumsum(rng.normal(0.0, rng.uniform(0.5, 5.0), length))
    out = np.zeros(length)
    for a in rng.integers(0, length, int(rng.integers(3, 20))):
        ring = np.exp(-np.arange(length - a) / rng.uniform(2, 20))
        out[a:] += rng.normal(0, 20) * ring * np.cos(np.arange(length - a) * rng.uniform(0.3, 2))
    return out


def motion_bursts(n: int, rng: np.random.Generator | int | None = None) -> NDArray:
    """Motion to add to a still record: one to three bursts of random kind, length and place.

    Parameters
    ----------
    n : int
        Samples.
    rng : Generator, int or None
        Randomness (a seed for a repeatable record).

    Returns
    -------
    ndarray, shape (n,)
        Zero outside the bursts; each burst is a fast oscillation, jerky steps (a random
        walk) or taps that ring, in units of a unit noise (amplitudes 2-30), over 2-12.5 %
        of the record. Real logs are still and moving stretches (issue 26's regimes).
    """
    rng = _rng(rng)
    out = np.zeros(n)
    for _ in range(int(rng.integers(1, 4))):
        length = int(rng.integers(n // 50, n // 8))
        a = int(rng.integers(0, n - length))
        out[a : a + length] += _motion(length, rng)
    return out


def still_start(
    still: int, n: int = 500, rng: np.random.Generator | int | None = None, sigma: float = 0.03
) -> NDArray:
    """A record still for its first ``still`` samples, then an oscillation with extra noise.

    Parameters
    ----------
    still : int
        Still samples at the start (white noise of std ``sigma`` alone).
    n : int
        Samples.
    rng : Generator, int or None
        Randomness (a seed for a repeatable record).
    sigma : float
        The still noise's standard deviation.

    Returns
    -------
    ndarray, shape (n,)
        From ``still`` on, a 25-sample sinusoid of amplitude 1-3 and white noise of std 0.3
        added: a still stretch too short (or long enough) for an R of its own.
    """
    rng = _rng(rng)
    t = np.arange(n)
    z = sigma * rng.normal(size=n)
    m = t >= still
    z[m] += 2.0 * np.sin(2 * np.pi * t[m] / 25.0) * rng.uniform(0.5, 1.5)
    return z + m * 0.3 * rng.normal(size=n)


def postures(
    raised: float = 2.2, rest: int = 5000, rng: np.random.Generator | int | None = None
) -> NDArray:
    """Two still levels: a short rest at variance 1, a long one at ``raised`` (another
    posture), motion between.

    Parameters
    ----------
    raised : float
        The long rest's noise variance (the short rests' is 1).
    rest : int
        Samples of the long rest.
    rng : Generator, int or None
        Randomness (a seed for a repeatable record).

    Returns
    -------
    ndarray
        300 still samples, 400 of motion (a 40-sample sinusoid of amplitude 30 under a
        Hann window, white noise of std 30), ``rest`` at ``raised``, 400 of motion, 300
        still.
    """
    rng = _rng(rng)
    parts = []
    for kind, n in (("s", 300), ("m", 400), ("r", rest), ("m", 400), ("s", 300)):
        t = np.arange(n)
        if kind == "m":
            parts.append(30 * np.sin(2 * np.pi * t / 40) * np.hanning(n) + rng.normal(0, 30, n))
        else:
            parts.append(rng.normal(0.0, np.sqrt(raised if kind == "r" else 1.0), n))
    return np.concatenate(parts)


def sine_bursts(n: int, rng: np.random.Generator | int | None = None) -> NDArray:
    """White noise (σ = 1) with a burst of a fast sinusoid every ``n // 5`` samples.

    Parameters
    ----------
    n : int
        Samples (at least 30).
    rng : Generator, int or None
        Randomness (a seed for a repeatable record).

    Returns
    -------
    ndarray, shape (n,)
        Bursts of ``n // 30`` samples from sample ``n // 20`` on, each a sinusoid of
        amplitude 3-20 and period 2π x 2-7 samples: a record whose level varies, for the
        same-numbers checks of the estimator's speed work.
    """
    rng = _rng(rng)
    x = rng.normal(size=n)
    t = np.arange(n)
    for s in range(n // 20, n, n // 5):
        burst = slice(s, s + n // 30)
        x[burst] += rng.uniform(3, 20) * np.sin(t[burst] / rng.uniform(2, 7))
    return x
