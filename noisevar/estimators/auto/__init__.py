"""``auto``, our default estimator, in one folder (docs/algorithms.md §F5).

- :mod:`~noisevar.estimators.auto.core`: the estimator (residuals, spans per block,
  block sums, the estimate) and its finishing step;
- :mod:`~noisevar.estimators.auto._trim`: outliers and jumps flagged and left out;
- :mod:`~noisevar.estimators.auto._quantised`: the correction of a quantised record at
  low noise (§E3), loaded only when a record is on a grid;
- :mod:`~noisevar.estimators.auto.chunked`: its engine for a record read in chunks.

:data:`AUTO` declares them on one :class:`~noisevar.estimators.spec.MethodSpec`:
``func``, ``coloured_params``, ``chunked`` and ``finish``.
"""

from __future__ import annotations

from noisevar.estimators.auto._trim import AUTO_BLOCK
from noisevar.estimators.auto.chunked import CHUNK, ChunkedAuto, chunks
from noisevar.estimators.auto.core import (
    AUTO_COLOURED_SPAN,
    AUTO_SPANS,
    AutoPart,
    auto_estimate,
    auto_method,
    auto_part,
    auto_reduce,
    auto_spans,
    finish_quantised,
    jump_mask,
)
from noisevar.estimators.spec import MethodSpec
from noisevar.numeric.fir import residual_sequence

__all__ = [
    "AUTO",
    "AUTO_BLOCK",
    "AUTO_COLOURED_SPAN",
    "AUTO_SPANS",
    "CHUNK",
    "AutoPart",
    "ChunkedAuto",
    "auto_estimate",
    "auto_part",
    "auto_reduce",
    "auto_spans",
    "chunks",
    "jump_mask",
    "residual_sequence",
]

AUTO = MethodSpec(
    "auto",
    "robust zero-lag polynomial virtual sensor (our default)",
    "ours",
    auto_method,
    ("span", "order", "trim"),
    coloured_params={"span": AUTO_COLOURED_SPAN},
    chunked=ChunkedAuto,
    finish=finish_quantised,
    residual=lambda p: residual_sequence(p["span"], p["order"]),
)
