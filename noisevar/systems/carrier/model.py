"""The carrier EKF model and the AEKF's R/Q adaptation (docs/algorithms.md §B1)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from noisevar.errors import NoisevarError
from noisevar.kalman import KalmanFilter, ResidualQR, StateSpaceModel
from noisevar.kalman.strategies import MovingMean, ResidualR
from noisevar.systems.carrier.scenario import JERK_PSD, Q_RULES, R_STARTS, CarrierScenario


def carrier_model(
    scenario: CarrierScenario,
    control: NDArray[np.float64],
    jerk_psd: float = JERK_PSD,
    amplitude_walk: float = 1e-3,
    measurement_variance: float = 1.0,
) -> StateSpaceModel:
    """The EKF model of eq. (6) with the NCO's phase advance as control input.

    ``x(k+1) = F x(k) - [Δφ_NCO(k+1), 0, 0, 0]`` with
    ``F = [[1, T, T²/2, 0], [0, 1, T, 0], [0, 0, 1, 0], [0, 0, 0, 1]]``;
    ``h(x) = [A cos θ_e, A sin θ_e]``.

    Parameters
    ----------
    scenario : CarrierScenario
    control : ndarray, shape (B,)
        Holder the caller fills with the NCO phase advance of the coming
        step before each ``predict`` (a closure input).
    jerk_psd : float
        Spectral density of the white Doppler jerk (rad²/s⁵) of the fixed
        ``Q``; the default covers the scenario's manoeuvres (rate ramps of
        ``2π·25/0.5`` rad/s³).
    amplitude_walk : float
        Amplitude random-walk variance per step (relative to ``A²``).
    measurement_variance : float
        The filter's ``R = σ² I`` for the unit-variance I/Q noise: 1 is the
        truth; :func:`nominal_measurement_variance` gives a nominal design's.

    Returns
    -------
    StateSpaceModel
    """
    T = scenario.integration_s
    F = np.array(
        [[1.0, T, T * T / 2, 0.0], [0.0, 1.0, T, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    )
    q = jerk_psd
    Q = np.zeros((4, 4))
    Q[:3, :3] = q * np.array(
        [
            [T**5 / 20, T**4 / 8, T**3 / 6],
            [T**4 / 8, T**3 / 3, T**2 / 2],
            [T**3 / 6, T**2 / 2, T],
        ]
    )
    amp = scenario.amplitude
    Q[3, 3] = amplitude_walk * amp**2
    two_pi = 2 * np.pi
    x0 = np.array([0.0, two_pi * scenario.doppler_hz, 0.0, amp])
    P0 = np.diag(
        [
            (np.pi / np.sqrt(3)) ** 2,
            (two_pi * max(2.5 * scenario.initial_doppler_error_hz, 1.0)) ** 2,
            (two_pi * 10.0) ** 2,
            (0.3 * amp) ** 2,
        ]
    )

    def f(x: NDArray, k: int) -> NDArray:
        out = x @ F.T
        if x.shape[0] == control.shape[0]:  # (the core also probes f with one state)
            out[:, 0] -= control
        return out

    def F_jacobian(x: NDArray, k: int) -> NDArray:
        return F

    def h(x: NDArray, k: int) -> NDArray:
        return np.stack([x[:, 3] * np.cos(x[:, 0]), x[:, 3] * np.sin(x[:, 0])], axis=-1)

    def H_jacobian(x: NDArray, k: int) -> NDArray:
        c, s = np.cos(x[:, 0]), np.sin(x[:, 0])
        J = np.zeros((x.shape[0], 2, 4))
        J[:, 0, 0] = -x[:, 3] * s
        J[:, 0, 3] = c
        J[:, 1, 0] = x[:, 3] * c
        J[:, 1, 3] = s
        return J

    return StateSpaceModel(
        Q=Q,
        R=measurement_variance * np.eye(2),
        x0=x0,
        P0=P0,
        f=f,
        F_jacobian=F_jacobian,
        h=h,
        H_jacobian=H_jacobian,
        dt=T,
        state_names=("phase error", "doppler", "doppler rate", "amplitude"),
        measurement_names=("I", "Q"),
        name="carrier eq. (6)",
    )


def nominal_measurement_variance(cn0_dbhz: float, nominal_cn0_dbhz: float) -> float:
    """``R`` of a filter designed for ``nominal_cn0_dbhz`` when the signal is at ``cn0_dbhz``.

    The design's phase-noise variance ``R / A² = 1 / (2 (C/N0)_nom T)`` with
    unit-variance I/Q noise gives ``R = (C/N0) / (C/N0)_nom``.

    Parameters
    ----------
    cn0_dbhz : float
        Actual C/N0 (dB-Hz).
    nominal_cn0_dbhz : float
        Design C/N0 (dB-Hz).

    Returns
    -------
    float
        The filter's I/Q noise variance (the truth is 1).
    """
    if not (np.isfinite(nominal_cn0_dbhz) and nominal_cn0_dbhz > 0):
        raise NoisevarError(
            f"nominal C/N0 = {nominal_cn0_dbhz} dB-Hz: give the positive C/N0 the fixed EKF "
            "is designed for (for example 45)."
        )
    return float(10.0 ** ((cn0_dbhz - nominal_cn0_dbhz) / 10.0))


def nominal_jerk_psd(
    scenario: CarrierScenario, nominal_doppler_rate_hz_s: float, jerk_psd: float = JERK_PSD
) -> float:
    """Jerk density of a ``Q`` designed for manoeuvres of ``nominal_doppler_rate_hz_s``.

    With the same ramp time the density scales with the square of the peak
    rate: ``q_nom = jerk_psd · (rate_nom / rate)²``.

    Parameters
    ----------
    scenario : CarrierScenario
    nominal_doppler_rate_hz_s : float
        Peak Doppler rate the design assumes (Hz/s).
    jerk_psd : float
        Matched density (rad²/s⁵).

    Returns
    -------
    float
    """
    if not (np.isfinite(nominal_doppler_rate_hz_s) and nominal_doppler_rate_hz_s > 0):
        raise NoisevarError(
            f"nominal Doppler rate = {nominal_doppler_rate_hz_s} Hz/s: give the positive peak "
            "Doppler rate the fixed EKF is designed for."
        )
    if not scenario.doppler_rate_hz_s > 0:
        raise NoisevarError(
            "a nominal Doppler rate is scaled against the scenario's manoeuvres; this scenario "
            "has doppler_rate_hz_s = 0 (give jerk_psd directly instead)."
        )
    return float(jerk_psd * (nominal_doppler_rate_hz_s / scenario.doppler_rate_hz_s) ** 2)


class AdaptiveCarrierQR(ResidualQR):
    """The AEKF's adaptation: eq. (22) ``R`` and a choice of ``Q`` rules.

    ``R̂ = Ĉ_r + H P(k|k) Hᵀ`` over the last ``W`` residuals (eq. (22),
    :class:`~noisevar.kalman.ResidualQR`). ``Q``: ``q_rule="paper"`` is
    ``Q̂ = K Ĉ_d Kᵀ`` (eq. (26)); ``q_rule="scaled"`` scales the kinematic
    ``Q`` by ``λ``, moved by ``log λ += log(N̄) / W`` only when the windowed
    mean tangential NIS ``N̄`` leaves its ``χ²_W / W`` band.

    Parameters
    ----------
    window : int
        ``W`` of eq. (14) (``R̂``, ``Ĉ_d`` and the ``NIS_t`` window).
    adapt_r, adapt_q : bool
        Estimate ``R`` (eq. (22)) and ``Q``; both off gives the EKF.
    q_rule : {"paper", "scaled"}
        ``Q`` adaptation.
    q_bound : float
        ``λ`` stays within ``[1 / q_bound, q_bound]`` (``"scaled"``).
    coverage : float
        Probability of the ``χ²_W / W`` band inside which ``λ`` is left
        alone (``"scaled"``).
    r_start : {"design", "running"}
        Start of the windowed ``R̂``: a window full of the design ``R``, or
        the paper's running mean of the first residuals. The method as
        published is ``q_rule="paper", r_start="running"``.

    Attributes
    ----------
    q_scale : ndarray, shape (B,)
        Current ``λ`` per run (``"scaled"``).

    Notes
    -----
    See docs/algorithms.md §B1. Eq. (26) feeds on itself (each step adds the
    transition's covariance growth to ``Q``); the dead band of the scaled
    rule keeps ``λ ≈ 1`` when the design dynamics are right.
    """

    name = "aekf"

    def __init__(
        self,
        window: int = 50,
        adapt_r: bool = True,
        adapt_q: bool = True,
        q_rule: str = "paper",
        q_bound: float = 1e3,
        coverage: float = 0.99,
        r_start: str = "design",
    ) -> None:
        super().__init__(window=window, diagonal=True, warmup=1)
        if q_rule not in Q_RULES:
            raise NoisevarError(f"q_rule={q_rule!r}; choose 'paper' or 'scaled'.")
        if r_start not in R_STARTS:
            raise NoisevarError(f"r_start={r_start!r}; choose 'design' or 'running'.")
        if not (np.isfinite(q_bound) and q_bound > 1):
            raise NoisevarError(f"q_bound={q_bound} must be a finite number above 1.")
        if not 0 < coverage < 1:
            raise NoisevarError(f"coverage={coverage} is a probability in (0, 1).")
        self.adapt_r = bool(adapt_r)
        self.adapt_q = bool(adapt_q)
        self.q_rule = q_rule
        self.q_bound = float(q_bound)
        self.coverage = float(coverage)
        self.r_start = r_start
        a = (1.0 - coverage) / 2.0
        self._band = (
            float(stats.chi2.ppf(a, self.window) / self.window),
            float(stats.chi2.ppf(1.0 - a, self.window) / self.window),
        )

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        Q = filt.model.Q
        self._kinematic = Q.copy()
        self._kinematic[3, :] = self._kinematic[:, 3] = 0.0
        self._amplitude_q = Q - self._kinematic
        self.q_scale = np.ones(filt.batch_size)
        self._nis_t = MovingMean(self.window, (filt.batch_size,))
        self._R_design = np.array(filt.model.R)

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        return super().measurement_covariance(filt) if self.adapt_r else filt.model.R

    def process_covariance(self, filt: KalmanFilter) -> NDArray | None:
        if not self.adapt_q:
            return None
        if self.q_rule == "paper":
            return super().process_covariance(filt)
        return self._amplitude_q + self.q_scale[:, None, None] * self._kinematic

    def observe(self, filt: KalmanFilter) -> None:
        if self.q_rule == "paper":
            super().observe(filt)  # eq. (22) and eq. (26)
        else:
            ResidualR.observe(self, filt)  # eq. (22) only
        if self.r_start == "design":
            self._start_from_design()
        if self.q_rule == "paper" or not self.adapt_q:
            return
        if self.adapt_r and self.r_start == "design" and self._cov.count <= self.window:
            return  # this step's S used a design share of R: not evidence about Q
        theta = filt.x_pred[:, 0]
        t = np.stack([-np.sin(theta), np.cos(theta)], axis=-1)
        d_t = np.einsum("bi,bi->b", filt.innovation, t)
        s_t = np.einsum("bi,bij,bj->b", t, np.broadcast_to(filt.S, (t.shape[0], 2, 2)), t)
        self._nis_t.push(d_t * d_t / s_t)
        if self._nis_t.count < self.window:
            return
        mean = self._nis_t.mean()
        lo, hi = self._band
        outside = (mean < lo) | (mean > hi)
        if outside.any():
            step = np.where(outside, np.log(np.maximum(mean, 1e-300)) / self.window, 0.0)
            limit = np.log(self.q_bound)
            self.q_scale = np.exp(np.clip(np.log(self.q_scale) + step, -limit, limit))

    def _start_from_design(self) -> None:
        """``r_start="design"``: the window starts full of the design ``R``.

        After ``k < W`` residuals, ``R̂ = (1 - k/W) R_design + (k/W) R̂₂₂``
        with ``R̂₂₂`` eq. (22) over those ``k`` residuals (the running mean):
        the ``W - k`` window places no residual has filled yet still hold
        the design. From ``k = W`` on it is eq. (22) over the window.
        """
        k = self._cov.count
        if k >= self.window:
            return
        a = k / self.window
        self._R = (1.0 - a) * self._R_design + a * self._R


def _fold_amplitude(filt: KalmanFilter) -> None:
    """Keep the amplitude positive: ``(A, θ) -> (-A, θ + π)`` describe the same signal.

    The measurement ``[A cos θ, A sin θ]`` cannot tell the two apart; left
    free, an EKF that starts half a cycle off may lock with ``A < 0``. The
    fold is exact (a change of sign of one state), so the covariance follows
    with ``J P J``, ``J = diag(1, 1, 1, -1)``.
    """
    negative = filt.x[:, 3] < 0
    if not negative.any():
        return
    x, P = np.array(filt.x), np.array(filt.P)
    x[negative, 3] *= -1.0
    x[negative, 0] += np.pi
    flip = np.array([1.0, 1.0, 1.0, -1.0])
    P[negative] = P[negative] * flip[:, None] * flip[None, :]
    filt.x, filt.P = x, P
