"""Closed-loop tracking of a batch of runs with the EKF or the AEKF (docs/algorithms.md §B1)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import FixedR, KalmanFilter, RStrategy
from noisevar.systems.base import BatchResult
from noisevar.systems.carrier.model import (
    AdaptiveCarrierQR,
    _fold_amplitude,
    carrier_model,
    nominal_jerk_psd,
    nominal_measurement_variance,
)
from noisevar.systems.carrier.scenario import (
    JERK_PSD,
    METHODS,
    Q_RULES,
    R_STARTS,
    CarrierScenario,
    CarrierTruth,
    simulate_channel,
)


@dataclass(frozen=True)
class CarrierResult(BatchResult):
    """One filter's tracking of a batch of runs, with what the figures need.

    Attributes
    ----------
    method : str
        ``"ekf"`` or ``"aekf"``.
    scenario : CarrierScenario
    time : ndarray, shape (N,)
        Interval centres (s).
    phase_error : ndarray, shape (B, N)
        Tracking error ``θ̂_e - θ_e`` less whole cycles (rad): the paper's
        Figs. 2-3.
    cycles : ndarray of int, shape (B, N)
        Whole cycles (half cycles with data bits) in the unwrapped error.
    slipped : ndarray of bool, shape (B,)
        Runs whose cycle count changed after ``settle_s``.
    doppler_error_hz : ndarray, shape (B, N)
        ``f̂_d - f_d`` (Hz).
    true_doppler_hz : ndarray, shape (B, N)
    estimate : ndarray, shape (B, N, 4)
        ``x̂(k|k)``.
    R_track : ndarray, shape (B, N, 2)
        Diagonal of the ``R`` used each step.
    Q_phase_track : ndarray, shape (B, N)
        ``Q[0, 0]`` used each step (follows the ``Q`` adaptation).
    iq : ndarray, shape (B, N, 2)
        The correlator outputs the filter saw.
    settle_steps : int
        Steps left out of the RMS and of the slip test.
    measurement_variance : float
        The ``R = σ² I`` the filter was designed with (1: the truth).
    jerk_psd : float
        The jerk density of the design ``Q`` (rad²/s⁵).
    q_rule : str
        ``"none"`` for the EKF or without ``Q`` adaptation, else the AEKF's
        :data:`Q_RULES` entry.
    """

    method: str
    scenario: CarrierScenario
    time: NDArray[np.float64]
    phase_error: NDArray[np.float64]
    cycles: NDArray[np.int64]
    slipped: NDArray[np.bool_]
    doppler_error_hz: NDArray[np.float64]
    true_doppler_hz: NDArray[np.float64]
    estimate: NDArray[np.float64]
    R_track: NDArray[np.float64]
    Q_phase_track: NDArray[np.float64]
    iq: NDArray[np.float64]
    settle_steps: int
    measurement_variance: float = 1.0
    jerk_psd: float = JERK_PSD
    q_rule: str = "none"

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.estimate.shape[0])

    @property
    def label(self) -> str:
        """``"<method>/<q_rule>"``, e.g. ``"aekf/scaled"``."""
        return f"{self.method}/{self.q_rule}"

    @property
    def rms_phase_error(self) -> float:
        """RMS phase error over runs and steps after the start-up (rad)."""
        e = self.phase_error[:, self.settle_steps :]
        return float(np.sqrt(np.nanmean(e**2)))

    @property
    def loss_of_lock(self) -> float:
        """Fraction of runs that slipped a cycle."""
        return float(np.mean(self.slipped))


def run_carrier(
    scenario: CarrierScenario,
    method: str = "aekf",
    seed: int = 0,
    runs: int = 1,
    window: int = 50,
    adapt_r: bool = True,
    adapt_q: bool = True,
    jerk_psd: float = JERK_PSD,
    settle_s: float = 0.5,
    truth: CarrierTruth | None = None,
    phase_init: bool = True,
    q_rule: str = "paper",
    nominal_cn0_dbhz: float | None = None,
    nominal_doppler_rate_hz_s: float | None = None,
    r_start: str = "design",
) -> CarrierResult:
    """Track ``runs`` seeded runs of the channel with the EKF or the AEKF.

    Both filters start from the same design ``(R, Q)``: by default the
    matched one (``R`` the true I/Q noise, ``Q`` from ``jerk_psd``); with
    ``nominal_cn0_dbhz`` / ``nominal_doppler_rate_hz_s`` the design of a
    receiver built for nominal conditions (see
    :func:`nominal_measurement_variance`, :func:`nominal_jerk_psd`). The
    EKF keeps it; the AEKF adapts from it.

    Parameters
    ----------
    scenario : CarrierScenario
        The actual signal.
    method : {"ekf", "aekf"}
        Fixed-noise EKF, or the adaptive EKF (eqs. (14), (22) and the
        ``Q`` rule).
    seed, runs : int
        Seed and number of runs (all filtered in lock-step). The same seed
        gives both methods the same signals and noise.
    window : int
        ``W`` of eq. (14) (AEKF).
    adapt_r, adapt_q : bool
        AEKF: estimate ``R`` and/or ``Q`` (both off: the EKF).
    jerk_psd : float
        Doppler-jerk density matched to the scenario's manoeuvres
        (rad²/s⁵): the design ``Q`` unless ``nominal_doppler_rate_hz_s``
        rescales it.
    settle_s : float
        Start-up left out of the RMS phase error and the slip test (s).
    truth : CarrierTruth, optional
        Precomputed :func:`simulate_channel` output (else made from ``seed``).
    phase_init : bool
        Start the phase state from the first prompt output (the loop's
        pull-in; the default). Without it the prior phase is 0 ± π/√3 and an
        EKF with a precise measurement (high C/N0) can be thrown off by the
        linearisation of a large first phase error.
    q_rule : {"paper", "scaled"}
        AEKF ``Q`` adaptation (:class:`AdaptiveCarrierQR`): the paper's
        eq. (26) (default; it runs away), or our innovation-matched scaling
        (the experiment's ``aekf``).
    nominal_cn0_dbhz : float, optional
        The design's C/N0 (dB-Hz): ``R = 10^((C/N0 - nominal)/10) I``.
        Default: ``R`` matched to the actual C/N0.
    nominal_doppler_rate_hz_s : float, optional
        The design's peak Doppler rate (Hz/s); ``Q`` from
        :func:`nominal_jerk_psd`. Default: ``jerk_psd`` as given.
    r_start : {"design", "running"}
        AEKF: how the windowed ``R̂`` starts (:class:`AdaptiveCarrierQR`):
        from a window full of the design ``R`` (default) or from the
        paper's running mean of the first residuals.

    Returns
    -------
    CarrierResult
    """
    _check_settings(scenario, method, jerk_psd, q_rule, r_start)
    r_design = (
        1.0
        if nominal_cn0_dbhz is None
        else nominal_measurement_variance(scenario.cn0_dbhz, nominal_cn0_dbhz)
    )
    q_design = (
        float(jerk_psd)
        if nominal_doppler_rate_hz_s is None
        else nominal_jerk_psd(scenario, nominal_doppler_rate_hz_s, jerk_psd)
    )
    truth = truth if truth is not None else simulate_channel(scenario, seed, runs)
    B = truth.mid_phase.shape[0]
    control = np.zeros(B)
    model = carrier_model(scenario, control, jerk_psd=q_design, measurement_variance=r_design)
    strategy: RStrategy = (
        FixedR()
        if method == "ekf"
        else AdaptiveCarrierQR(window, adapt_r, adapt_q, q_rule=q_rule, r_start=r_start)
    )
    filt = KalmanFilter(model, strategy=strategy, batch_size=B)
    _start_filter(filt, scenario, truth, seed, phase_init)
    est, R_track, Q_track, iq_rec, theta_true = _track(filt, control, scenario, truth)
    T = scenario.integration_s
    n = truth.mid_phase.shape[1]
    settle = min(int(round(settle_s / T)), n - 1)
    wrapped, cycles, slipped = _slips(est, theta_true, scenario.data_bits, settle)
    return CarrierResult(
        method=method,
        scenario=scenario,
        time=(np.arange(n) + 0.5) * T,
        phase_error=wrapped,
        cycles=cycles,
        slipped=slipped,
        doppler_error_hz=est[:, :, 1] / (2 * np.pi) - truth.doppler_hz,
        true_doppler_hz=truth.doppler_hz,
        estimate=est,
        R_track=R_track,
        Q_phase_track=Q_track,
        iq=iq_rec,
        settle_steps=settle,
        measurement_variance=r_design,
        jerk_psd=q_design,
        q_rule=q_rule if method == "aekf" and adapt_q else "none",
    )


def _slips(
    est: NDArray[np.float64], theta_true: NDArray[np.float64], data_bits: bool, settle: int
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.bool_]]:
    """Phase error less whole cycles, the cycle counts, and the runs that slipped."""
    ambiguity = np.pi if data_bits else 2 * np.pi
    # e = θ̂_e - θ_e
    err = est[:, :, 0] - theta_true
    cycles = np.round(err / ambiguity).astype(np.int64)
    wrapped = err - ambiguity * cycles
    finite = np.all(np.isfinite(est), axis=(1, 2))
    slipped = np.any(cycles[:, settle:] != cycles[:, settle : settle + 1], axis=1) | ~finite
    return wrapped, cycles, slipped


def _check_settings(
    scenario: CarrierScenario, method: str, jerk_psd: float, q_rule: str, r_start: str
) -> None:
    """Raise :class:`NoisevarError` on settings :func:`run_carrier` cannot use."""
    if method not in METHODS:
        raise NoisevarError(f"method={method!r}; choose 'ekf' or 'aekf'.")
    scenario.validate()
    if not (np.isfinite(jerk_psd) and jerk_psd > 0):
        raise NoisevarError(f"jerk_psd={jerk_psd} must be positive.")
    if q_rule not in Q_RULES:
        raise NoisevarError(f"q_rule={q_rule!r}; choose 'paper' or 'scaled'.")
    if r_start not in R_STARTS:
        raise NoisevarError(f"r_start={r_start!r}; choose 'design' or 'running'.")


def _start_filter(
    filt: KalmanFilter,
    scenario: CarrierScenario,
    truth: CarrierTruth,
    seed: int,
    phase_init: bool,
) -> None:
    """Acquisition: a seeded Doppler error, and the phase of the first prompt output."""
    B = filt.batch_size
    T, S = scenario.integration_s, int(scenario.sub_samples)
    amp = scenario.amplitude
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    filt.x = filt.x.copy()
    filt.x[:, 1] += 2 * np.pi * scenario.initial_doppler_error_hz * rng.standard_normal(B)
    if not phase_init:
        return
    # Pull-in: the phase of the first prompt output (NCO at the acquired Doppler) starts the
    # phase state, with the variance of one sample's phase (1/A² for unit-variance I/Q noise).
    offsets = (np.arange(S) + 0.5) * (T / S)
    first = truth.phase[:, :S] - (filt.x[:, 1] + T * filt.x[:, 2])[:, None] * offsets
    z_first = amp * np.mean(np.exp(1j * first), axis=1) * truth.bits[:, 0]
    z_first = z_first + truth.noise[:, 0, 0] + 1j * truth.noise[:, 0, 1]
    filt.x[:, 0] = np.angle(z_first)
    P = np.array(filt.P)
    P[:, 0, 0] = 1.0 / amp**2
    filt.P = P


def _track(
    filt: KalmanFilter,
    control: NDArray[np.float64],
    scenario: CarrierScenario,
    truth: CarrierTruth,
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """The closed loop: estimates, R and Q[0,0] used, I/Q seen and the true phase error."""
    B, n = truth.mid_phase.shape
    T, S = scenario.integration_s, int(scenario.sub_samples)
    amp = scenario.amplitude
    offsets = (np.arange(S) + 0.5) * (T / S)
    est = np.empty((B, n, 4))
    R_track = np.empty((B, n, 2))
    Q_track = np.empty((B, n))
    iq_rec = np.empty((B, n, 2))
    theta_true = np.empty((B, n))
    nco_phase = np.zeros(B)  # NCO phase at the start of the current interval
    nco_freq_prev = None
    for k in range(n):  # closed loop: the NCO of step k depends on the estimate of k-1
        nco_freq = filt.x[:, 1] + T * filt.x[:, 2]  # predicted Doppler, rad/s
        if nco_freq_prev is None:
            nco_freq_prev = nco_freq
        # NCO phase advance between the centres of intervals k-1 and k
        control[:] = 0.5 * T * (nco_freq_prev + nco_freq)
        filt.predict()
        fine_phase = truth.phase[:, k * S : (k + 1) * S]
        nco = nco_phase[:, None] + nco_freq[:, None] * offsets[None, :]
        theta = fine_phase - nco
        # z = d A mean(e^{jθ}) + n
        corr = np.mean(np.exp(1j * theta), axis=1)
        z = amp * truth.bits[:, k, None] * np.stack([corr.real, corr.imag], axis=-1)
        z = z + truth.noise[:, k]
        theta_true[:, k] = truth.mid_phase[:, k] - (nco_phase + 0.5 * T * nco_freq)
        if scenario.data_bits:
            # d̂ = sign(I cos θ̂ + Q sin θ̂)
            pred = filt.x_pred[:, 0]
            bit = np.sign(z[:, 0] * np.cos(pred) + z[:, 1] * np.sin(pred))
            z = z * np.where(bit == 0, 1.0, bit)[:, None]
        iq_rec[:, k] = z
        filt.update(z)
        _fold_amplitude(filt)
        est[:, k] = filt.x
        R_track[:, k] = np.diagonal(np.broadcast_to(filt.R, (B, 2, 2)), 0, -2, -1)
        Q_track[:, k] = np.broadcast_to(filt.Q, (B, 4, 4))[:, 0, 0]
        nco_phase = nco_phase + T * nco_freq
        nco_freq_prev = nco_freq
    return est, R_track, Q_track, iq_rec, theta_true


def comparison_variants(
    nominal_cn0_dbhz: float | None = 45.0,
    nominal_doppler_rate_hz_s: float | None = None,
) -> dict[str, dict[str, object]]:
    """The filters of the realistic comparison, as :func:`run_carrier` keyword sets.

    ``ekf`` is the fixed EKF of a receiver designed for nominal conditions
    (the paper's "traditional EKF": noise settings fixed beforehand);
    ``aekf`` adapts from the same design with eq. (22) and the stabilised
    ``Q`` (``q_rule="scaled"``); ``aekf_r_only`` adapts ``R`` only;
    ``aekf_paper_q`` uses the paper's eq. (26) for ``Q`` (it runs away);
    ``ekf_matched`` is the reference EKF with the true ``R`` and the ``Q``
    matched to the scenario's manoeuvres — no real receiver has that design
    at every C/N0, but it is the bound the adaptive filters should approach.

    Parameters
    ----------
    nominal_cn0_dbhz : float or None
        The design C/N0 (``None``: matched ``R``).
    nominal_doppler_rate_hz_s : float or None
        The design peak Doppler rate (``None``: the scenario's).

    Returns
    -------
    dict of str to dict
    """
    nominal: dict[str, object] = {
        "nominal_cn0_dbhz": nominal_cn0_dbhz,
        "nominal_doppler_rate_hz_s": nominal_doppler_rate_hz_s,
    }
    return {
        "ekf": {"method": "ekf", **nominal},
        "aekf": {"method": "aekf", "q_rule": "scaled", **nominal},
        "ekf_matched": {"method": "ekf"},
        "aekf_r_only": {"method": "aekf", "adapt_q": False, **nominal},
        "aekf_paper_q": {"method": "aekf", "q_rule": "paper", "r_start": "running", **nominal},
    }


def compare(
    scenario: CarrierScenario,
    variants: Mapping[str, Mapping[str, object]] | None = None,
    seed: int = 0,
    runs: int = 1,
    truth: CarrierTruth | None = None,
    **kwargs: object,
) -> dict[str, CarrierResult]:
    """Run several filters on the same signals (one :func:`simulate_channel`).

    Parameters
    ----------
    scenario : CarrierScenario
    variants : mapping of str to mapping, optional
        Name to :func:`run_carrier` keywords (default: ``{"ekf": {"method":
        "ekf"}, "aekf": {"method": "aekf"}}``: both with the matched design,
        the AEKF with the paper's eq. (26)).
    seed, runs : int
    truth : CarrierTruth, optional
        Precomputed signals.
    **kwargs
        Passed to every :func:`run_carrier` call (``window``, ...).

    Returns
    -------
    dict of str to CarrierResult
    """
    variants = variants or {m: {"method": m} for m in METHODS}
    truth = truth if truth is not None else simulate_channel(scenario, seed, runs)
    return {
        name: run_carrier(scenario, seed=seed, runs=runs, truth=truth, **{**kwargs, **v})
        for name, v in variants.items()
    }
