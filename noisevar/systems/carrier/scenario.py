"""The tracking channel: scenario, Doppler profile and simulated truth (docs/algorithms.md §B1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.systems.base import BatchResult

L1_HZ = 1575.42e6
METHODS = ("ekf", "aekf")
#: Q adaptations of the AEKF: the paper's eq. (26) and our innovation-matched scaling.
Q_RULES = ("paper", "scaled")
#: Start of the AEKF's windowed R: the window full of the design R, or the paper's running mean.
R_STARTS = ("design", "running")
#: Jerk density (rad²/s⁵) of the matched model: covers the default 25 Hz/s manoeuvres.
JERK_PSD = 4.0e4


@dataclass(frozen=True)
class CarrierScenario:
    """Parameters of one tracking channel.

    Parameters
    ----------
    cn0_dbhz : float
        Carrier-to-noise density ratio (dB-Hz); the paper's case is 30.
    integration_s : float
        Coherent integration time ``T`` (s); 1 to 20 ms for L1 C/A.
    duration_s : float
        Length of the run (s).
    doppler_hz : float
        Initial Doppler (Hz).
    doppler_rate_hz_s : float
        Peak Doppler rate of the manoeuvres (Hz/s; 1 g along the line of sight
        is about 51 Hz/s at L1).
    manoeuvres_s : tuple of float
        Start times of the two manoeuvres (s).
    ramp_s, hold_s : float
        Duration of a rate ramp and of the constant-rate part (s).
    clock_frequency_walk : float
        Receiver-clock frequency random walk (Hz/sqrt(s)).
    initial_doppler_error_hz : float
        Standard deviation of the acquisition's Doppler error (Hz).
    data_bits : bool
        Modulate 50 bit/s navigation data.
    sub_samples : int
        Points per integration interval for the correlator average.
    """

    cn0_dbhz: float = 30.0
    integration_s: float = 0.01
    duration_s: float = 10.0
    doppler_hz: float = 1500.0
    doppler_rate_hz_s: float = 25.0
    manoeuvres_s: tuple[float, float] = (2.0, 6.0)
    ramp_s: float = 0.5
    hold_s: float = 1.5
    clock_frequency_walk: float = 0.1
    initial_doppler_error_hz: float = 2.0
    data_bits: bool = False
    sub_samples: int = 8

    def validate(self) -> None:
        """Raise :class:`NoisevarError` when a parameter is out of range."""
        if not np.isfinite(self.cn0_dbhz) or self.cn0_dbhz <= 0:
            raise NoisevarError(
                f"C/N0 = {self.cn0_dbhz} dB-Hz is not a usable carrier-to-noise density; give "
                "a positive value (weak signals are 20-35 dB-Hz, strong ones 45-50)."
            )
        if not 0 < self.integration_s <= 0.02:
            raise NoisevarError(
                f"integration_s={self.integration_s}: give a coherent integration time in "
                "(0, 0.02] s (at most one 20 ms data bit)."
            )
        if (
            self.data_bits
            and abs(0.02 / self.integration_s - round(0.02 / self.integration_s)) > 1e-9
        ):
            raise NoisevarError(
                "with data bits the integration time must divide the 20 ms bit (1, 2, 4, 5, 10 "
                "or 20 ms)."
            )
        if not self.duration_s >= 20 * self.integration_s:
            raise NoisevarError("duration_s must cover at least 20 integration periods.")
        if self.clock_frequency_walk < 0 or self.initial_doppler_error_hz < 0:
            raise NoisevarError("clock_frequency_walk and initial_doppler_error_hz must be >= 0.")
        if int(self.sub_samples) != self.sub_samples or self.sub_samples < 2:
            raise NoisevarError(f"sub_samples={self.sub_samples} must be an integer >= 2.")
        if self.ramp_s <= 0 or self.hold_s < 0:
            raise NoisevarError("ramp_s must be positive and hold_s >= 0.")

    @property
    def amplitude(self) -> float:
        """Correlator amplitude ``A = sqrt(2 (C/N0) T)`` for unit-variance I/Q noise."""
        return float(np.sqrt(2.0 * 10.0 ** (self.cn0_dbhz / 10.0) * self.integration_s))

    @property
    def n_steps(self) -> int:
        """Number of integration periods."""
        return int(round(self.duration_s / self.integration_s))


def doppler_profile(scenario: CarrierScenario, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Doppler rate (Hz/s) at times ``t``: two jerk-limited manoeuvres of opposite sign."""
    rate = np.zeros_like(t)
    r, hold = scenario.ramp_s, scenario.hold_s
    for sign, t0 in zip((1.0, -1.0), scenario.manoeuvres_s, strict=True):
        up = np.clip((t - t0) / r, 0.0, 1.0)
        down = np.clip((t - t0 - r - hold) / r, 0.0, 1.0)
        rate += sign * scenario.doppler_rate_hz_s * (up - down)
    return rate


@dataclass(frozen=True)
class CarrierTruth(BatchResult):
    """The true carrier of a batch of runs on the correlator's fine time grid.

    Attributes
    ----------
    fine_time : ndarray, shape (N*S,)
        Sub-sample times (s), ``S`` per integration interval.
    phase : ndarray, shape (B, N*S)
        True carrier phase (rad) at ``fine_time``.
    mid_phase : ndarray, shape (B, N)
        True carrier phase at the interval centres.
    doppler_hz : ndarray, shape (B, N)
        True Doppler at the interval centres (Hz).
    bits : ndarray, shape (B, N)
        Data bit (±1) of each interval.
    noise : ndarray, shape (B, N, 2)
        Unit-variance I/Q noise.
    """

    fine_time: NDArray[np.float64]
    phase: NDArray[np.float64]
    mid_phase: NDArray[np.float64]
    doppler_hz: NDArray[np.float64]
    bits: NDArray[np.float64]
    noise: NDArray[np.float64]

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.mid_phase.shape[0])

    @property
    def label(self) -> str:
        """``"carrier truth"``."""
        return "carrier truth"


def simulate_channel(scenario: CarrierScenario, seed: int = 0, runs: int = 1) -> CarrierTruth:
    """The true carrier phase, data bits and correlator noise of ``runs`` runs.

    The correlator outputs themselves depend on the NCO, hence on the
    filter: :func:`run_carrier` forms them step by step from this truth.

    Parameters
    ----------
    scenario : CarrierScenario
    seed : int
        Seed of the random generator.
    runs : int
        Number of Monte Carlo runs ``B``.

    Returns
    -------
    CarrierTruth
    """
    scenario.validate()
    if int(runs) != runs or runs < 1:
        raise NoisevarError(f"runs={runs} must be a positive integer.")
    rng = np.random.default_rng(seed)
    T, S, n = scenario.integration_s, int(scenario.sub_samples), scenario.n_steps
    dt = T / S
    fine = (np.arange(n * S) + 0.5) * dt
    grid = np.arange(n * S + 1) * dt  # sub-interval edges
    rate = doppler_profile(scenario, grid)
    doppler = scenario.doppler_hz + np.concatenate(
        [[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * dt)]
    )
    clock = np.cumsum(
        scenario.clock_frequency_walk * np.sqrt(dt) * rng.standard_normal((runs, n * S + 1)),
        axis=1,
    )
    freq = doppler[None, :] + clock  # Hz, at the edges
    phase_edges = (
        2
        * np.pi
        * np.concatenate(
            [np.zeros((runs, 1)), np.cumsum(0.5 * (freq[:, 1:] + freq[:, :-1]) * dt, axis=1)],
            axis=1,
        )
    )
    phase_edges += rng.uniform(-np.pi, np.pi, (runs, 1))
    phase = 0.5 * (phase_edges[:, 1:] + phase_edges[:, :-1])
    mid_phase = phase_edges[:, S // 2 :: S][:, :n] if S % 2 == 0 else phase[:, S // 2 :: S]
    mid_freq = freq[:, S // 2 :: S][:, :n]
    if scenario.data_bits:
        per_bit = int(round(0.02 / T))
        n_bits = -(-n // per_bit)
        bits = np.repeat(rng.choice([-1.0, 1.0], (runs, n_bits)), per_bit, axis=1)[:, :n]
    else:
        bits = np.ones((runs, n))
    noise = rng.standard_normal((runs, n, 2))
    return CarrierTruth(
        fine_time=fine,
        phase=phase,
        mid_phase=mid_phase,
        doppler_hz=mid_freq,
        bits=bits,
        noise=noise,
    )
