"""Imported by the fork server of ``batch(jobs=N)``: load the estimators' compiled code once.

Worker processes are forked from the server, so they start with ``noisevar`` and the
readers' libraries imported and the compiled (numba) kernels loaded, instead of each paying
for that (seconds) on its first file. The fork server dies with the batch that started it
(:mod:`noisevar.batch._lifeline`).
"""

from __future__ import annotations

import io

import numpy as np

import noisevar.batch._task  # noqa: F401 - the task function the workers run
from noisevar.batch._lifeline import follow_parent
from noisevar.estimators import estimate
from noisevar.io import load_table, pick_column

follow_parent()  # the fork server dies with the batch, and its workers with it

_buf = io.BytesIO()
np.save(_buf, np.random.default_rng(0).normal(size=(512, 2)))
# reading a small CSV and .npy imports what the readers import on first use (pandas)
for _raw, _name in ((b"t,x\n0,1.0\n1,1.5\n2,0.5\n", "warm.csv"), (_buf.getvalue(), "warm.npy")):
    load_table(_raw, _name)
# one small estimate loads the compiled kernels of the default method
estimate(pick_column(load_table(_buf.getvalue(), "warm.npy")))
