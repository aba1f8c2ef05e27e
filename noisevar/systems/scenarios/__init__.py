"""Seeded scenarios: truth, measurements and a ready filter model.

Each generator returns a :class:`Scenario` holding ``B`` Monte Carlo runs
(same trajectory, independent noise), the true measurement covariance at
every step, the per-channel smoothing ``h`` for the SOMD estimator, and a
:meth:`Scenario.run` that filters all runs at once with any strategy.

* :func:`gps_circle` — the 2016 paper's section 3.2 (docs/algorithms.md §A9).
* :func:`noise_step`, :func:`noise_ramp` — a manoeuvring target whose
  position-noise standard deviation steps (ramps) up three-fold mid-run.
* :func:`outliers` — the same target with bursts of gross errors.
"""

from noisevar.systems.scenarios.gps import (
    GPS_CHANNELS,
    GPS_DURATION,
    GPS_H_SMOOTH,
    GPS_NOISE_STD,
    GPS_OMEGA,
    GPS_R0,
    GPS_RADIUS,
    GPS_T,
    gps_circle,
    gps_process_noise,
    gps_transition,
)
from noisevar.systems.scenarios.scenario import Scenario, constant_velocity_model
from noisevar.systems.scenarios.target import (
    TARGET_H_SMOOTH,
    TARGET_MANOEUVRES,
    TARGET_Q,
    TARGET_SIGMA,
    TARGET_STEPS,
    TARGET_T,
    noise_ramp,
    noise_step,
    outliers,
)

SCENARIOS = {
    "gps-circle": gps_circle,
    "noise-step": noise_step,
    "noise-ramp": noise_ramp,
    "outliers": outliers,
}

__all__ = [
    "GPS_CHANNELS",
    "GPS_DURATION",
    "GPS_H_SMOOTH",
    "GPS_NOISE_STD",
    "GPS_OMEGA",
    "GPS_R0",
    "GPS_RADIUS",
    "GPS_T",
    "SCENARIOS",
    "TARGET_H_SMOOTH",
    "TARGET_MANOEUVRES",
    "TARGET_Q",
    "TARGET_SIGMA",
    "TARGET_STEPS",
    "TARGET_T",
    "Scenario",
    "constant_velocity_model",
    "gps_circle",
    "gps_process_noise",
    "gps_transition",
    "noise_ramp",
    "noise_step",
    "outliers",
]
