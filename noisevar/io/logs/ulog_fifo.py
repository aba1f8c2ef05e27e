"""PX4's raw IMU FIFO topics (``sensor_gyro_fifo``, ``sensor_accel_fifo``), one row per sample.

Each message holds up to 32 samples of a FIFO read: ``x[]``, ``y[]``, ``z[]`` raw int16
counts, ``samples`` of them valid, ``dt`` µs apart, and ``scale`` (physical unit per count).
As PX4 defines them (PX4/PX4-Autopilot):

- ``msg/SensorGyroFifo.msg`` (at 500cfdf): ``float32 dt  # delta time between samples
  (microseconds)``, ``float32 scale  # rad/s per count``, ``uint8 samples  # number of valid
  samples``, ``int16[32] x  # FRD board frame X-axis raw counts (rad/s = x * scale)``;
  ``msg/SensorAccelFifo.msg`` likewise in m/s² (its consumer scales by ``scale`` too).
- Values: ``src/modules/sensors/vehicle_angular_velocity/VehicleAngularVelocity.cpp``,
  ``Run()``: ``data[n] = sensor_fifo_data.scale * raw_data_array[axis][n]`` for
  ``n < N = samples``, only when ``dt > 0`` and ``0 < N <= 32`` (else the message is
  skipped); ``VehicleAcceleration.cpp`` the same for the accelerometer.
- Times: the drivers stamp a message with the FIFO read's time (``ICM42688P::ProcessGyro``:
  ``gyro.timestamp_sample = timestamp_sample``, the read's ``hrt_absolute_time``), and
  ``src/lib/drivers/gyroscope/PX4Gyroscope.cpp``, ``updateFIFO``, integrates ``x[0] ..
  x[N-1]`` as equally spaced samples ending with ``x[N-1]`` and publishes that average at
  ``timestamp_sample``: the last sample is the newest. So sample ``k`` of ``N`` is at
  ``timestamp_sample - (N - 1 - k)·dt``.

A log whose FIFO message has no ``scale`` field (older PX4) is read in raw counts, with no
unit declared.
"""

from __future__ import annotations

import re

import numpy as np

#: The FIFO topics and the unit ``x * scale`` is in (their ``.msg`` comments).
FIFO_UNITS: dict[str, str] = {"sensor_gyro_fifo": "rad/s", "sensor_accel_fifo": "m/s**2"}
#: The unpacked fields, one value per sample.
AXES = ("x", "y", "z")
_SLOT = re.compile(r"^x\[(\d+)\]$")


def is_fifo(message: str, fields: dict) -> bool:
    """Whether ``message`` is a FIFO topic whose data has the fields to unpack."""
    return message in FIFO_UNITS and all(k in fields for k in ("samples", "dt", "x[0]"))


def units(message: str, fields: dict) -> dict[str, str]:
    """The unpacked fields' units (none without a ``scale`` field: raw counts)."""
    if "scale" not in fields:
        return {}
    return dict.fromkeys(AXES, FIFO_UNITS[message])


def _width(fields: dict) -> int:
    return 1 + max(int(m.group(1)) for k in fields if (m := _SLOT.match(k)))


def unpack(data: dict[str, np.ndarray], time_field: str) -> tuple[np.ndarray, dict]:
    """Every valid sample of every message: times (s) and ``x``, ``y``, ``z``.

    Parameters
    ----------
    data : dict of str to ndarray
        pyulog's arrays of the topic (``x[0]`` .. ``x[31]``, ``samples``, ``dt``, ...).
    time_field : str
        ``timestamp_sample`` (else ``timestamp``): the newest sample's time, µs.

    Returns
    -------
    t : ndarray
        Each sample's time in seconds, in order.
    values : dict of str to ndarray
        ``x``, ``y``, ``z`` times ``scale`` (raw counts without one).
    """
    width = _width(data)
    n = np.asarray(data["samples"], dtype=np.int64)
    dt = np.asarray(data["dt"], dtype=np.float64)
    ok = (n > 0) & (n <= width) & (dt > 0)  # what PX4's consumers accept
    n, dt = n[ok], dt[ok]
    stamp = np.asarray(data[time_field], dtype=np.int64)[ok]
    k = np.arange(width)
    valid = k[None, :] < n[:, None]
    # seconds from the first message in exact integers, then the within-message offset
    base = (stamp - (stamp[0] if stamp.size else 0)).astype(np.float64)
    offset = (n[:, None] - 1 - k[None, :]) * dt[:, None]
    t0 = float(stamp[0]) / 1e6 if stamp.size else 0.0
    t = t0 + (base[:, None] - offset)[valid] / 1e6
    scale = np.asarray(data["scale"], dtype=np.float64)[ok] if "scale" in data else None
    values = {}
    for ax in AXES:
        raw = np.column_stack([np.asarray(data[f"{ax}[{i}]"])[ok] for i in range(width)])
        raw = raw.astype(np.float64)
        values[ax] = (raw * scale[:, None] if scale is not None else raw)[valid]
    return t, values


def rate(data: dict[str, np.ndarray]) -> float | None:
    """The sample rate ``1e6 / median(dt)`` (Hz) of the valid messages."""
    dt = np.asarray(data["dt"], dtype=np.float64)
    dt = dt[dt > 0]
    return float(1e6 / np.median(dt)) if dt.size else None


def count(data: dict[str, np.ndarray]) -> int:
    """The number of valid samples."""
    n = np.asarray(data["samples"], dtype=np.int64)
    dt = np.asarray(data["dt"], dtype=np.float64)
    return int(n[(n > 0) & (n <= _width(data)) & (dt > 0)].sum())
