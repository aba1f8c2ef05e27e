"""The one exception type noisevar raises for bad input or bad parameters."""

from __future__ import annotations


class NoisevarError(ValueError):
    """Bad input or parameters, with a message that says what is wrong and what to do.

    Every user-facing check in :mod:`noisevar` raises this type, so a caller
    (the CLI, the dashboard, a notebook) can catch one exception and show its
    message as it is: one line, no traceback.
    """
