"""The message types read from bags, decoded from their bytes into :mod:`novelty.io.ros.messages`' types.

Written from the message definitions (``sensor_msgs``, ``nav_msgs``,
``geometry_msgs``, ``tf2_msgs``) and the two encodings of :mod:`.wire`, so
that every stated size is checked before it is used (the caps of
:mod:`.caps`) and an error names the file, topic, message number and field;
the tests compare every decoder with ``rosbags``' deserialization.

- ``LaserScan`` -> :class:`~.messages.LaserScan` (at least one beam);
- ``MultiEchoLaserScan`` -> :class:`~.messages.LaserScan` of one echo a beam:
  its ``first``, ``last`` or ``strongest`` (the highest intensity); a beam
  without an echo reads NaN (no information);
- ``PointCloud2`` -> the (x, y, z) of its points, its layout checked
  (known datatypes, fields within a point, points within a row, rows within the data);
- ``Range`` -> :class:`~.messages.RangeReading`;
- ``Odometry``, ``PoseStamped``, ``PoseWithCovarianceStamped`` ->
  :class:`~.messages.Pose` (the heading is the orientation's yaw; a
  non-finite position or orientation is refused);
- ``TFMessage`` (``tf2_msgs``, and ``tf``'s ``tfMessage``) -> a list of
  :class:`~.messages.Transform`.
"""

from __future__ import annotations

import math
import struct

import numpy as np

from . import caps
from .caps import Where
from .clouds import cloud_points
from .messages import LaserScan, Pose, RangeReading, Transform
from .quaternions import yaw
from .wire import Cursor

__all__ = ["decode", "peek", "DECODED", "ECHOES", "largest"]

#: Which echo of a MultiEchoLaserScan's beam is read.
ECHOES = ("first", "last", "strongest")


def _scan_head(c: Cursor) -> tuple[float, str, tuple]:
    stamp, frame = c.header()
    return stamp, frame, c.take("f4", "angle_min", 7)


def _laser_scan(c: Cursor, topic: str, options: dict) -> LaserScan:
    fast = _little_endian_scan(c)
    if fast is not None:
        return fast
    stamp, frame, head = _scan_head(c)
    ranges = c.array("f4", "ranges", caps.MAX_BEAMS, "beams", "MAX_BEAMS")
    if len(ranges) == 0:
        raise c.where.error("ranges", "holds no beams; a scan needs at least one.")
    return _scan(c.where, stamp, frame, head, ranges, topic)


_ROS1_HEAD, _CDR_HEAD, _SCAN_TAIL = struct.Struct("<4I"), struct.Struct("<iII"), struct.Struct("<7fI")


def _little_endian_scan(c: Cursor) -> LaserScan | None:
    """The common case of :func:`_laser_scan` in a few unpacks: little-endian, within every cap.

    Reads what the field-by-field path reads, to the same values (tested);
    None sends anything else (a cap passed, a truncated message, big-endian
    CDR) to that path for its error.
    """
    data, pos = c.data, c.pos
    if c.ros1:
        if len(data) < 16:
            return None
        _, sec, nsec, n = _ROS1_HEAD.unpack_from(data, 0)
        pos = 16
    else:
        if c.order != "<" or len(data) < 16:
            return None
        sec, nsec, n = _CDR_HEAD.unpack_from(data, pos)
        pos += 12
    if n > caps.MAX_NAME or pos + n + 3 + _SCAN_TAIL.size > len(data):
        return None
    frame = bytes(data[pos:pos + n])
    pos += n
    if not c.ros1:
        frame = frame.rstrip(b"\0")
        pos += -(pos - 4) % 4
    *head, count = _SCAN_TAIL.unpack_from(data, pos)
    pos += _SCAN_TAIL.size
    if not 0 < count <= caps.MAX_BEAMS or pos + 4 * count > len(data):
        return None
    ranges = np.frombuffer(data, "<f4", count, pos)
    return _scan(c.where, sec + nsec * 1e-9, frame.decode("utf-8", "replace"), head, ranges, c.where.topic)


def _scan(where: Where, stamp, frame, head, ranges, topic) -> LaserScan:
    # LaserScan's seven floats: angle_min, angle_max, angle_increment, time_increment, scan_time, range_min,
    # range_max
    angle_min, _, increment, _, _, range_min, range_max = head
    for name, value in (("angle_min", angle_min), ("angle_increment", increment)):
        if not math.isfinite(value):
            raise where.error(name, f"is {value}; a scan's beams need finite angles.")
    # the ranges as the message holds them (float32, read-only): cleaning them makes the float64 copy
    return LaserScan(stamp, ranges, angle_min, increment, range_min, range_max if range_max > 0 else math.inf,
                     source=topic, frame=frame.strip("/"))


def _multi_echo(c: Cursor, topic: str, options: dict) -> LaserScan:
    stamp, frame, head = _scan_head(c)
    echoes = _echoes(c, "ranges")
    if not echoes:
        raise c.where.error("ranges", "holds no beams; a scan needs at least one.")
    choice = options.get("echo", "first")
    if choice == "strongest":
        strength = _echoes(c, "intensities")
        if [len(e) for e in strength] != [len(e) for e in echoes]:
            raise c.where.error("intensities", "does not give one intensity an echo; the strongest echo "
                                "cannot be chosen (choose the first or the last).")
        picked = [e[int(np.argmax(s))] if len(e) else math.nan for e, s in zip(echoes, strength)]
    else:
        k = 0 if choice == "first" else -1
        picked = [e[k] if len(e) else math.nan for e in echoes]
    return _scan(c.where, stamp, frame, head, np.array(picked, dtype=np.float64), topic)


def _echoes(c: Cursor, field: str) -> list[np.ndarray]:
    n = c.count(field, caps.MAX_BEAMS, "beams", "MAX_BEAMS", 4)
    return [c.array("f4", f"{field}[{i}].echoes", caps.MAX_ECHOES, "echoes", "MAX_ECHOES") for i in range(n)]


def _range(c: Cursor, topic: str, options: dict) -> RangeReading:
    stamp, frame = c.header()
    c.one("u1", "radiation_type")
    fov, low, high, value = c.take("f4", "field_of_view", 4)
    return RangeReading(stamp, value, frame.strip("/"), low, high, fov, frame.strip("/"))


def _pose(c: Cursor, field: str) -> tuple:
    values = c.take("f8", field, 7)
    bad = next((i for i, v in enumerate(values) if not math.isfinite(v)), None)
    if bad is not None:
        part = ("position.x", "position.y", "position.z", "orientation.x", "orientation.y", "orientation.z",
                "orientation.w")[bad]
        raise c.where.error(f"{field}.{part}", f"is {values[bad]}; a pose must be finite.")
    return values


def _odometry(c: Cursor, topic: str, options: dict) -> Pose:
    stamp, _ = c.header()
    c.string("child_frame_id")
    return _planar(stamp, _pose(c, "pose.pose"), topic)


def _pose_stamped(c: Cursor, topic: str, options: dict) -> Pose:
    stamp, _ = c.header()
    return _planar(stamp, _pose(c, "pose"), topic)


def _pose_with_covariance(c: Cursor, topic: str, options: dict) -> Pose:
    stamp, _ = c.header()
    return _planar(stamp, _pose(c, "pose.pose"), topic)


def _planar(stamp: float, values: tuple, topic: str) -> Pose:
    return Pose(stamp, values[0], values[1], yaw(values[3:]), topic)


def _transforms(c: Cursor, topic: str, options: dict) -> list[Transform]:
    static = options.get("static", False)
    fast = _little_endian_transforms(c, static)
    if fast is not None:
        return fast
    n = c.count("transforms", caps.MAX_TRANSFORMS, "transforms", "MAX_TRANSFORMS", 60)
    out = []
    for i in range(n):
        stamp, parent = c.header()
        child = c.string(f"transforms[{i}].child_frame_id")
        values = _pose(c, f"transforms[{i}].transform")
        out.append(Transform(stamp, parent.strip("/"), child.strip("/"), values[:3], values[3:], static))
    return out


_SEVEN_DOUBLES, _U32 = struct.Struct("<7d"), struct.Struct("<I")


def _little_endian_transforms(c: Cursor, static: bool) -> list[Transform] | None:
    """The common case of :func:`_transforms` read in a few unpacks a transform, to the same values (tested);
    None sends anything else (a cap passed, a truncated message, a pose not finite, big-endian CDR) to the
    field-by-field path for its error."""
    data, pos, ros1 = c.data, c.pos, c.ros1
    end = len(data)
    if (not ros1 and c.order != "<") or pos + 4 > end:
        return None
    (n,) = _U32.unpack_from(data, pos)
    pos += 4
    if n > caps.MAX_TRANSFORMS:
        return None
    out = []
    for _ in range(n):
        if ros1:
            if pos + 16 > end:
                return None
            _, sec, nsec, size = _ROS1_HEAD.unpack_from(data, pos)
            pos += 16
        else:
            pos += -(pos - 4) % 4
            if pos + 12 > end:
                return None
            sec, nsec, size = _CDR_HEAD.unpack_from(data, pos)
            pos += 12
        names = []
        for _ in range(2):   # the header's frame, then the child's
            if size > caps.MAX_NAME or pos + size + 4 > end:
                return None
            raw = bytes(data[pos:pos + size])
            names.append((raw if ros1 else raw.rstrip(b"\0")).decode("utf-8", "replace").strip("/"))
            pos += size
            if len(names) == 1:
                pos += 0 if ros1 else -(pos - 4) % 4
                (size,) = _U32.unpack_from(data, pos)
                pos += 4
        pos += 0 if ros1 else -(pos - 4) % 8
        if pos + 56 > end:
            return None
        values = _SEVEN_DOUBLES.unpack_from(data, pos)
        pos += 56
        if not all(map(math.isfinite, values)):
            return None
        out.append(Transform(sec + nsec * 1e-9, names[0], names[1], values[:3], values[3:], static))
    return out


_DECODERS = {
    "sensor_msgs/msg/LaserScan": _laser_scan,
    "sensor_msgs/msg/MultiEchoLaserScan": _multi_echo,
    "sensor_msgs/msg/PointCloud2": cloud_points,
    "sensor_msgs/msg/Range": _range,
    "nav_msgs/msg/Odometry": _odometry,
    "geometry_msgs/msg/PoseStamped": _pose_stamped,
    "geometry_msgs/msg/PoseWithCovarianceStamped": _pose_with_covariance,
    "tf2_msgs/msg/TFMessage": _transforms,
    "tf/msg/tfMessage": _transforms,
}
#: The message types decoded here.
DECODED = tuple(_DECODERS)
#: The largest serialized message of each type accepted: a cap's worth of its variable parts.
_LARGEST = {
    "sensor_msgs/msg/LaserScan": 8 * caps.MAX_BEAMS,
    "sensor_msgs/msg/MultiEchoLaserScan": 8 * caps.MAX_BEAMS * (caps.MAX_ECHOES + 1),
    "sensor_msgs/msg/PointCloud2": caps.MAX_MESSAGE_BYTES,
    "tf2_msgs/msg/TFMessage": caps.MAX_TRANSFORMS * (2 * caps.MAX_NAME + 80),
    "tf/msg/tfMessage": caps.MAX_TRANSFORMS * (2 * caps.MAX_NAME + 80),
}


def largest(msgtype: str) -> int:
    """The most bytes a message of ``msgtype`` may hold to be read (its names and headers included)."""
    return min(_LARGEST.get(msgtype, 0) + 4 * caps.MAX_NAME + 1024, caps.MAX_MESSAGE_BYTES + 4 * caps.MAX_NAME)


def decode(msgtype: str, data: bytes, ros1: bool, where: Where, topic: str, **options):
    """The message ``data`` of ``msgtype`` (ROS 1 serialization or CDR) as this package's types."""
    return _DECODERS[msgtype](Cursor(data, ros1, where), topic, options)


def peek(msgtype: str, prefix: bytes, ros1: bool, where: Where) -> None:
    """Read the sizes a message's first bytes state, raising the error of one beyond its cap.

    Used for a message longer than :func:`largest` allows, before the rest is
    inflated: the error then names the field that asks for too much. A
    prefix that ends before such a field raises nothing.
    """
    c = Cursor(prefix, ros1, where)
    try:
        if msgtype in ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/MultiEchoLaserScan"):
            _scan_head(c)
            c.count("ranges", caps.MAX_BEAMS, "beams", "MAX_BEAMS", 0)
        elif msgtype == "sensor_msgs/msg/PointCloud2":
            c.header()
            height, width = c.take("u4", "height", 2)
            where.count(height * width, caps.MAX_POINTS, "height x width", "points", "MAX_POINTS")
        elif msgtype in ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage"):
            c.count("transforms", caps.MAX_TRANSFORMS, "transforms", "MAX_TRANSFORMS", 0)
    except caps.TruncatedError:   # the prefix ends before the field: the whole message says more
        return
