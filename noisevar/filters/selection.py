"""Window selection of the SOMD estimator (docs/algorithms.md §A5, §A6; paper eqs. [15]-[19]).

Each window of ``m`` samples is kept when the amplitude ratios of the smooth output
about its line and the angle between the smooth and tracking lines pass eq. [19].
``amplitude="paper"`` is the printed chain ``A1/A2, A2/A3, A3/A4``; ``"symmetric"``
closes it (adds ``A4/A1``) with a band centred on 1 in ``ln ρ``, so that the estimate
does not change when the signal is negated. ``angle="paper"`` takes slopes in raw
units per sample; ``"scaled"`` divides them by a robust noise scale first, so the test
is unit-free. Everything is vectorised over windows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar._arrays import median_inplace
from noisevar.errors import NoisevarError

ANGLES = ("scaled", "paper")
AMPLITUDE_TESTS = ("symmetric", "paper")
#: 0-based amplitude index pairs of each test: paper A1/A2, A2/A3, A3/A4; symmetric adds A4/A1
AMPLITUDE_PAIRS = {
    "paper": ((0, 1), (1, 2), (2, 3)),
    "symmetric": ((0, 1), (1, 2), (2, 3), (3, 0)),
}


def robust_noise_scale(z: ArrayLike) -> float:
    """Robust noise standard deviation from the MAD of second differences.

    ``median(|Δ²z - median(Δ²z)|) / 0.6745 / sqrt(6)``: insensitive to
    trends, curvature and jumps; used to make slopes scale-free.

    Parameters
    ----------
    z : array_like, shape (n,)
        Finite samples (n >= 3).

    Returns
    -------
    float
        The noise scale (0 for a signal with no noise).
    """
    d2 = np.diff(np.asarray(z, dtype=float), n=2)  # a new array: ours to reorder
    if d2.size == 0:
        return 0.0
    # MAD = median(|Δ²z - median(Δ²z)|): the order of Δ²z does not matter
    d2 -= median_inplace(d2)
    mad = median_inplace(np.abs(d2, out=d2))
    return float(mad / 0.6744897501960817 / np.sqrt(6.0))


def _line_fit(w: NDArray) -> tuple[NDArray, NDArray]:
    """Least-squares slope and intercept of each row, abscissa i = 1..m [17]."""
    m = w.shape[-1]
    i = np.arange(1, m + 1, dtype=float)
    ic = i - i.mean()
    slope = (w * ic).sum(axis=-1) / (ic**2).sum()
    intercept = w.mean(axis=-1) - slope * i.mean()
    return slope, intercept


@dataclass
class WindowSelection:
    """Per-window record of the selection of eqs. [16]-[19].

    Attributes
    ----------
    window : int
        Window length ``m``.
    starts : ndarray of int, shape (n_windows,)
        Index of each window's first sample.
    slope_smooth, slope_track : ndarray, shape (n_windows,)
        Fitted slopes ``a_S``, ``a_T`` (raw units per sample).
    amplitudes : ndarray, shape (n_windows, 4)
        ``A1..A4`` of eq. [18] (``A2``, ``A4`` are negative); NaN where a half
        has no point on one side of the line.
    angle_diff_deg : ndarray, shape (n_windows,)
        ``|atan(a_S) - atan(a_T)|`` in degrees, under the chosen convention.
    amp_ok, ang_ok, in_record : ndarray of bool
        Amplitude test passed, angle test passed, window lies after the
        start-up transient.
    amplitude_test : {"symmetric", "paper"}
        Convention of the amplitude test (module docstring).
    amplitude_deviation : ndarray, shape (n_windows,)
        The amplitude test's statistic: the test passes where it is below
        ``Γ_amp`` (NaN where an amplitude is undefined).
    kept : ndarray of bool
        ``amp_ok & ang_ok & in_record``.
    """

    window: int
    starts: NDArray
    slope_smooth: NDArray
    slope_track: NDArray
    amplitudes: NDArray
    angle_diff_deg: NDArray
    amp_ok: NDArray
    ang_ok: NDArray
    in_record: NDArray
    amplitude_test: str = "symmetric"
    amplitude_deviation: NDArray | None = None

    @property
    def amplitude_pairs(self) -> tuple[tuple[int, int], ...]:
        """Index pairs ``(i, j)`` of the ratios ``|A_i / A_j|`` the amplitude test uses."""
        return AMPLITUDE_PAIRS[self.amplitude_test]

    def amplitude_ratios(self) -> NDArray:
        """``|A_i / A_j|`` for each of :attr:`amplitude_pairs`, per window (NaN if undefined)."""
        num, den = (list(x) for x in zip(*self.amplitude_pairs, strict=True))
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.abs(self.amplitudes[:, num] / self.amplitudes[:, den])

    @property
    def kept(self) -> NDArray:
        """Windows that pass both tests (and lie after the transient)."""
        return self.amp_ok & self.ang_ok & self.in_record

    @property
    def n_windows(self) -> int:
        """Number of whole windows in the record."""
        return int(self.starts.size)

    def sample_mask(self, n: int) -> NDArray:
        """Boolean mask of length ``n``: samples inside kept windows."""
        mask = np.zeros(n, dtype=bool)
        kept = self.kept
        if np.any(kept):
            idx = self.starts[kept][:, None] + np.arange(self.window)
            mask[idx.ravel()] = True
        return mask

    def rejection_summary(self) -> dict[str, int]:
        """How many windows each test rejected (a window can fail both)."""
        considered = self.in_record
        return {
            "windows": int(considered.sum()),
            "kept": int(self.kept.sum()),
            "failed_amplitude": int((~self.amp_ok & considered).sum()),
            "failed_angle": int((~self.ang_ok & considered).sum()),
        }


def select_windows(
    z: ArrayLike,
    smooth_output: ArrayLike,
    track_output: ArrayLike,
    window: int = 40,
    gamma_amp: float = 0.5,
    gamma_ang: float = 10.0,
    angle: str = "scaled",
    skip: int = 0,
    noise_scale: float | None = None,
    amplitude: str = "symmetric",
) -> WindowSelection:
    """Apply the amplitude and angle tests of eq. [19] to every window.

    Parameters
    ----------
    z : array_like, shape (n,)
        Raw samples (used only for the noise scale of ``angle="scaled"``).
    smooth_output, track_output : array_like, shape (n,)
        Outputs of the smoothing (``h_S``) and tracking (``h_T``) filters.
    window : int
        Window length ``m`` (at least 8).
    gamma_amp : float
        Amplitude-consistency threshold ``Γ_amp`` in (0, 1].
    gamma_ang : float
        Angle threshold ``Γ_ang`` in degrees, in (0, 90].
    angle : {"scaled", "paper"}
        Slope convention for the angle test (see module docstring).
    skip : int
        Windows starting before this sample are marked out of the record
        (the filters' start-up transient).
    noise_scale : float, optional
        Slope scale for ``angle="scaled"``; default :func:`robust_noise_scale`.
    amplitude : {"symmetric", "paper"}
        Amplitude-test convention (see module docstring).

    Returns
    -------
    WindowSelection
    """
    if angle not in ANGLES:
        raise NoisevarError(f"angle must be one of {ANGLES}, got {angle!r}")
    if amplitude not in AMPLITUDE_TESTS:
        raise NoisevarError(f"amplitude must be one of {AMPLITUDE_TESTS}, got {amplitude!r}")
    smooth = np.asarray(smooth_output, dtype=float)
    track = np.asarray(track_output, dtype=float)
    m = int(window)
    n_win = smooth.size // m
    starts = np.arange(n_win) * m
    ws = smooth[: n_win * m].reshape(n_win, m)
    wt = track[: n_win * m].reshape(n_win, m)
    a_s, b_s = _line_fit(ws)
    a_t, _ = _line_fit(wt)
    i = np.arange(1, m + 1, dtype=float)
    dev = ws - (a_s[:, None] * i + b_s[:, None])
    first = np.zeros(m, dtype=bool)
    first[: m // 2] = True
    amps = np.empty((n_win, 4))
    above = dev >= 0
    sel, part = np.empty(dev.shape, dtype=bool), np.empty_like(dev)
    with np.errstate(invalid="ignore", divide="ignore"):
        for col, (half, side) in enumerate(
            [(first, above), (first, ~above), (~first, above), (~first, ~above)]
        ):
            np.logical_and(side, half, out=sel)
            # A = mean of the deviations on that side, in that half (x·1 = x, x·0 = ±0)
            amps[:, col] = np.multiply(dev, sel, out=part).sum(axis=1) / sel.sum(axis=1)
        num, den = (list(x) for x in zip(*AMPLITUDE_PAIRS[amplitude], strict=True))
        r = np.abs(amps[:, num] / amps[:, den])
        if amplitude == "paper":
            lo, hi = 1.0 - gamma_amp, 1.0 + gamma_amp
            amp_ok = np.all((r > lo) & (r < hi), axis=1)
            deviation = np.max(np.abs(r - 1.0), axis=1)
        else:  # tanh|ln r| < Γ  <=>  max/min of the pair < sqrt((1 + Γ) / (1 - Γ))
            deviation = np.max(np.tanh(np.abs(np.log(r))), axis=1)
            amp_ok = deviation < gamma_amp
    if angle == "scaled":
        scale = robust_noise_scale(z) if noise_scale is None else float(noise_scale)
        if not scale > 0:
            scale = 1.0
        ang_s, ang_t = np.arctan(a_s / scale), np.arctan(a_t / scale)
    else:
        ang_s, ang_t = np.arctan(a_s), np.arctan(a_t)
    angle_diff = np.degrees(np.abs(ang_s - ang_t))
    ang_ok = angle_diff < gamma_ang
    return WindowSelection(
        window=m,
        starts=starts,
        slope_smooth=a_s,
        slope_track=a_t,
        amplitudes=amps,
        angle_diff_deg=angle_diff,
        amp_ok=amp_ok,
        ang_ok=ang_ok,
        in_record=starts >= skip,
        amplitude_test=amplitude,
        amplitude_deviation=deviation,
    )
