"""PX4's raw IMU FIFO topics unpacked to one row per sample (noisevar/io/logs/ulog_fifo.py),
on ULogs written by pyulog's own writer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from logfiles import write_ulog_fifo

from noisevar.cli import main
from noisevar.io import load_table
from noisevar.io.logs import ulog

PX4 = Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg"
DT_US = 125.0  # 8 kHz
SCALE = 1.0e-3 * np.pi / 180  # rad/s per count: an odd float32


def _log(tmp_path, m=60, seed=0, scale=SCALE, name="sensor_gyro_fifo", sigma=400.0):
    rng = np.random.default_rng(seed)
    counts = np.clip(np.round(sigma * rng.standard_normal((m, 3, 32))), -32768, 32767)
    samples = np.full(m, 8)
    samples[[5, 9]] = [3, 32]  # a short read, a full one
    samples[[7, 11, 13]] = [0, 40, 8]  # no samples; more than the array holds: skipped
    dt = np.full(m, DT_US)
    dt[13] = 0.0  # no time step: skipped, as PX4's consumers do
    stamps = 5_000_000 + np.cumsum(samples * DT_US).astype(np.int64)
    path = tmp_path / "fifo.ulg"
    counts = counts.astype(np.int16)
    write_ulog_fifo(path, counts, samples, dt, scale, stamps, name=name, base=PX4)
    return path, counts, samples, dt, stamps


def _expected(counts, samples, dt, stamps, scale):
    t, x = [], []
    for i, n in enumerate(samples):
        if not (0 < n <= 32 and dt[i] > 0):
            continue
        k = np.arange(n)
        t.append((stamps[i] - (n - 1 - k) * dt[i]) / 1e6)
        x.append(counts[i, 0, :n] * (np.float32(scale) if scale is not None else 1.0))
    return np.concatenate(t), np.concatenate(x)


def test_each_sample_at_its_time_in_rad_per_s(tmp_path):
    path, counts, samples, dt, stamps = _log(tmp_path)
    info = next(t for t in ulog.topics(path) if t.name == "sensor_gyro_fifo")
    t_want, x_want = _expected(counts, samples, dt, stamps, SCALE)
    assert info.fields == ("x", "y", "z") and info.units == dict.fromkeys("xyz", "rad/s")
    assert info.count == t_want.size and info.rate == pytest.approx(8000.0)
    table = load_table(path, topic="sensor_gyro_fifo")
    assert table.units["x"] == "rad/s" and table.n_rows == t_want.size
    chunks = list(ulog.read(path, "sensor_gyro_fifo", None))
    t = np.concatenate([c.times for c in chunks])
    x = np.concatenate([c.values["x"] for c in chunks])
    np.testing.assert_allclose(t, t_want, rtol=0, atol=1e-9)
    np.testing.assert_allclose(x, x_want, rtol=1e-6)
    assert np.all(np.diff(t) > 0)  # in time order
    assert table.sample_period == pytest.approx(DT_US / 1e6)


def test_accel_fifo_and_an_old_log_without_scale(tmp_path):
    path, counts, samples, dt, stamps = _log(tmp_path, name="sensor_accel_fifo", scale=None)
    info = next(t for t in ulog.topics(path) if t.name == "sensor_accel_fifo")
    assert info.fields == ("x", "y", "z") and info.units == {}  # raw counts: no unit
    x = np.concatenate([c.values["x"] for c in ulog.read(path, "sensor_accel_fifo", ["x"])])
    np.testing.assert_array_equal(x, _expected(counts, samples, dt, stamps, None)[1])


def test_noise_density_from_a_fifo_topic(tmp_path, capsys):
    """White counts of std 400 at 8 kHz: N = 400 · scale / sqrt(8000) rad/s/√Hz."""
    path, *_ = _log(tmp_path, m=500, seed=3)
    argv = ["imu", str(path), "--topic", "sensor_gyro_fifo", "--columns", "x", "--format", "json"]
    assert main(argv) == 0
    fit = json.loads(capsys.readouterr().out)["columns"]["x"]
    n = fit["terms"]["random_walk"]
    assert fit["unit"] == "rad/s" and fit["rate"] == pytest.approx(8000.0)
    assert n["value"] == pytest.approx(400 * np.float32(SCALE) / np.sqrt(8000), rel=0.05)
