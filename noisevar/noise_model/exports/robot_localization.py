"""robot_localization: the ``sensor_msgs/Imu`` covariance fields and ``process_noise_covariance``.

Meaning, from robot_localization's code (cra-ros-pkg/robot_localization, ros2 at 1cb9533):
``src/ros_filter.cpp:588-605`` copies the message's ``angular_velocity_covariance`` (and
the acceleration's) into the measurement covariance R of each message: the per-message
variance at the IMU rate, ``σ² = N² f`` (``sensor_msgs/Imu.msg``: "covariance of the
measurement", row-major 3x3). ``src/ekf.cpp:435-436`` adds ``delta_sec *
process_noise_covariance`` per prediction: a variance per second. Its defaults
(``src/filter_base.cpp:111-125``; ``params/ekf.yaml``: x y z roll pitch yaw vx vy vz vroll
vpitch vyaw ax ay az, diagonal form allowed) model the vehicle's motion.

Ambiguity, said in the file: robot_localization has no IMU bias state, so the bias random
walk the IMU adds to the rate it reports can only go into the process noise of the states
the IMU measures (vroll, vpitch, vyaw: ``K_g²``; ax, ay, az: ``K_a²``, (unit/s)²/s). They are
ADDED to the package's defaults, which stay for the vehicle's own motion.
"""

from __future__ import annotations

from noisevar import units
from noisevar.noise_model.exports.base import Consumer, ExportFile, Value, discrete, number
from noisevar.noise_model.exports.model import ImuModel

#: The package's default process noise diagonal (src/filter_base.cpp:111-125).
DEFAULTS = (
    0.05,
    0.05,
    0.06,
    0.03,
    0.03,
    0.06,
    0.025,
    0.025,
    0.04,
    0.01,
    0.01,
    0.02,
    0.01,
    0.01,
    0.015,
)
STATES = (
    "x",
    "y",
    "z",
    "roll",
    "pitch",
    "yaw",
    "vx",
    "vy",
    "vz",
    "vroll",
    "vpitch",
    "vyaw",
    "ax",
    "ay",
    "az",
)


def write(model: ImuModel) -> ExportFile:
    """The IMU message covariances and the process noise diagonal."""
    f = model.rate
    g, a = model.gyro, model.accel
    values = [
        Value(
            "angular_velocity_covariance",
            units.sigma_at(g.N, f) ** 2,
            units.variance_label(g.unit),
            discrete(f),
            f"(N sqrt(f))^2 = {g.N:.6g}^2 x {f:g}",
        ),
        Value(
            "linear_acceleration_covariance",
            units.sigma_at(a.N, f) ** 2,
            units.variance_label(a.unit),
            discrete(f),
            f"(N sqrt(f))^2 = {a.N:.6g}^2 x {f:g}",
        ),
    ]
    diag = list(DEFAULTS)
    for i, state in enumerate(STATES):
        s = g if state.startswith("v") and state[1:] in ("roll", "pitch", "yaw") else a
        if state in ("vroll", "vpitch", "vyaw", "ax", "ay", "az"):
            diag[i] += s.K**2
            values.append(
                Value(
                    f"process_noise_covariance[{state}]",
                    diag[i],
                    f"({units.term_unit(s.unit, 'R')})²/Hz",
                    "variance per second",
                    f"default {DEFAULTS[i]:g} + K^2 = {s.K:.6g}^2",
                    s.k_withheld,
                )
            )
    lines = [f"# {h}" for h in model.header("robot_localization")]
    lines += [
        "# sensor_msgs/Imu covariance fields: set them in the IMU driver (row-major 3x3),",
        "# per message at the IMU rate.",
        "# AMBIGUOUS: robot_localization has no IMU bias state; the bias random walk K^2 is",
        "# added to its default process noise of the states the IMU measures.",
    ]
    lines += [
        "# imu_driver: rename to your IMU driver's node (ROS 2 parameter file layout), or",
        "# fill the message's fields in the driver's code.",
        "imu_driver:",
        "  ros__parameters:",
    ]
    for v in values[:2]:
        row = ", ".join(number(v.value) if i % 4 == 0 else "0.0" for i in range(9))
        lines += [f"    # {v.comment()}", f"    {v.name}: [{row}]"]
    lines += ["ekf_filter_node:", "  ros__parameters:", "    # diagonal: " + " ".join(STATES)]
    lines += [f"    # {v.name}: {v.comment()}" for v in values[2:]]
    lines.append(f"    process_noise_covariance: [{', '.join(number(d) for d in diag)}]")
    return ExportFile(
        "robot_localization", "robot_localization.yaml", "\n".join(lines) + "\n", tuple(values)
    )


def parse(text: str) -> dict[str, float]:
    """The covariances and the process noise entries of the file (YAML)."""
    import yaml

    d = yaml.safe_load(text)
    out = {k: float(v[0]) for k, v in d["imu_driver"]["ros__parameters"].items()}
    diag = d["ekf_filter_node"]["ros__parameters"]["process_noise_covariance"]
    out.update(
        {f"process_noise_covariance[{s}]": float(x) for s, x in zip(STATES, diag, strict=True)}
    )
    return out


CONSUMER = Consumer(
    "robot_localization",
    "robot_localization IMU covariances and Q",
    "robot_localization.yaml",
    write,
    parse,
)
