"""Rate noise with given IEEE-952 terms (docs/algorithms.md §E4), for tests and teaching."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError


def flicker(n: int, rate: float, level: float, rng: np.random.Generator) -> NDArray:
    """Flicker (1/f) rate noise whose Allan deviation is flat at ``sqrt(2 ln 2 / pi) level``.

    Parameters
    ----------
    n : int
        Samples.
    rate : float
        Sample rate (Hz).
    level : float
        Bias instability B.
    rng : numpy.random.Generator

    Returns
    -------
    ndarray
    """
    f = np.fft.rfftfreq(n, 1.0 / rate)
    # one-sided PSD S(f) = B^2 / (pi f), flat ADEV^2 = 2 ln2 h_{-1} = (2 ln 2 / pi) B^2
    psd = np.zeros_like(f)
    psd[1:] = level**2 / (math.pi * f[1:])
    # a bin of complex amplitude c(a + ib) adds variance 4 c^2 / n^2 = S(f) fs / n
    c = np.sqrt(psd * rate * n) / 2.0
    spec = c * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    return np.fft.irfft(spec, n)


def simulate_thermal(
    temperature: NDArray,
    rate: float,
    *,
    polynomial: tuple[float, ...],
    warmup: tuple[float, float] = (0.0, 1.0),
    reference: float = 25.0,
    seed: int = 0,
    **terms: float,
) -> NDArray:
    """Rate samples with bias ``poly(T - reference) + A exp(-t/tau)`` plus IEEE-952 noise.

    Parameters
    ----------
    temperature : ndarray, shape (n,)
        Temperature (°C) at each sample.
    rate : float
        Sample rate (Hz).
    polynomial : tuple of float
        Bias coefficients in powers of ``T - reference``, lowest first.
    warmup : (float, float)
        Amplitude ``A`` and time constant ``tau`` (s) of the power-on transient.
    reference : float
        Reference temperature (°C).
    seed : int
    **terms : float
        Noise terms of :func:`simulate_inertial` (``random_walk=...``).

    Returns
    -------
    ndarray

    Notes
    -----
    docs/algorithms.md §E9: the model :func:`noisevar.noise_model.temperature_model` fits.
    """
    temp = np.asarray(temperature, dtype=float)
    t = np.arange(temp.size) / rate
    amplitude, tau = warmup
    bias = np.polynomial.polynomial.polyval(temp - reference, polynomial)
    return (
        bias + amplitude * np.exp(-t / tau) + simulate_inertial(temp.size, rate, seed=seed, **terms)
    )


def simulate_inertial(
    n: int,
    rate: float,
    *,
    quantization: float = 0.0,
    random_walk: float = 0.0,
    bias_instability: float = 0.0,
    rate_random_walk: float = 0.0,
    rate_ramp: float = 0.0,
    gauss_markov: tuple[tuple[float, float], ...] = (),
    seed: int = 0,
) -> NDArray:
    """Rate samples whose Allan variance is eq. E4.1 with the given terms.

    Parameters
    ----------
    n : int
        Samples.
    rate : float
        Sample rate (Hz).
    quantization, random_walk, bias_instability, rate_random_walk, rate_ramp : float
        Q, N, B, K, R in the units of eq. E4.1.
    gauss_markov : tuple of (sigma, tau_c)
        First-order Gauss-Markov biases: stationary std (unit) and correlation time (s).
    seed : int
        Seed of the noise.

    Returns
    -------
    ndarray
    """
    if n < 2 or not rate > 0:
        raise NoisevarError(f"Need at least 2 samples and a positive rate; got n={n}, {rate}.")
    rng = np.random.default_rng(seed)
    # white angle error q_k of std Q, seen as rate: (q_k - q_{k-1}) fs
    q = quantization * rng.standard_normal(n + 1)
    y = np.diff(q) * rate
    # white rate: std N sqrt(fs)
    y += random_walk * math.sqrt(rate) * rng.standard_normal(n)
    if bias_instability > 0:
        y += flicker(n, rate, bias_instability, rng)
    # rate random walk: increments of std K / sqrt(fs)
    y += np.cumsum(rate_random_walk / math.sqrt(rate) * rng.standard_normal(n))
    # rate ramp: slope R per second
    y += rate_ramp * np.arange(n) / rate
    for sigma, tau_c in gauss_markov:
        y += gauss_markov_bias(n, rate, sigma, tau_c, rng)
    return y


def gauss_markov_bias(
    n: int, rate: float, sigma: float, tau_c: float, rng: np.random.Generator
) -> NDArray:
    """A stationary first-order Gauss-Markov bias: ``b_k = phi b_(k-1) + w_k``.

    ``phi = exp(-1 / (tau_c fs))``, ``var(w) = sigma^2 (1 - phi^2)``, ``b_0 ~ N(0, sigma^2)``.
    """
    from scipy.signal import lfilter

    phi = math.exp(-1.0 / (tau_c * rate))
    w = sigma * math.sqrt(-math.expm1(-2.0 / (tau_c * rate))) * rng.standard_normal(n)
    b0 = sigma * rng.standard_normal()
    return lfilter([1.0], [1.0, -phi], w, zi=[phi * b0])[0]
