"""Imported once by the worker pool's fork server (:mod:`dashboard.workers`): warm start.

Importing noisevar and running one small estimate of each quick kind loads the libraries
and compiles the kernels once, in the fork server; every worker forked from it starts
warm (a first request on a cold worker otherwise pays about two seconds). The fork server
also exits as soon as the server that started it is gone (Python's own fork server
outlives a killed parent); its workers follow it (``dashboard.workers``).
"""

from __future__ import annotations

import os
import threading
import time

import numpy as np

import noisevar
from noisevar.errors import NoisevarError
from noisevar.estimators.compare import SLOW_METHODS


def warm() -> None:
    """One estimate of every kind on a short record (errors ignored: warming only)."""
    z = np.random.default_rng(0).normal(size=2000)
    for method in noisevar.methods():
        if method in SLOW_METHODS:
            continue
        try:
            noisevar.estimate(z, method=method)
        except (NoisevarError, ValueError, TypeError):
            pass


def exit_with(parent: int) -> None:
    """Exit this process (the fork server) when ``parent`` is no longer its parent."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(0)

    threading.Thread(target=watch, name="noisevar-parent-watch", daemon=True).start()


exit_with(os.getppid())
warm()
