"""MATLAB ``gyroparams``/``accelparams`` for ``imuSensor``: continuous-time terms.

Meaning, from MathWorks' documentation of ``gyroparams`` and ``accelparams`` (Navigation /
Sensor Fusion Toolbox): ``NoiseDensity`` in (rad/s)/√Hz and (m/s²)/√Hz, ``RandomWalk`` in
(rad/s)·√Hz and (m/s²)·√Hz (= rad/s²/√Hz, m/s³/√Hz), ``BiasInstability`` in rad/s and
m/s²; ``NoiseType`` "double-sided" (the default) draws white noise of std
``NoiseDensity·√(Fs/2)``, "single-sided" ``NoiseDensity·√Fs``. The Allan N is one-sided,
so the file sets ``'NoiseType', 'single-sided'`` (MathWorks' example "Inertial Sensor
Noise Analysis Using Allan Variance" does the same). Its B is the Allan-minimum B of
IEEE-952 (``scfB = sqrt(2*log(2)/pi)`` in that example), as ours.
"""

from __future__ import annotations

import re

from noisevar.noise_model.exports.base import Consumer, ExportFile, ascii_text, density, number
from noisevar.noise_model.exports.model import ImuModel

_CALL = re.compile(r"^(\w+)\s*=\s*(gyroparams|accelparams)\((.*)\);\s*$")


def write(model: ImuModel) -> ExportFile:
    """A MATLAB script defining ``gyro``, ``accel`` and ``imu`` (an ``imuSensor``)."""
    parts = {}
    values = []
    for var, fn, sensor in (
        ("gyro", "gyroparams", "gyroscope"),
        ("accel", "accelparams", "accelerometer"),
    ):
        vs = [
            density(model, sensor, "N", f"{var}.NoiseDensity"),
            density(model, sensor, "K", f"{var}.RandomWalk"),
            density(model, sensor, "B", f"{var}.BiasInstability"),
        ]
        values += vs
        args = ", ".join(f"'{v.name.split('.')[1]}', {number(v.value)}" for v in vs)
        parts[var] = (fn, args, vs)
    lines = [f"% {h}" for h in model.header("MATLAB imuSensor")]
    for var, (fn, args, vs) in parts.items():
        lines += [f"% {v.name}: {v.comment()}" for v in vs]
        lines.append(f"{var} = {fn}({args}, 'NoiseType', 'single-sided');")
    lines.append(
        f"imu = imuSensor('accel-gyro', 'SampleRate', {model.rate:g}, "
        "'Gyroscope', gyro, 'Accelerometer', accel);"
    )
    return ExportFile("matlab", "imu_params.m", ascii_text("\n".join(lines) + "\n"), tuple(values))


def parse(text: str) -> dict[str, float]:
    """``var.Name -> value`` of the script's ``gyroparams``/``accelparams`` calls.

    A small parser of the MATLAB subset written: ``%`` comments, ``v = f('Name', value,
    ...);`` with quoted names and numeric or quoted values; anything else is an error.
    """
    out = {}
    for line in text.splitlines():
        code = line.split("%", 1)[0].strip()
        if not code or code.startswith("imu = imuSensor("):
            continue
        m = _CALL.match(code)
        if not m:
            raise ValueError(f"not MATLAB this parser reads: {code!r}")
        args = [a.strip() for a in m.group(3).split(",")]
        if len(args) % 2:
            raise ValueError(f"odd name-value list: {code!r}")
        for name, value in zip(args[::2], args[1::2], strict=True):
            if not (name.startswith("'") and name.endswith("'")):
                raise ValueError(f"unquoted name {name!r}")
            if not value.startswith("'"):
                out[f"{m.group(1)}.{name[1:-1]}"] = float(value)
    return out


CONSUMER = Consumer("matlab", "MATLAB gyroparams/accelparams", "imu_params.m", write, parse)
