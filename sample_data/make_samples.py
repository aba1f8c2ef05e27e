"""Write the sample data files of ``sample_data/`` (seeded; never edit the outputs by hand).

Run from the repository root::

    python sample_data/make_samples.py

Files:

``fast_slow.csv``      t, z: the paper's Fig. 1 style signal, noise std 5.
``gps_circle.csv``     t, east, north, speed, heading: the vehicle of docs/algorithms.md §A9
                       (noise std 5 m, 5 m, √2 m/s, 0.01 rad), 3000 s at 0.5 s.
``noise_step.csv``     t, z: noise std steps from 5 to 15 mid-record.
``steps_ramps.csv``    z only, no header: ramps with jumps.
``two_sensors.csv``    t, sensor_a, sensor_b: one quantity, two sensors (noise
                       std 1 and 4) with slowly drifting biases.
``three_sensors.csv``  t, sensor_a, sensor_b, sensor_c (noise std 1, 2, 3).
``imu_temperature.csv``  t, gyro_x, gyro_y (deg/s), temp_c: a still gyro through a 30 min
                       chamber ramp 20 -> 45 °C at 5 Hz, bias 0.1 + 0.01 (T - 25) and
                       -0.05 - 0.004 (T - 25) deg/s, warm-up 0.2 exp(-t/120 s) on gyro_x,
                       white noise 0.005 deg/s/√Hz, temperature sensor noise 0.03 °C
                       (docs/algorithms.md §E9).
``gps_track.nmea``     GGA + RMC sentences of the circle (positions near
                       39.98 N 116.35 E, 1 Hz, noise std 5 m), valid checksums.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pynmea2

import noisevar

HERE = Path(__file__).resolve().parent
EARTH_RADIUS = 6_378_137.0


def _write_csv(name: str, header: list[str] | None, columns: list[np.ndarray]) -> None:
    with open(HERE / name, "w", newline="") as fh:
        w = csv.writer(fh)
        if header:
            w.writerow(header)
        for row in zip(*columns, strict=True):
            w.writerow([f"{v:.6f}" for v in row])


def _nmea_lat(lat: float) -> tuple[str, str]:
    d = int(abs(lat))
    return f"{d:02d}{(abs(lat) - d) * 60:07.4f}", "N" if lat >= 0 else "S"


def _nmea_lon(lon: float) -> tuple[str, str]:
    d = int(abs(lon))
    return f"{d:03d}{(abs(lon) - d) * 60:07.4f}", "E" if lon >= 0 else "W"


def imu_temperature() -> None:
    """``imu_temperature.csv`` (the Noise model page's temperature example)."""
    from noisevar.noise_model.simulate import simulate_thermal

    rate, n = 5.0, 9000
    t = np.arange(n) / rate
    temp = 20.0 + 25.0 * t / t[-1]
    noise = {"random_walk": 0.005}
    gx = simulate_thermal(temp, rate, polynomial=(0.1, 0.01), warmup=(0.2, 120.0), seed=61, **noise)
    gy = simulate_thermal(temp, rate, polynomial=(-0.05, -0.004), seed=62, **noise)
    measured = temp + np.random.default_rng(63).normal(0.0, 0.03, n)
    _write_csv("imu_temperature.csv", ["t", "gyro_x", "gyro_y", "temp_c"], [t, gx, gy, measured])


def main() -> None:
    """Write every sample file."""
    g = noisevar.generate("fast-slow", n=6000, seed=2016)
    _write_csv("fast_slow.csv", ["t", "z"], [g.t, g.measured])

    chans = {
        c: noisevar.generate("gps-circle", channel=c, seed=20 + i)
        for i, c in enumerate(["east", "north", "speed", "heading"])
    }
    t = chans["east"].t
    _write_csv(
        "gps_circle.csv",
        ["t", "east", "north", "speed", "heading"],
        [t] + [chans[c].measured for c in ["east", "north", "speed", "heading"]],
    )

    g = noisevar.generate("noise-step", n=6000, seed=7)
    _write_csv("noise_step.csv", ["t", "z"], [g.t, g.measured])

    g = noisevar.generate("steps-ramps", n=4000, seed=8)
    _write_csv("steps_ramps.csv", None, [g.measured])

    rng = np.random.default_rng(42)
    n = 5000
    t = np.arange(n) * 0.1
    truth = 50.0 * np.sin(2 * np.pi * t / 120.0) + 0.2 * t
    drift_a = 2.0 + 0.5 * np.sin(2 * np.pi * t / 400.0)
    drift_b = -1.0 + 0.01 * t
    a = truth + drift_a + rng.normal(0, 1.0, n)
    b = truth + drift_b + rng.normal(0, 4.0, n)
    _write_csv("two_sensors.csv", ["t", "sensor_a", "sensor_b"], [t, a, b])
    c = truth + rng.normal(0, 3.0, n)
    b2 = truth + drift_b + rng.normal(0, 2.0, n)
    _write_csv("three_sensors.csv", ["t", "sensor_a", "sensor_b", "sensor_c"], [t, a, b2, c])

    # NMEA: 1 Hz fixes of the circle, 5 m position noise, around a reference point
    lat0, lon0 = 39.98, 116.35
    n = 900
    tt = np.arange(n, dtype=float)
    omega, radius = np.pi / 100.0, 300.0
    east = radius * np.cos(omega * tt) + rng.normal(0, 5.0, n)
    north = radius * np.sin(omega * tt) + rng.normal(0, 5.0, n)
    lat = lat0 + np.degrees(north / EARTH_RADIUS)
    lon = lon0 + np.degrees(east / (EARTH_RADIUS * np.cos(np.radians(lat0))))
    speed_kn = (radius * omega + rng.normal(0, np.sqrt(2.0), n)) / 0.514444
    course = np.degrees(np.arctan2(np.cos(omega * tt), -np.sin(omega * tt))) % 360.0
    lines = []
    for k in range(n):
        secs = 36000 + k
        hhmmss = f"{secs // 3600:02d}{secs % 3600 // 60:02d}{secs % 60:02d}.00"
        la, ns = _nmea_lat(lat[k])
        lo, ew = _nmea_lon(lon[k])
        gga = pynmea2.GGA(
            "GP",
            "GGA",
            (hhmmss, la, ns, lo, ew, "1", "08", "0.9", "52.0", "M", "-8.0", "M", "", ""),
        )
        rmc = pynmea2.RMC(
            "GP",
            "RMC",
            (
                hhmmss,
                "A",
                la,
                ns,
                lo,
                ew,
                f"{speed_kn[k]:.2f}",
                f"{course[k]:.1f}",
                "221126",
                "",
                "",
            ),
        )
        lines += [str(gga), str(rmc)]
    (HERE / "gps_track.nmea").write_text("\n".join(lines) + "\n")
    imu_temperature()


if __name__ == "__main__":
    main()
