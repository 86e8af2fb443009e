"""ROS 1 bags and ROS 2 bags (SQLite ``.db3``, MCAP ``.mcap``), read through ``rosbags``.

``rosbags`` (pure Python, on the package index) is an optional dependency:
``pip install 'novelty-habituation[ros]'``. Without it, opening a bag raises
an ``ImportError`` that says so; the rest of :mod:`novelty.io` works.

Messages read, by type (ROS 1 and ROS 2 names alike), into the types of
:mod:`novelty.io.messages`:

- ``sensor_msgs/LaserScan`` -> :class:`~novelty.io.messages.LaserScan`;
- ``sensor_msgs/Range`` -> :class:`~novelty.io.messages.RangeReading`, its
  sensor the message's frame (one topic for all sonars), or its topic when
  several topics are read (one topic a sonar) or the frame is empty;
- ``sensor_msgs/PointCloud2`` -> :class:`~novelty.io.messages.LaserScan`:
  the points (fields x, y, z) flattened into 360 one-degree beams all round,
  each the nearest point's horizontal range (:func:`novelty.io.scans.cloud_scan`);
- ``nav_msgs/Odometry``, ``geometry_msgs/PoseStamped`` and
  ``geometry_msgs/PoseWithCovarianceStamped`` -> :class:`~novelty.io.messages.Pose`
  (the heading is the yaw of the orientation quaternion);
- ``tf2_msgs/TFMessage`` and ``tf/tfMessage`` (``/tf``) -> :class:`~novelty.io.messages.Pose`, one
  for each transform whose child is the robot's ``base_frame`` (its pose in
  the parent frame, odom or map, as that one transform says: no chains).

A message's time is its header's stamp (s); a zero stamp (a driver that
leaves it unset) takes the time the bag recorded the message. Messages come
in the bag's order (by record time), one at a time; nothing is read before
it is asked for.

References
----------
ROS message definitions ``sensor_msgs/LaserScan``, ``sensor_msgs/Range``,
``nav_msgs/Odometry``, ``geometry_msgs/PoseStamped``; the bag formats as
``rosbags`` reads them (https://gitlab.com/ternaris/rosbags).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from .messages import LaserScan, Pose, RangeReading
from .scans import cloud_scan

__all__ = ["BagError", "bag_topics", "topic_types", "read_bag", "SUPPORTED_TYPES", "SCAN_TYPES", "POSE_TYPES", "BAG_SUFFIXES", "is_bag"]

#: Message types read, by their ``rosbags`` names (``package/msg/Type``).
SUPPORTED_TYPES = ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/Range", "sensor_msgs/msg/PointCloud2",
                   "nav_msgs/msg/Odometry",
                   "geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/PoseWithCovarianceStamped",
                   "tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
#: The transforms' types (tf2's, and the older tf's of ROS 1 bags).
TF_TYPES = SUPPORTED_TYPES[-2:]
#: The types read as scans.
SCAN_TYPES = SUPPORTED_TYPES[:3]
#: The types read as poses.
POSE_TYPES = SUPPORTED_TYPES[3:]
#: File names taken for bags: a ROS 1 bag, ROS 2 storage files (a ROS 2 bag folder too).
BAG_SUFFIXES = (".bag", ".db3", ".mcap")

_EXTRA = "pip install 'novelty-habituation[ros]' (or pip install rosbags)"


class BagError(ValueError):
    """A file that is not a readable bag, a topic it does not hold, a type not read here."""


def is_bag(path) -> bool:
    """Whether ``path`` names a bag: a ``.bag``, ``.db3`` or ``.mcap`` file, or a ROS 2 bag folder."""
    path = Path(path)
    return path.suffix in BAG_SUFFIXES or (path.is_dir() and (path / "metadata.yaml").exists())


def _rosbags():
    # deferred: rosbags is an optional dependency, imported only to open a bag
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise ImportError(f"Reading ROS bags needs the optional package rosbags: {_EXTRA}.") from None
    return AnyReader, Stores, get_typestore


def _open(path):
    AnyReader, Stores, get_typestore = _rosbags()
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"No such bag: {path}")
    if not is_bag(path):
        raise BagError(f"{path} is not a bag: expected a ROS 1 .bag, a ROS 2 .db3 or .mcap file, or a "
                       "ROS 2 bag folder (with metadata.yaml).")
    try:
        # ROS 2 bags written without their message definitions are read with the latest ROS 2 types
        reader = AnyReader([path], default_typestore=get_typestore(Stores.LATEST))
        reader.open()
    except Exception as exc:   # rosbags and sqlite raise many kinds for a damaged file
        raise BagError(f"{path} is not a readable bag ({type(exc).__name__}: {exc}).") from None
    return reader


def bag_topics(path) -> dict[str, str]:
    """Every topic of the bag with its message type (``package/msg/Type``)."""
    reader = _open(path)
    try:
        return {topic: info.msgtype for topic, info in sorted(reader.topics.items())}
    finally:
        reader.close()


def read_bag(path, topics: str | Sequence[str], base_frame: str = "base_link") -> Iterator[
        LaserScan | RangeReading | Pose]:
    """The messages of ``topics``, in the bag's order, converted (see the module docstring).

    ``base_frame`` is the robot's frame whose transforms a ``tf`` topic's
    messages give as poses.

    Raises :class:`BagError` (before anything is read) for a topic the bag
    does not hold, listing its topics and their types, or of a type not
    read here, listing those that are.
    """
    topics = [topics] if isinstance(topics, str) else list(topics)
    if not topics:
        raise ValueError("Name at least one topic.")
    reader = _open(path)
    try:
        connections = _connections(reader, path, topics)
        # several Range topics: one a sonar, named by its topic; one: the sonars told apart by frame
        by_topic = len({c.topic for c in connections if c.msgtype == "sensor_msgs/msg/Range"}) > 1
        for connection, record_time, raw in reader.messages(connections=connections):
            try:
                msg = reader.deserialize(raw, connection.msgtype)
            except Exception as exc:
                raise BagError(f"{path}: a message on {connection.topic} cannot be decoded "
                               f"({type(exc).__name__}: {exc}).") from None
            if connection.msgtype in TF_TYPES:
                yield from _tf_poses(msg, connection.topic, record_time, base_frame.strip("/"))
            else:
                yield _convert(msg, connection.msgtype, connection.topic, record_time, by_topic)
    finally:
        reader.close()


def _connections(reader, path, topics: Sequence[str]) -> list:
    _check_topics(path, {topic: info.msgtype for topic, info in reader.topics.items()}, topics)
    return [c for c in reader.connections if c.topic in topics]


def topic_types(path, topics: Sequence[str]) -> list[str]:
    """The message type of each of ``topics``; a :class:`BagError` for one missing or not read here."""
    available = bag_topics(path)
    _check_topics(path, available, topics)
    return [available[t] for t in topics]


def _check_topics(path, available: dict, topics: Sequence[str]) -> None:
    listing = ", ".join(f"{t} ({available[t]})" for t in sorted(available)) or "none"
    for topic in topics:
        if topic not in available:
            raise BagError(f"{path} has no topic {topic!r}; its topics: {listing}.")
        if available[topic] not in SUPPORTED_TYPES:
            raise BagError(f"Topic {topic} holds {available[topic]}, not read here; supported: "
                           f"{', '.join(SUPPORTED_TYPES)}.")


# ------------------------------------------------------------------ conversion
def _stamp(header, record_time: int) -> float:
    stamp = header.stamp.sec + header.stamp.nanosec * 1e-9
    return stamp if stamp > 0 else record_time * 1e-9


def _yaw(q) -> float:
    """The heading of a quaternion: its rotation about z (ZYX Euler angles' yaw)."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


#: PointField datatypes (sensor_msgs/PointField) as numpy's
_POINT_TYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}


def _cloud_points(msg, topic: str) -> np.ndarray:
    """The (x, y, z) of every point of a PointCloud2, whatever its layout."""
    fields = {f.name: f for f in msg.fields}
    if not {"x", "y", "z"} <= set(fields):
        raise BagError(f"The point clouds on {topic} have fields {sorted(fields)}; x, y and z are needed.")
    order = ">" if msg.is_bigendian else "<"
    dtype = np.dtype({"names": ["x", "y", "z"],
                      "formats": [order + _POINT_TYPES[fields[k].datatype] for k in "xyz"],
                      "offsets": [fields[k].offset for k in "xyz"], "itemsize": msg.point_step})
    data = np.asarray(msg.data, dtype=np.uint8).reshape(msg.height, msg.row_step)
    rows = data[:, :msg.width * msg.point_step].copy()   # a row may be padded beyond its points
    points = rows.view(dtype).reshape(-1)
    return np.column_stack([points[k].astype(np.float64) for k in "xyz"])


def _tf_poses(msg, topic: str, record_time: int, base_frame: str) -> Iterator[Pose]:
    """The transforms of ``base_frame`` from its parent (odom, map) as poses; the others are passed over."""
    for t in msg.transforms:
        if t.child_frame_id.strip("/") == base_frame:
            yield Pose(_stamp(t.header, record_time), float(t.transform.translation.x),
                       float(t.transform.translation.y), _yaw(t.transform.rotation), topic)


def _convert(msg, msgtype: str, topic: str, record_time: int, by_topic: bool):
    stamp = _stamp(msg.header, record_time)
    if msgtype == "sensor_msgs/msg/LaserScan":
        return LaserScan(stamp, np.asarray(msg.ranges, dtype=np.float64), float(msg.angle_min),
                         float(msg.angle_increment), float(msg.range_min), float(msg.range_max),
                         source=topic)
    if msgtype == "sensor_msgs/msg/PointCloud2":
        return cloud_scan(_cloud_points(msg, topic), stamp, source=topic)
    if msgtype == "sensor_msgs/msg/Range":
        sensor = topic if by_topic or not msg.header.frame_id else msg.header.frame_id
        return RangeReading(stamp, float(msg.range), sensor, float(msg.min_range), float(msg.max_range),
                            float(msg.field_of_view))
    pose = msg.pose.pose if msgtype in ("nav_msgs/msg/Odometry",
                                        "geometry_msgs/msg/PoseWithCovarianceStamped") else msg.pose
    return Pose(stamp, float(pose.position.x), float(pose.position.y), _yaw(pose.orientation), topic)
