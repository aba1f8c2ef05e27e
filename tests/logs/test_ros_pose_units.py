"""Units of ROS poses, velocities and forces: their definitions state none, REP 103 does
(metre, m/s, rad/s, newton); a quaternion has none. evo's and blobjugglerpy's bags
(benchmarks/real_audit4.py, issue 26) carry odometry, poses and wrenches."""

from __future__ import annotations

import numpy as np

from noisevar.io import load_table
from noisevar.io.logs import list_topics


def _odometry_bag(path, n: int = 40):
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    ty = store.types
    odo, pose_st = ty["nav_msgs/msg/Odometry"], ty["geometry_msgs/msg/PoseStamped"]
    hdr, tm = ty["std_msgs/msg/Header"], ty["builtin_interfaces/msg/Time"]
    point, quat, vec = (ty[f"geometry_msgs/msg/{k}"] for k in ("Point", "Quaternion", "Vector3"))
    pose, twist = ty["geometry_msgs/msg/Pose"], ty["geometry_msgs/msg/Twist"]
    pcov, tcov = (
        ty["geometry_msgs/msg/PoseWithCovariance"],
        ty["geometry_msgs/msg/TwistWithCovariance"],
    )
    rng = np.random.default_rng(0)
    w = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    w.open()
    c_odo = w.add_connection("/odom", odo.__msgtype__, typestore=store)
    c_pose = w.add_connection("/pose", pose_st.__msgtype__, typestore=store)
    for i in range(n):
        ns = 1_700_000_000 * 10**9 + i * 50_000_000
        h = hdr(stamp=tm(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="odom")
        x, v = rng.normal(size=2)
        p = pose(position=point(x=x, y=0.0, z=0.0), orientation=quat(x=0.0, y=0.0, z=0.0, w=1.0))
        tw = twist(linear=vec(x=v, y=0.0, z=0.0), angular=vec(x=0.0, y=0.0, z=0.1))
        msg = odo(header=h, child_frame_id="base", pose=pcov(pose=p, covariance=np.zeros(36)),
                  twist=tcov(twist=tw, covariance=np.zeros(36)))  # fmt: skip
        w.write(c_odo, ns, store.serialize_cdr(msg, odo.__msgtype__))
        w.write(c_pose, ns, store.serialize_cdr(pose_st(header=h, pose=p), pose_st.__msgtype__))
    w.close()
    return path


def test_odometry_and_pose_units(tmp_path):
    bag = _odometry_bag(tmp_path / "bag")
    topics = {t.name: t for t in list_topics(bag)}
    odo = topics["/odom"].units
    assert odo["pose.pose.position.x"] == "m" and odo["twist.twist.linear.x"] == "m/s"
    assert odo["twist.twist.angular.z"] == "rad/s"
    assert "pose.pose.orientation.w" not in odo  # a quaternion has no unit
    assert topics["/pose"].units == {f"pose.position.{a}": "m" for a in "xyz"}
    tab = load_table(bag, topic="/odom", fields=["twist.twist.linear.x"])
    assert tab.units == {"twist.twist.linear.x": "m/s"}
