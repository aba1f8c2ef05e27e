"""A ROS Imu topic's sensors are found by their declared units: ``noisevar imu`` fits the six
inertial axes (not the orientation quaternion) and the Noise model page's pickers start on
them, as ``--export`` takes them (one rule: ``noisevar.units.sensor_columns``)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from logfiles import imu_values
from streamlit.testing.v1 import AppTest

from noisevar.cli import main
from noisevar.units import sensor_columns

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
GYRO = [f"angular_velocity.{a}" for a in "xyz"]
ACCEL = [f"linear_acceleration.{a}" for a in "xyz"]


def _bag(path: Path, n: int = 2000) -> Path:
    """A ROS 2 Imu topic whose orientation varies (an AHRS's output beside the sensors)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    ty = store.types
    imu, hdr = ty["sensor_msgs/msg/Imu"], ty["std_msgs/msg/Header"]
    tm, vec = ty["builtin_interfaces/msg/Time"], ty["geometry_msgs/msg/Vector3"]
    quat = ty["geometry_msgs/msg/Quaternion"]
    z = imu_values(n, seed=5)
    q = np.cumsum(np.random.default_rng(6).normal(0, 1e-3, size=(n, 3)), axis=0)
    w = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    w.open()
    conn = w.add_connection("/imu", imu.__msgtype__, typestore=store)
    cov = np.zeros(9)
    for i in range(n):
        ns = 1_700_000_000 * 10**9 + i * 2_500_000
        msg = imu(
            header=hdr(stamp=tm(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="imu"),
            orientation=quat(x=q[i, 0], y=q[i, 1], z=q[i, 2], w=1.0), orientation_covariance=cov,
            angular_velocity=vec(x=z[i, 0], y=z[i, 1], z=z[i, 2]), angular_velocity_covariance=cov,
            linear_acceleration=vec(x=z[i, 3], y=z[i, 4], z=z[i, 5]),
            linear_acceleration_covariance=cov,
        )  # fmt: skip
        w.write(conn, ns, store.serialize_cdr(msg, imu.__msgtype__))
    w.close()
    return next(path.glob("*.mcap"))


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> Path:
    return _bag(tmp_path_factory.mktemp("b") / "b")


def test_sensor_columns_by_unit():
    units = {"orientation.x": None, "angular_velocity.x": "rad/s", "t": "s",
             "linear_acceleration.x": "m/s**2", "w": "deg/s", "a": "g"}  # fmt: skip
    assert sensor_columns(units) == (["angular_velocity.x", "w"], ["linear_acceleration.x", "a"])


def test_imu_command_fits_the_inertial_axes_only(bag, capsys):
    code = main(["imu", str(bag), "--topic", "/imu"])
    out, err = capsys.readouterr()
    assert code == 0 and not err
    fitted = [line.split(":")[0] for line in out.splitlines() if "samples at" in line]
    assert fitted == GYRO + ACCEL
    assert "left out: orientation.x, orientation.y, orientation.z (give --columns" in out
    code = main(["imu", str(bag), "--topic", "/imu", "--columns", "orientation.x"])
    out, _ = capsys.readouterr()
    assert code == 0 and [ln.split(":")[0] for ln in out.splitlines() if "samples at" in ln] == [
        "orientation.x"
    ]


def test_noise_model_pickers_start_on_the_sensors(bag):
    at = AppTest.from_file(APP, default_timeout=180)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(("robot.mcap", bag.read_bytes(), "")).run()
    at.switch_page("app_pages/Noise_model.py").run()
    assert not at.error
    assert at.multiselect(key="nm_gyro").value == GYRO
    assert at.multiselect(key="nm_accel").value == ACCEL
    assert any("gyroscope_noise_density" in c.value for c in at.code)  # Kalibr's imu.yaml
    # the file opens on its first sensor channel, not the orientation an AHRS fills
    assert at.session_state["nv_signal"].column == "angular_velocity.x"


def _phyphox_csv(path: Path, n: int = 3000) -> Path:
    """A phone's gyroscope and accelerometer as phyphox writes them: three axes and their
    norm ("Absolute"), 9 significant digits, in one table."""
    rng = np.random.default_rng(11)
    g = rng.normal(0, 0.01, (n, 3))
    a = rng.normal(0, 0.05, (n, 3)) + [0.0, 0.0, 9.81]
    cols = [np.arange(n) * 0.005, *g.T, np.linalg.norm(g, axis=1), *a.T, np.linalg.norm(a, axis=1)]
    gyro = [f"Gyroscope {x} (rad/s)" for x in "xyz"]
    accel = [f"Acceleration {x} (m/s^2)" for x in "xyz"]
    head = ["Time (s)", *gyro, "Absolute (rad/s)", *accel, "Absolute acceleration (m/s^2)"]
    np.savetxt(path, np.column_stack(cols), delimiter=",", fmt="%.9E", comments="",
               header=",".join(head))  # fmt: skip
    return path


def test_a_norm_column_is_no_axis(tmp_path, capsys):
    """phyphox's "Absolute" columns are the norm of the axes: not fitted, not exported."""
    path = _phyphox_csv(tmp_path / "phone.csv")
    import json

    from noisevar.io import load_table

    assert main(["imu", str(path), "--format", "json"]) == 0
    fitted = json.loads(capsys.readouterr().out)["columns"]
    assert len(fitted) == 6 and not any("Absolute" in c for c in fitted)
    assert main(["imu", str(path), "--kalibr", str(tmp_path / "imu.yaml")]) == 0
    assert "--gyro Gyroscope x (rad/s)" in capsys.readouterr().out
    assert (tmp_path / "imu.yaml").exists()

    table = load_table(path)
    gyro, accel = sensor_columns(table.units, table.columns)
    assert gyro == [f"Gyroscope {x} (rad/s)" for x in "xyz"]
    assert accel == [f"Acceleration {x} (m/s^2)" for x in "xyz"]
    assert len(sensor_columns(table.units)[1]) == 4  # without the data: by unit alone


def test_columns_of_several_lengths_have_no_norm():
    from noisevar.units import norm_columns

    data = {"x": np.ones(5), "y": np.ones(5), "n": np.full(4, np.sqrt(2))}
    assert norm_columns(data, ["x", "y", "n"]) == []
    data["n"] = np.full(5, np.sqrt(2))
    assert norm_columns(data, ["x", "y", "n"]) == ["n"]
