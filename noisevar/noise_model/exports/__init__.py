"""Each consumer's file from one IMU noise model (docs/algorithms.md §E7).

A consumer is one module of this package with a ``CONSUMER`` (:class:`Consumer`) and one
line in :data:`CONSUMERS`. Every value is written with its unit and a comment that says
whether it is a continuous-time density or a discrete std at a stated rate, and how it
was converted; each module's docstring cites the consumer's code that gives the meaning.
"""

from __future__ import annotations

import importlib
import io
import os
import zipfile
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from noisevar.errors import NoisevarError
from noisevar.noise_model.exports.base import Consumer, ExportFile, Value
from noisevar.noise_model.exports.model import (
    DEFAULT_VARIANT,
    VARIANTS,
    ImuModel,
    SensorTerms,
    composite_fits,
    imu_model,
)

#: The consumers, in the order files are listed: key -> module of this package.
CONSUMERS: dict[str, str] = {
    "kalibr": "kalibr",
    "openvins": "openvins",
    "vins": "vins",
    "orbslam3": "orbslam3",
    "robot_localization": "robot_localization",
    "px4": "px4",
    "ardupilot": "ardupilot",
    "matlab": "matlab",
    "filterpy": "filterpy",
}

__all__ = [
    "CONSUMERS",
    "DEFAULT_VARIANT",
    "VARIANTS",
    "Consumer",
    "ExportFile",
    "ImuModel",
    "SensorTerms",
    "Value",
    "composite_fits",
    "consumer",
    "consumers",
    "export",
    "imu_model",
    "write_exports",
    "zip_exports",
]


def consumer(key: str) -> Consumer:
    """The registered consumer ``key``."""
    if key not in CONSUMERS:
        raise NoisevarError(f"unknown consumer {key!r}; known: {', '.join(CONSUMERS)}, all")
    return importlib.import_module(f"{__name__}.{CONSUMERS[key]}").CONSUMER


def consumers(spec: str | Iterable[str]) -> list[str]:
    """The consumer keys of ``"px4,kalibr"``, ``"all"`` or a list; unknown ones refused."""
    keys = [k.strip() for k in spec.split(",")] if isinstance(spec, str) else list(spec)
    keys = [k for k in keys if k]
    if keys == ["all"]:
        return list(CONSUMERS)
    if not keys:
        raise NoisevarError(f"no consumer named; known: {', '.join(CONSUMERS)}, all")
    for k in keys:
        consumer(k)
    return list(dict.fromkeys(keys))


def export(
    model: ImuModel,
    keys: str | Iterable[str] = "all",
    options: Mapping[str, Any] | None = None,
    params: Mapping[str, float] | None = None,
) -> list[ExportFile]:
    """Each consumer's file of ``model``; ``options`` maps a key to its writer's options;
    ``params``: the flight log's parameters (:func:`noisevar.io.logs.params.log_parameters`),
    each writer given those it reads (:attr:`Consumer.log_params`: the EKF's step)."""
    opts = options or {}
    out = []
    for k in consumers(keys):
        c = consumer(k)
        given = {n: params[n] for n in c.log_params if params and n in params}
        extra = {"params": given} if given else {}
        out.append(c.write(model, **extra, **opts.get(k, {})))
    return out


def write_exports(files: Iterable[ExportFile], out: str | os.PathLike) -> list[Path]:
    """Write ``files`` into the directory ``out`` (made if missing); the paths written."""
    root = Path(out)
    if root.exists() and not root.is_dir():
        raise NoisevarError(f"--out {str(root)!r} is a file, not a directory")
    root.mkdir(parents=True, exist_ok=True)
    paths = []
    for f in files:
        p = root / f.filename
        p.write_text(f.text, encoding="utf-8")
        paths.append(p)
    return paths


def zip_exports(files: Iterable[ExportFile]) -> bytes:
    """All ``files`` in one zip archive (for a single download)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for f in files:
            z.writestr(f.filename, f.text)
    return buf.getvalue()
