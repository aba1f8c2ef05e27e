"""``noisevar experiment noise-ramp``: tracking a noise level that ramps up three-fold.

The noise-step target with the std ramping from 5 m to 15 m between 40 % and
60 % of the record (:func:`noisevar.systems.scenarios.noise_ramp`); parameters,
metrics and JSON are those of :mod:`noisevar.experiments.noise_step`.
"""

from __future__ import annotations

from noisevar.experiments.noise_step import noise_change_experiment

EXPERIMENT = noise_change_experiment(
    "noise-ramp", "manoeuvring target whose noise std ramps up 3x mid-run: R tracking and RMSE"
)
