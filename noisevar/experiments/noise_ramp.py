"""``noisevar experiment noise-ramp``: tracking a noise level that ramps up three-fold.

Scenario :func:`noisevar.systems.scenarios.noise_ramp` (the noise-step target;
the position-noise std ramps linearly from 5 m to 15 m between 40 % and 60 %
of the record). Options, metrics and JSON are those of
:mod:`noisevar.experiments.noise_step`; R tracking is scored from the end of
the ramp plus ``--settle`` steps.
"""

from __future__ import annotations

from noisevar.experiments import Experiment
from noisevar.experiments.noise_step import add_arguments, format_table, make_run

EXPERIMENT = Experiment(
    name="noise-ramp",
    help="manoeuvring target whose noise std ramps up 3x mid-run: R tracking and RMSE",
    run=make_run("noise-ramp"),
    add_arguments=add_arguments,
    default_runs=20,
    format_table=format_table,
)
