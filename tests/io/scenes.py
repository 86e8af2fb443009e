"""A simulated room seen by simulated lasers, written into bags shaped like real robots' (rosbags' writers).

The room is a rectangle of walls with a box in it (line segments); a laser
at a pose in the room casts its beams and reads the distance to the nearest
wall (``inf`` beyond ``range_max``). :func:`write_robot_bag` writes what a
robot would record of it: scans on their topics in their frames, ``/tf``
and ``/tf_static``, odometry.
"""

import math
import shutil

import numpy as np

from .bag_files import _header, _make, store

#: the room: x from -3 to 5, y from -2 to 4, with a box from (1, 1) to (2, 1.5)
WALLS = [((-3, -2), (5, -2)), ((5, -2), (5, 4)), ((5, 4), (-3, 4)), ((-3, 4), (-3, -2)),
         ((1, 1), (2, 1)), ((2, 1), (2, 1.5)), ((2, 1.5), (1, 1.5)), ((1, 1.5), (1, 1))]
#: a convex room (no box): seen from inside, nothing hides anything
CONVEX = WALLS[:4]


def cast(origin, directions, walls=WALLS, range_max=30.0) -> np.ndarray:
    """The distance from ``origin`` (x, y) along each direction (rad, world frame) to the nearest wall."""
    d = np.stack([np.cos(directions), np.sin(directions)], axis=1)
    best = np.full(len(directions), np.inf)
    o = np.asarray(origin, dtype=np.float64)
    for a, b in walls:
        a, b = np.asarray(a, float), np.asarray(b, float)
        e = b - a
        denom = d[:, 0] * e[1] - d[:, 1] * e[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((a[0] - o[0]) * e[1] - (a[1] - o[1]) * e[0]) / denom
            u = ((a[0] - o[0]) * d[:, 1] - (a[1] - o[1]) * d[:, 0]) / denom
        hit = (np.abs(denom) > 1e-12) & (t > 1e-9) & (u >= 0) & (u <= 1)
        best = np.where(hit & (t < best), t, best)
    return np.where(best <= range_max, best, np.inf)


def quaternion(roll=0.0, pitch=0.0, yaw=0.0):
    """(x, y, z, w) of the rotation yaw about z, then pitch about y, then roll about x (ZYX)."""
    cr, sr, cp, sp, cy, sy = (f(v / 2) for v in (roll, pitch, yaw) for f in (math.cos, math.sin))
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def laser_ranges(robot, mount, angles, walls=WALLS, flipped=False):
    """What a laser mounted at ``mount`` (x, y, yaw in the robot's frame) on a robot at ``robot`` (x, y, yaw)
    reads at its own ``angles`` (upside down: its angles run clockwise seen from above)."""
    rx, ry, ryaw = robot
    mx, my, myaw = mount
    origin = (rx + mx * math.cos(ryaw) - my * math.sin(ryaw), ry + mx * math.sin(ryaw) + my * math.cos(ryaw))
    return cast(origin, ryaw + myaw + (-1 if flipped else 1) * np.asarray(angles), walls)


def scan_message(ts, t, frame, angle_min, increment, ranges, range_max=30.0):
    return _make(ts, "sensor_msgs/msg/LaserScan", header=_header(ts, t, frame), angle_min=angle_min,
                 angle_max=angle_min + increment * (len(ranges) - 1), angle_increment=increment, range_min=0.05,
                 range_max=range_max, ranges=np.asarray(ranges, np.float32), intensities=np.zeros(0, np.float32))


def transform(ts, t, parent, child, xyz=(0.0, 0.0, 0.0), q=(0.0, 0.0, 0.0, 1.0)):
    return _make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, t, parent), child_frame_id=child,
                 transform=_make(ts, "geometry_msgs/msg/Transform",
                                 translation=_make(ts, "geometry_msgs/msg/Vector3", x=xyz[0], y=xyz[1], z=xyz[2]),
                                 rotation=_make(ts, "geometry_msgs/msg/Quaternion", x=q[0], y=q[1], z=q[2], w=q[3])))


def tf_message(ts, transforms):
    return _make(ts, "tf2_msgs/msg/TFMessage", transforms=list(transforms))


def odometry(ts, t, pose, child="base_link"):
    x, y, yaw = pose
    vector = _make(ts, "geometry_msgs/msg/Vector3")
    q = _make(ts, "geometry_msgs/msg/Quaternion", z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    p = _make(ts, "geometry_msgs/msg/Pose", position=_make(ts, "geometry_msgs/msg/Point", x=x, y=y), orientation=q)
    return _make(ts, "nav_msgs/msg/Odometry", header=_header(ts, t, "odom"), child_frame_id=child,
                 pose=_make(ts, "geometry_msgs/msg/PoseWithCovariance", pose=p, covariance=np.zeros(36)),
                 twist=_make(ts, "geometry_msgs/msg/TwistWithCovariance", covariance=np.zeros(36),
                             twist=_make(ts, "geometry_msgs/msg/Twist", linear=vector, angular=vector)))


def write_robot_bag(path, kind, messages):
    """Write ``messages`` (``(time, topic, type, build)``, ``build(ts)`` making the message) as a bag of
    ``kind`` ("ros1", "sqlite3"); its path (a ROS 2 bag: its .db3 file)."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    ts = store(kind)
    if kind == "ros1":
        out = path if path.suffix == ".bag" else path.with_name(path.name + ".bag")
        writer, serialize = Writer1(out), ts.serialize_ros1
    else:
        shutil.rmtree(path, ignore_errors=True)
        writer = Writer2(path, version=9, storage_plugin=StoragePlugin.SQLITE3)
        serialize, out = ts.serialize_cdr, path / f"{path.name}.db3"
    with writer:
        connections = {}
        for t, topic, msgtype, build in sorted(messages, key=lambda m: m[0]):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=ts)
            writer.write(connections[topic], int(round(t * 1e9)), serialize(build(ts), msgtype))
    return out
