"""ROS 1 bags of a robot driving loops round the simulated room of ``tests/io/scenes.py``, and their bytes.

:func:`robot_bag` writes what such a robot records (rosbags' writer): laser
scans (one laser or two, whole or in fragments, upright or upside down,
mounted off the centre) in their frames, ``/tf`` (``odom -> base_link``)
and the lasers' mounts on ``/tf_static`` (latched, as ``rosbag record``
keeps it). Every time is at least 1 s: ``rosbag play`` starts a bag's clock
at its first message, and loses messages recorded at time 0.
:func:`messages` gives a bag's messages as a subscription delivers them:
their topic, type and bytes, in the bag's order.
"""

import math

import numpy as np

from novelty.io.ros1.bag1 import Bag1
from novelty.io.ros.decoders import largest

from ..io.scenes import WALLS, laser_ranges, quaternion, scan_message, tf_message, transform, write_robot_bag

SCAN = "sensor_msgs/msg/LaserScan"
TF = "tf2_msgs/msg/TFMessage"
#: seconds a loop round the box takes
LOOP = 20.0


def pose_at(t: float) -> tuple[float, float, float]:
    """The robot's pose at ``t`` s: a circle of 2 m round (1, 1), the box at its middle, facing along it."""
    a = 2 * math.pi * t / LOOP
    return 1.0 + 2.0 * math.cos(a), 1.0 + 2.0 * math.sin(a), a + math.pi / 2


def laser(times, topic="/scan", frame="laser", beams=360, span=2 * math.pi, mount=(0.1, 0.0, 0.0), flipped=False,
          fragments=1, ranges=None, walls=lambda t: WALLS):
    """A laser's messages at ``times``: whole scans, or each cut in ``fragments`` messages a millisecond apart;
    ``ranges(t, r)`` may change what it reads, ``walls(t)`` the room it sees."""
    inc = span / beams
    start = -span / 2
    angles = start + inc * np.arange(beams)
    per = beams // fragments
    out = []
    for t in times:
        r = laser_ranges(pose_at(t), mount, angles, walls(t), flipped=flipped)
        r = r if ranges is None else ranges(t, r)
        for k in range(fragments):
            tk = round(t + k * 0.001, 6)
            part = r[k * per:(k + 1) * per]
            out.append((tk, topic, SCAN, lambda ts, tk=tk, k=k, part=part: scan_message(
                ts, tk, frame, start + k * per * inc, inc, part)))
    return out


def odometry_tf(times, skip=lambda t: False):
    """``odom -> base_link`` on /tf at ``times`` (those where ``skip(t)``, left out: a gap)."""
    return [(t, "/tf", TF, lambda ts, t=t: tf_message(ts, [transform(
        ts, t, "odom", "base_link", (*pose_at(t)[:2], 0.0), quaternion(yaw=pose_at(t)[2]))]))
        for t in times if not skip(t)]


def mounts(t, *edges):
    """The lasers' mounts on /tf_static: ``(frame, (x, y, yaw), flipped)`` each."""
    def build(ts):
        return tf_message(ts, [transform(ts, t, "base_link", frame, (x, y, 0.2),
                                         quaternion(roll=math.pi if flipped else 0.0, yaw=yaw))
                               for frame, (x, y, yaw), flipped in edges])
    return (t, "/tf_static", TF, build)


def robot_bag(path, seconds=6.0, rate=10.0, tf_rate=50.0, start=1.0, **laser_options):
    """One laser at ``rate`` Hz for ``seconds`` from ``start``, odometry on /tf, its mount on /tf_static."""
    times = np.round(start + np.arange(0.0, seconds, 1.0 / rate), 6)
    tf_times = np.round(start - 0.1 + np.arange(0.0, seconds + 0.3, 1.0 / tf_rate), 6)
    mount = laser_options.get("mount", (0.1, 0.0, 0.0))
    messages = laser(times, **laser_options) + odometry_tf(tf_times) + [
        mounts(start - 0.5, (laser_options.get("frame", "laser"), mount, laser_options.get("flipped", False)))]
    return write_robot_bag(path, "ros1", messages)


def messages(path):
    """``(topic, type, record time (s), bytes)`` of each message of a ROS 1 bag, in its order."""
    with Bag1(path) as bag:
        limits = {t: (largest(kind), lambda *args: None) for t, kind in bag.topics.items()}
        for connection, time, _, data in bag.messages(list(bag.topics), limits):
            yield connection.topic, connection.msgtype, time * 1e-9, bytes(data)


#: a box that appears on the second loop of :func:`two_loops`, half a metre outside the robot's circle
NEW_BOX = [((3.5, 0.85), (3.8, 0.85)), ((3.8, 0.85), (3.8, 1.15)), ((3.8, 1.15), (3.5, 1.15)), ((3.5, 1.15), (3.5, 0.85))]


def two_loops(path, rate=20.0):
    """Two loops round the room (:data:`LOOP` s each) with a 360-beam laser; on the second, a new box by the way."""
    times = np.round(1.0 + np.arange(0.0, 2 * LOOP, 1.0 / rate), 6)
    scans = laser(times, walls=lambda t: WALLS + NEW_BOX if t >= 1.0 + LOOP else WALLS)
    tf_times = np.round(0.9 + np.arange(0.0, 2 * LOOP + 0.3, 0.02), 6)
    return write_robot_bag(path, "ros1", scans + odometry_tf(tf_times) + [mounts(0.5, ("laser", (0.1, 0.0, 0.0),
                                                                                     False))])
