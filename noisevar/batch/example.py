"""A small example fleet on disk: IMU-like logs of several sensors, one of them noisier."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

#: Channels of the example logs and their noise standard deviations.
EXAMPLE_CHANNELS = {"ax": 0.02, "ay": 0.02, "az": 0.05}


def write_example_fleet(
    folder: str | os.PathLike,
    n_sensors: int = 12,
    n: int = 3000,
    seed: int = 0,
    noisy: tuple[int, ...] = (4,),
    factor: float = 3.0,
) -> list[Path]:
    """Write ``n_sensors`` CSV logs (``time, ax, ay, az``) of a production line.

    Every sensor sees a slow random walk plus white noise of the standard deviation of
    :data:`EXAMPLE_CHANNELS`, within a ±5 % tolerance from unit to unit
    (uniform); the sensors whose index
    is in ``noisy`` have ``factor`` times more noise on ``ay``.

    Parameters
    ----------
    folder : str or path
        Where to write (created if needed).
    n_sensors, n : int
        Sensors (files) and samples per file (100 Hz).
    seed : int
        Random seed.
    noisy : tuple of int
        Indices of the faulty sensors.
    factor : float
        Their noise factor on ``ay``.

    Returns
    -------
    list of Path
        The files, ``imu_00.csv`` ...
    """
    root = Path(folder)
    root.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    stds = np.array(list(EXAMPLE_CHANNELS.values()))
    header = "time," + ",".join(EXAMPLE_CHANNELS)
    out = []
    for i in range(n_sensors):
        unit = stds * (1.0 + rng.uniform(-0.05, 0.05, stds.size))
        if i in noisy:
            unit[1] *= factor
        walk = np.cumsum(rng.normal(0.0, 0.002, (n, stds.size)), axis=0)
        data = walk + rng.standard_normal((n, stds.size)) * unit
        path = root / f"imu_{i:02d}.csv"
        np.savetxt(
            path, np.column_stack([t, data]), delimiter=",", header=header, comments="", fmt="%.6f"
        )
        out.append(path)
    return out
