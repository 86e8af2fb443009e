"""ROS 1 bags and ROS 2 bags (SQLite ``.db3``, MCAP ``.mcap``): topics, and their messages decoded.

:class:`Bag` opens either kind by its name: ROS 1 bags read from the
format's documented layout (:mod:`novelty.io.ros1`), so that a chunk is
inflated only as far as the messages read need and every stated size is
checked first; ROS 2 bags through the optional package ``rosbags``
(:mod:`novelty.io.ros2`: pure Python, on the package index, ``pip install
'novelty-habituation[ros]'``; without it, opening a bag raises an
``ImportError`` that says so, and the rest of :mod:`novelty.io` works),
after :mod:`novelty.io.ros2.inflation` has checked that no compressed part
(an MCAP chunk, a file, the messages of the topics read) inflates beyond
its cap.
Every message is decoded from its bytes by :mod:`novelty.io.ros.decoders`,
its sizes checked against :mod:`novelty.io.ros.caps` first: an error
names the file, the topic, the message's number on it and the field.

Messages read, by type (ROS 1 and ROS 2 names alike), into the types of
:mod:`novelty.io.ros.messages`:

- ``sensor_msgs/LaserScan`` and ``sensor_msgs/MultiEchoLaserScan`` (one echo
  a beam: ``echo="first"``, ``"last"`` or ``"strongest"``) ->
  :class:`~novelty.io.ros.messages.LaserScan`;
- ``sensor_msgs/Range`` -> :class:`~novelty.io.ros.messages.RangeReading`, its
  sensor the message's frame (one topic for all sonars), or its topic when
  several topics are read (one topic a sonar) or the frame is empty;
- ``sensor_msgs/PointCloud2`` -> :class:`~novelty.io.ros.messages.LaserScan`:
  the points (fields x, y, z) flattened into 360 one-degree beams all round,
  each the nearest point's horizontal range (:func:`novelty.io.ros.clouds.cloud_scan`);
- ``nav_msgs/Odometry``, ``geometry_msgs/PoseStamped`` and
  ``geometry_msgs/PoseWithCovarianceStamped`` -> :class:`~novelty.io.ros.messages.Pose`
  (the heading is the yaw of the orientation quaternion);
- ``tf2_msgs/TFMessage`` and ``tf/tfMessage`` (``/tf``, ``/tf_static``):
  :func:`read_bag` gives a :class:`~novelty.io.ros.messages.Pose` for each
  transform whose child is the robot's ``base_frame`` (as that one transform
  says); :func:`bag_messages` gives the transforms themselves, for a tree
  (:mod:`novelty.io.frames.tf`).

A message's time is its header's stamp (s); a zero stamp (a driver that
leaves it unset) takes the time the bag recorded the message. Messages come
in the bag's order (by record time), one at a time; nothing is read before
it is asked for.

References
----------
ROS message definitions ``sensor_msgs/LaserScan``, ``sensor_msgs/MultiEchoLaserScan``,
``sensor_msgs/Range``, ``sensor_msgs/PointCloud2``, ``nav_msgs/Odometry``,
``geometry_msgs/PoseStamped``, ``tf2_msgs/TFMessage``; the ROS 1 bag format
2.0 (ROS wiki, "Bags/Format/2.0"); the ROS 2 bag formats as ``rosbags``
reads them (https://gitlab.com/ternaris/rosbags).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Iterator, Sequence

from ..ros.caps import MessageError, Where
from ..ros.clouds import cloud_scan
from ..ros.decoders import decode, largest, peek
from ..ros.messages import LaserScan, Pose, RangeReading, Transform
from ..ros.quaternions import yaw
from ..ros1.bag1 import Bag1, BagFormatError
from ..ros2.bag2 import Bag2, rosbags

__all__ = ["BagError", "Bag", "bag_topics", "topic_types", "topic_counts", "read_bag", "bag_messages", "converted",
           "SUPPORTED_TYPES",
           "SCAN_TYPES", "POSE_TYPES", "TF_TYPES", "BAG_SUFFIXES", "is_bag"]

#: Message types read, by their ``rosbags`` names (``package/msg/Type``).
SUPPORTED_TYPES = ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/Range", "sensor_msgs/msg/PointCloud2",
                   "sensor_msgs/msg/MultiEchoLaserScan", "nav_msgs/msg/Odometry",
                   "geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/PoseWithCovarianceStamped",
                   "tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
#: The transforms' types (tf2's, and the older tf's of ROS 1 bags).
TF_TYPES = SUPPORTED_TYPES[-2:]
#: The types read as scans.
SCAN_TYPES = SUPPORTED_TYPES[:4]
#: The types read as poses.
POSE_TYPES = SUPPORTED_TYPES[4:]
#: File names taken for bags: a ROS 1 bag, ROS 2 storage files (a ROS 2 bag folder too).
BAG_SUFFIXES = (".bag", ".db3", ".mcap")

class BagError(ValueError):
    """A file that is not a readable bag, a topic it does not hold, a type not read here."""


def is_bag(path) -> bool:
    """Whether ``path`` names a bag: a ``.bag``, ``.db3`` or ``.mcap`` file, or a ROS 2 bag folder."""
    path = Path(path)
    return path.suffix in BAG_SUFFIXES or (path.is_dir() and (path / "metadata.yaml").exists())


def _rosbags():
    # the optional rosbags, asked for whenever a bag is opened (a ROS 2 bag is read through it)
    return rosbags()


class Bag:
    """An open bag of either kind: its topics with their types and counts; :meth:`messages` reads them.

    Attributes
    ----------
    types : dict of str to str
        Every topic's message type.
    counts : dict of str to int
        Every topic's number of messages.
    """

    def __init__(self, path):
        AnyReader, Stores, get_typestore = _rosbags()
        self.path = Path(path)
        if not self.path.exists():
            raise FileNotFoundError(f"No such bag: {self.path}")
        if not is_bag(self.path):
            raise BagError(f"{self.path} is not a bag: expected a ROS 1 .bag, a ROS 2 .db3 or .mcap file, or a "
                           "ROS 2 bag folder (with metadata.yaml).")
        self.ros1 = self.path.suffix == ".bag"
        try:
            self.reader = Bag1(self.path) if self.ros1 else Bag2(self.path, (AnyReader, Stores, get_typestore))
            self.types = self.reader.topics
            self.counts = {t: self.reader.count(t) for t in self.types}
        except MessageError:   # a ROS 2 bag's compressed part beyond its cap, said as it is
            raise
        except BagFormatError as exc:
            raise BagError(str(exc)) from None
        except Exception as exc:   # rosbags and sqlite raise many kinds for a damaged file
            raise BagError(f"{self.path} is not a readable bag ({type(exc).__name__}: {exc}).") from None

    def close(self) -> None:
        self.reader.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    def check(self, topics: Sequence[str]) -> None:
        """Refuse (:class:`BagError`) a topic the bag does not hold, or of a type not read here."""
        listing = ", ".join(f"{t} ({self.types[t]})" for t in sorted(self.types)) or "none"
        for topic in topics:
            if topic not in self.types:
                raise BagError(f"{self.path} has no topic {topic!r}; its topics: {listing}.")
            if self.types[topic] not in SUPPORTED_TYPES:
                raise BagError(f"Topic {topic} holds {self.types[topic]}, not read here; supported: "
                               f"{', '.join(SUPPORTED_TYPES)}.")

    def messages(self, topics: str | Sequence[str], *, nonempty: Sequence[str] = (), **options) -> Iterator[
            tuple[str, Where, LaserScan | RangeReading | Pose | list[Transform] | tuple]]:
        """``(topic, where, message)`` of each message of ``topics`` in the bag's order, decoded.

        A ``LaserScan`` or ``MultiEchoLaserScan`` is a :class:`LaserScan`, a
        point cloud ``(stamp, frame, points)``, a ``tf`` message a list of
        :class:`Transform` (``static`` on ``/tf_static``). ``options`` reach
        the decoders (``echo=`` for a ``MultiEchoLaserScan``). A topic of
        ``nonempty`` that holds no message is refused before anything is read.
        """
        topics = [topics] if isinstance(topics, str) else list(topics)
        if not topics:
            raise ValueError("Name at least one topic.")
        self.check(topics)
        for topic in nonempty:
            if self.counts.get(topic, 0) == 0:
                raise BagError(f"{self.path}: topic {topic} holds no messages.")
        static = {t: t.rstrip("/").endswith("tf_static") for t in topics}
        for topic, msgtype, record_time, where, data in self._raw(topics):
            msg = decode(msgtype, data, self.ros1, where, topic, static=static[topic], **options)
            yield topic, where, _restamped(msg, msgtype, record_time)

    def _raw(self, topics: Sequence[str]) -> Iterator[tuple[str, str, int, Where, bytes]]:
        """``(topic, type, record time (ns), where, data)`` of each message, its length checked."""
        limits = {t: (largest(self.types[t]), self._explainer(self.types[t])) for t in topics}
        if self.ros1:
            for connection, time, number, data in self.reader.messages(topics, limits):
                yield connection.topic, connection.msgtype, time, Where(self.path, connection.topic, number), data
            return
        try:
            yield from self.reader.messages(topics, limits)
        except (MessageError, GeneratorExit):
            raise
        except Exception as exc:   # a damaged storage file, met while reading
            raise BagError(f"{self.path}: cannot be read past a message on {', '.join(topics)} "
                           f"({type(exc).__name__}: {exc}).") from None

    def _explainer(self, msgtype: str):
        return lambda prefix, where: peek(msgtype, prefix, self.ros1, where)


def bag_topics(path) -> dict[str, str]:
    """Every topic of the bag with its message type (``package/msg/Type``)."""
    with Bag(path) as bag:
        return bag.types


def topic_types(path, topics: Sequence[str]) -> list[str]:
    """The message type of each of ``topics``; a :class:`BagError` for one missing or not read here."""
    with Bag(path) as bag:
        bag.check(topics)
        return [bag.types[t] for t in topics]


def topic_counts(path) -> dict[str, int]:
    """How many messages each topic of the bag holds."""
    with Bag(path) as bag:
        return dict(bag.counts)


def bag_messages(path, topics: str | Sequence[str], **options) -> Iterator[tuple[str, Where, object]]:
    """``(topic, where, message)`` of each message of ``topics`` in the bag's order (:meth:`Bag.messages`)."""
    with Bag(path) as bag:
        yield from bag.messages(topics, **options)


def _restamped(msg, msgtype: str, record_time: int):
    """A zero header stamp (a driver that leaves it unset) takes the bag's record time."""
    if msgtype in TF_TYPES:
        return msg if all(t.stamp > 0 for t in msg) else [t if t.stamp > 0 else _with_stamp(t, record_time)
                                                          for t in msg]
    if msgtype == "sensor_msgs/msg/PointCloud2":
        stamp, frame, points = msg
        return (stamp if stamp > 0 else record_time * 1e-9), frame, points
    return msg if msg.stamp > 0 else _with_stamp(msg, record_time)


def _with_stamp(msg, record_time: int):
    return replace(msg, stamp=record_time * 1e-9)


def read_bag(path, topics: str | Sequence[str], base_frame: str = "base_link", **options) -> Iterator[
        LaserScan | RangeReading | Pose]:
    """The messages of ``topics``, in the bag's order, converted (see the module docstring).

    ``base_frame`` is the robot's frame whose transforms a ``tf`` topic's
    messages give as poses.

    Raises :class:`BagError` (before anything is read) for a topic the bag
    does not hold, listing its topics and their types, or of a type not
    read here, listing those that are.
    """
    topics = [topics] if isinstance(topics, str) else list(topics)
    with Bag(path) as bag:
        # several Range topics: one a sonar, named by its topic; one: the sonars told apart by frame
        by_topic = sum(bag.types.get(t) == "sensor_msgs/msg/Range" for t in topics) > 1
        yield from converted(bag.messages(topics, **options), base_frame, by_topic)


def converted(messages, base_frame: str = "base_link", by_topic: bool = False) -> Iterator[
        LaserScan | RangeReading | Pose]:
    """:meth:`Bag.messages` as :func:`read_bag` gives them (``by_topic``: a ``Range`` reading's sensor is its topic)."""
    for topic, _, msg in messages:
        if isinstance(msg, list):
            yield from (Pose(t.stamp, t.translation[0], t.translation[1], yaw(t.rotation), topic)
                        for t in msg if t.child == base_frame.strip("/"))
        elif isinstance(msg, tuple):
            stamp, _, points = msg
            yield cloud_scan(points, stamp, source=topic)
        elif isinstance(msg, RangeReading):
            yield replace(msg, sensor=topic) if by_topic or not msg.sensor else msg
        else:
            yield msg
