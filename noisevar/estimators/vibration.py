"""R without a vibration: the line the whiteness test found, taken out of R's residual (§E2).

A vibration (rotors, motors, a gait) or a periodic signal adds a line to the noise, and R's
residual filter passes it with its own gain at that frequency (the short filter's at the
Nyquist rate: several times its gain on white noise), so R read the noise plus the line
times that gain. A filter that is told to notch or low-pass the vibration out (what the
verdict says to do) sees the noise without it: the sinusoid at the found frequency is
fitted to R's residual by least squares and its share of the residual's power taken out of
R. The frequency is read in a first pass (the periodogram's peak near the one found, from
the residual's demodulated sums by blocks), the fit's sums in a second, by blocks, so that
a record read in chunks reads each block twice and gives the same numbers; the interval is the block
jackknife's of the whole statistic (Künsch 1989), as on differenced data.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy import special

from noisevar.diagnostics import NoiseDiagnostics
from noisevar.diagnostics.verdict_parts import found_oscillation
from noisevar.estimators.differenced_interval import BLOCK_FILTERS, JACK_BLOCKS
from noisevar.estimators.results import VarianceEstimate

#: Residuals per block of the first pass: a line off the frequency found by up to
#: :data:`FREQUENCY_REACH` turns by under a fifth of a cycle in a block.
PHASE_BLOCK = 16
#: How far the line's frequency is looked for from the oscillation's (cycles per sample:
#: five steps of its grid).
FREQUENCY_REACH = 0.01


def _residuals(
    read: Callable[[int, int], NDArray], n: int, d: NDArray, edges: NDArray
) -> list[tuple[int, NDArray]]:
    """R's residual ``e = d * z`` by blocks: ``(first index, e)``, each residual in the
    block of its first sample (read block by block)."""
    m = n - d.size + 1
    out = []
    for a, c in zip(edges[:-1], edges[1:], strict=True):
        z = np.asarray(read(a, min(n, c + d.size - 1)), dtype=float)
        out.append((int(a), np.convolve(z, d[::-1], mode="valid")[: max(min(c, m) - a, 0)]))
    return out


def _frequency(read: Callable[[int, int], NDArray], n: int, d: NDArray, f0: float) -> float:
    """The line's frequency near ``f0`` (cycles per sample): the peak of the periodogram of
    R's residual within :data:`FREQUENCY_REACH` of ``f0`` (and up to 1/2, a real line's
    image lying above), read off the demodulated sums ``Σ e_t exp(-2πi f0 t)`` of blocks of
    :data:`PHASE_BLOCK` residuals by a zero-padded FFT over the blocks (a step of
    ``1 / (8 n)``)."""
    m = n - d.size + 1
    edges = np.arange(0, m + 1, PHASE_BLOCK)
    s = np.array(
        [
            np.sum(e * np.exp(-2j * np.pi * f0 * (a + np.arange(e.size))))
            for a, e in _residuals(read, n, d, edges)
        ]
    )
    size = 1 << int(np.ceil(np.log2(8 * max(s.size, 1))))
    power = np.abs(np.fft.fft(s, size)) ** 2
    shift = np.fft.fftfreq(size) / PHASE_BLOCK  # δ: the line's frequency less f0
    near = (np.abs(shift) <= FREQUENCY_REACH) & (f0 + shift <= 0.5)
    return float(f0 + shift[near][np.argmax(power[near])]) if near.any() else f0


def _sums(
    read: Callable[[int, int], NDArray], n: int, d: NDArray, f: float, blocks: int
) -> NDArray:
    """Per block: ``Σ e²``, the count, ``Σ e c``, ``Σ e s``, ``Σ c²``, ``Σ s²``, ``Σ c s``
    (``c``, ``s``: the cosine and sine at ``f``)."""
    m = n - d.size + 1
    edges = np.linspace(0, m, blocks + 1).astype(int)
    out = np.zeros((blocks, 7))
    for b, (a, e) in enumerate(_residuals(read, n, d, edges)):
        w = 2 * np.pi * f * (a + np.arange(e.size))
        c, s = np.cos(w), np.sin(w)
        out[b] = [e @ e, e.size, e @ c, e @ s, c @ c, s @ s, c @ s]
    return out


def _noise_power(x: NDArray) -> NDArray:
    """``(Σ e² - h' G⁺ h) / count`` of each row of sums: the residual's power without the
    sinusoid fitted by least squares (``G`` the cosine and sine's Gram matrix, ``h``
    their products with ``e``; at the Nyquist rate the sine is 0 and ``G`` singular)."""
    g = np.stack([x[..., [4, 6]], x[..., [6, 5]]], axis=-2)
    h = x[..., 2:4]
    fit = np.einsum("...i,...i->...", h, np.einsum("...ij,...j->...i", np.linalg.pinv(g), h))
    return (x[..., 0] - fit) / x[..., 1]


def without_vibration(
    result: VarianceEstimate,
    read: Callable[[int, int], NDArray] | None,
    diag: NoiseDiagnostics,
    residual: Callable[[dict], NDArray] | None,
) -> VarianceEstimate:
    """``result`` without the line of the oscillation its diagnostics found (none found,
    several segments or no residual filter: ``result`` as it is).

    Parameters
    ----------
    result : VarianceEstimate
        R normalised for white noise on R's residual ``e = d * z``.
    read : callable or None
        ``read(a, b)``: samples ``a .. b`` of the one-segment record.
    diag : NoiseDiagnostics
        The record's diagnostics (:func:`~.verdict_parts.found_oscillation`).
    residual : callable or None
        The method's residual filter from its parameters (``MethodSpec.residual``).

    Returns
    -------
    VarianceEstimate
        ``R (1 - share)``, ``share`` the fitted sinusoid's part of the residual's power,
        with the block jackknife's interval (``R e^{± t se}``) on records of at least
        ``JACK_BLOCKS / 2`` blocks of ``BLOCK_FILTERS`` filter lengths (widened to R's own
        interval scaled by the same factor where R holds lone glitches, whose Poisson count
        it has; shorter records: R's own interval so scaled), and a note.

    Notes
    -----
    docs/algorithms.md §E2 *Vibration*: it assumes one line (a tone of steady frequency and
    amplitude) in white noise; a vibration spread over a band, or drifting, is taken out in
    part, and R then lies between the noise and the noise with the vibration.
    """
    o = found_oscillation(diag.whiteness)
    # on a grid, a line may be the rounding error of a ramp (periodic at its steps per
    # sample): noise a filter sees, which no notch takes out; a span chosen per block has
    # no one residual filter
    if o is None or read is None or residual is None or diag.lsb is not None:
        return result
    if result.params.get("span", 0) is None:
        return result
    d, n = residual(result.params), diag.n
    if n < 2 * PHASE_BLOCK + d.size:
        return result
    f = _frequency(read, n, d, o.frequency)
    blocks = max(min(JACK_BLOCKS, (n - d.size + 1) // (BLOCK_FILTERS * d.size)), 1)
    x = _sums(read, n, d, f, blocks)
    factor = float(_noise_power(x.sum(0)) / (x[:, 0].sum() / x[:, 1].sum()))
    if not 0.0 < factor <= 1.0:
        return result
    note = (
        f"the oscillation at {f:.4f} of the sample rate was taken out of R: a sinusoid "
        f"fitted to R's residual held {1 - factor:.1%} of its power (R without it: the noise "
        "a filter sees once the vibration is notched out; one line assumed, a spread band "
        "is taken out in part)"
    )
    r = result.variance * factor
    core = None if result.core_variance is None else result.core_variance * factor
    out = replace(result, variance=r, core_variance=core, notes=[*result.notes, note])
    if blocks < JACK_BLOCKS // 2:
        return replace(out, ci95=(result.ci95[0] * factor, result.ci95[1] * factor))
    drop = np.log(_noise_power(x.sum(0) - x))
    var = (blocks - 1) / blocks * float(np.sum((drop - drop.mean()) ** 2))
    half = float(special.stdtrit(blocks - 1, 0.975)) * np.sqrt(var)
    if not (np.isfinite(half) and var > 0):
        return replace(out, ci95=(result.ci95[0] * factor, result.ci95[1] * factor))
    lo, hi = r * float(np.exp(-half)), r * float(np.exp(half))
    if diag.glitches:  # R's own interval counts them (Poisson) where the blocks do not reach
        lo, hi = min(lo, result.ci95[0] * factor), max(hi, result.ci95[1] * factor)
    return replace(out, dof=2.0 / var, ci95=(lo, hi))
