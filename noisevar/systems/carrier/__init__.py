"""Adaptive-EKF carrier tracking of a weak GPS L1 C/A signal (docs/algorithms.md §B1).

One tracking channel after acquisition, simulated at baseband: each
integration period the prompt correlator gives ``I + jQ``; an EKF with the
state ``[θ_e, ω, ω̇, A]`` (phase error, Doppler, Doppler rate, amplitude)
tracks it and steers the NCO. ``ekf`` keeps its design ``R`` and ``Q``;
``aekf`` (:class:`AdaptiveCarrierQR`) adapts them from windowed residuals.

Submodules: :mod:`~noisevar.systems.carrier.scenario` (scenario and truth),
:mod:`~noisevar.systems.carrier.model` (EKF model, AEKF adaptation),
:mod:`~noisevar.systems.carrier.run` (:func:`run_carrier`, :func:`compare`),
:mod:`~noisevar.systems.carrier.sweep` (:func:`cn0_sweep`, :func:`slip_rates`).

Notes
-----
Measured results of the method live in ``BENCHMARKS.md``.
"""

from noisevar.systems.carrier.model import (
    AdaptiveCarrierQR,
    carrier_model,
    nominal_jerk_psd,
    nominal_measurement_variance,
)
from noisevar.systems.carrier.run import CarrierResult, compare, comparison_variants, run_carrier
from noisevar.systems.carrier.scenario import (
    JERK_PSD,
    L1_HZ,
    METHODS,
    Q_RULES,
    R_STARTS,
    CarrierScenario,
    CarrierTruth,
    doppler_profile,
    simulate_channel,
)
from noisevar.systems.carrier.sweep import (
    CarrierSweep,
    SlipRates,
    cn0_sweep,
    slip_rates,
    wilson_interval,
)

__all__ = [
    "JERK_PSD",
    "L1_HZ",
    "METHODS",
    "Q_RULES",
    "R_STARTS",
    "AdaptiveCarrierQR",
    "CarrierResult",
    "CarrierScenario",
    "CarrierSweep",
    "CarrierTruth",
    "SlipRates",
    "carrier_model",
    "cn0_sweep",
    "compare",
    "comparison_variants",
    "doppler_profile",
    "nominal_jerk_psd",
    "nominal_measurement_variance",
    "run_carrier",
    "simulate_channel",
    "slip_rates",
    "wilson_interval",
]
