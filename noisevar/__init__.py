"""noisevar: how noisy is a measured signal, and what that means for a Kalman filter."""

from .errors import NoisevarError

__version__ = "0.1.0"
__all__ = ["NoisevarError", "__version__"]
