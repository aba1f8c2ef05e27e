"""The noise a ROS message declares for its own fields: its covariance's diagonal.

A driver publishes ``sensor_msgs/Imu`` with ``angular_velocity_covariance``, a GNSS
receiver ``NavSatFix`` with ``position_covariance``; a ROS filter (robot_localization's
EKF and UKF) takes those numbers as its measurement noise R. Measured R against the
declared one says whether the filter is told the truth (docs/algorithms.md §E8, *Declared
noise*). Each entry maps a field to the element holding its variance (row-major 3x3 or 6x6
arrays: index ``4`` is the second diagonal element of a 3x3). NavSatFix's latitude and
longitude are in degrees while their covariance is in m² (east, north): not paired.
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
    "sensor_msgs/NavSatFix": {"altitude": "position_covariance.8"},
    "sensor_msgs/FluidPressure": {"fluid_pressure": "variance"},
    "sensor_msgs/Temperature": {"temperature": "variance"},
    "sensor_msgs/RelativeHumidity": {"relative_humidity": "variance"},
    "sensor_msgs/Illuminance": {"illuminance": "variance"},
    "nav_msgs/Odometry": {
        **_diagonal([f"pose.pose.position.{a}" for a in _XYZ], "pose.covariance", 6),
        **_diagonal([f"twist.twist.linear.{a}" for a in _XYZ], "twist.covariance", 6),
        **_diagonal([f"twist.twist.angular.{a}" for a in _XYZ], "twist.covariance", 6, 3),
    },
    "geometry_msgs/PoseWithCovarianceStamped": _diagonal(
        [f"pose.pose.position.{a}" for a in _XYZ], "pose.covariance", 6
    ),
    "geometry_msgs/TwistWithCovarianceStamped": {
        **_diagonal([f"twist.twist.linear.{a}" for a in _XYZ], "twist.covariance", 6),
        **_diagonal([f"twist.twist.angular.{a}" for a in _XYZ], "twist.covariance", 6, 3),
    },
}


def declared_fields(msgtype: str, fields: Sequence[str]) -> Mapping[str, str]:
    """Each of ``fields`` whose message declares its variance -> the field holding it."""
    table = DECLARED_VARIANCE.get(msgtype.replace("/msg/", "/"), {})
    return {f: table[f] for f in fields if f in table}
