"""The message types read from bags, decoded from their bytes into :mod:`novelty.io.messages`' types.

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
from .messages import LaserScan, Pose, RangeReading, Transform
from .quaternions import yaw
from .wire import Cursor

__all__ = ["decode", "peek", "DECODED", "ECHOES", "largest", "POINT_TYPES"]

#: PointField datatypes (sensor_msgs/PointField) as numpy's, with their sizes
POINT_TYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
#: Which echo of a MultiEchoLaserScan's beam is read.
ECHOES = ("first", "last", "strongest")
_SCAN_FIELDS = ("angle_min", "angle_max", "angle_increment", "time_increment", "scan_time", "range_min", "range_max")


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
    values = dict(zip(_SCAN_FIELDS, head))
    for name in ("angle_min", "angle_increment"):
        if not math.isfinite(values[name]):
            raise where.error(name, f"is {values[name]}; a scan's beams need finite angles.")
    return LaserScan(stamp, ranges.astype(np.float64), values["angle_min"], values["angle_increment"],
                     values["range_min"], values["range_max"] if values["range_max"] > 0 else math.inf,
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


def _cloud(c: Cursor, topic: str, options: dict) -> tuple[float, str, np.ndarray]:
    """A PointCloud2's stamp, frame and the (x, y, z) of every point, whatever its layout."""
    stamp, frame = c.header()
    height, width = c.take("u4", "height", 2)
    n_fields = c.count("fields", caps.MAX_FIELDS, "fields", "MAX_FIELDS", 13)
    fields = {}
    for i in range(n_fields):
        name = c.string(f"fields[{i}].name")
        offset, datatype, count = c.one("u4", f"fields[{i}].offset"), c.one("u1", f"fields[{i}].datatype"), \
            c.one("u4", f"fields[{i}].count")
        fields[name] = (i, offset, datatype, count)
    bigendian = c.one("u1", "is_bigendian")
    point_step, row_step = c.take("u4", "point_step", 2)
    data = c.array("u1", "data", caps.MAX_MESSAGE_BYTES, "bytes", "MAX_MESSAGE_BYTES")
    where = c.where
    where.count(height * width, caps.MAX_POINTS, "height x width", "points", "MAX_POINTS")
    if not {"x", "y", "z"} <= set(fields):
        raise where.error("fields", f"are {sorted(fields)}; x, y and z are needed.")
    formats = []
    for k in "xyz":
        i, offset, datatype, _ = fields[k]
        if datatype not in POINT_TYPES:
            raise where.error(f"fields[{i}].datatype", f"is {datatype} for {k}; PointField's datatypes are 1-8.")
        if offset + np.dtype(POINT_TYPES[datatype]).itemsize > point_step:
            raise where.error(f"fields[{i}].offset", f"puts {k} at byte {offset} of a {point_step}-byte point.")
        formats.append((">" if bigendian else "<") + POINT_TYPES[datatype])
    if width * point_step > row_step:
        raise where.error("row_step", f"is {row_step}: a row of {width} points of {point_step} bytes needs "
                          f"{width * point_step}.")
    where.within(height * row_step, len(data), "data")
    if width == 0 or height == 0:
        return stamp, frame, np.zeros((0, 3))
    dtype = np.dtype({"names": list("xyz"), "formats": formats, "offsets": [fields[k][1] for k in "xyz"],
                      "itemsize": point_step})
    rows = data[:height * row_step].reshape(height, row_step)[:, :width * point_step]
    points = np.ascontiguousarray(rows).view(dtype).reshape(-1)   # a row may be padded beyond its points
    return stamp, frame, np.column_stack([points[k].astype(np.float64) for k in "xyz"])


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
    n = c.count("transforms", caps.MAX_TRANSFORMS, "transforms", "MAX_TRANSFORMS", 60)
    static = options.get("static", False)
    out = []
    for i in range(n):
        stamp, parent = c.header()
        child = c.string(f"transforms[{i}].child_frame_id")
        values = _pose(c, f"transforms[{i}].transform")
        out.append(Transform(stamp, parent.strip("/"), child.strip("/"), values[:3], values[3:], static))
    return out


_DECODERS = {
    "sensor_msgs/msg/LaserScan": _laser_scan,
    "sensor_msgs/msg/MultiEchoLaserScan": _multi_echo,
    "sensor_msgs/msg/PointCloud2": _cloud,
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
