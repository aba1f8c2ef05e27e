"""Noise models of a record: Allan deviation and the inertial (IEEE-952) noise terms.

docs/algorithms.md §E4.
"""

from noisevar.noise_model.allan import AllanResult, allan
from noisevar.noise_model.inertial import InertialNoise, NoiseTerm, inertial_noise

__all__ = ["AllanResult", "InertialNoise", "NoiseTerm", "allan", "inertial_noise"]
