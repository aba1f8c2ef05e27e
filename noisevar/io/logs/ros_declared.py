"""The noise a ROS message declares for its own fields: its covariance's diagonal.

A driver publishes ``sensor_msgs/Imu`` with ``angular_velocity_covariance``, a GNSS
receiver ``NavSatFix`` with ``position_covariance``; a ROS filter (robot_localization's
EKF and UKF) takes those numbers as its measurement noise R. Measured R against the
declared one says whether the filter is told the truth (docs/algorithms.md §E8, *Declared
noise*). Each entry maps a field to the element holding its variance (row-major 3x3 arrays:
index ``4`` is the second diagonal element). Only a sensor's own noise is paired: the
covariance of an estimate (``Odometry``, AMCL's ``PoseWithCovarianceStamped``) or of a GNSS
fix (``NavSatFix``) covers slow errors too (drift, multipath) that the sample-to-sample R
does not see, so a ratio to it would mislead.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence


def _diagonal(fields: Sequence[str], array: str, size: int, first: int = 0) -> dict[str, str]:
    """``fields[i]`` -> ``array.k`` for the diagonal elements ``first + i`` of a size x size."""
    return {f: f"{array}.{(first + i) * (size + 1)}" for i, f in enumerate(fields)}


_XYZ = ("x", "y", "z")
#: Message type (without ``/msg/``) -> field -> the field that holds its variance.
DECLARED_VARIANCE: dict[str, dict[str, str]] = {
    "sensor_msgs/Imu": {
        **_diagonal([f"angular_velocity.{a}" for a in _XYZ], "angular_velocity_covariance", 3),
        **_diagonal(
            [f"linear_acceleration.{a}" for a in _XYZ], "linear_acceleration_covariance", 3
        ),
    },
    "sensor_msgs/MagneticField": _diagonal(
        [f"magnetic_field.{a}" for a in _XYZ], "magnetic_field_covariance", 3
    ),
    "sensor_msgs/FluidPressure": {"fluid_pressure": "variance"},
    "sensor_msgs/Temperature": {"temperature": "variance"},
    "sensor_msgs/RelativeHumidity": {"relative_humidity": "variance"},
    "sensor_msgs/Illuminance": {"illuminance": "variance"},
}


def declared_fields(msgtype: str, fields: Sequence[str]) -> Mapping[str, str]:
    """Each of ``fields`` whose message declares its variance -> the field holding it."""
    table = DECLARED_VARIANCE.get(msgtype.replace("/msg/", "/"), {})
    return {f: table[f] for f in fields if f in table}
