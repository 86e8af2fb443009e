"""Whole scans in the robot's base frame, every beam with its origin and direction: :class:`Sweep`.

A recording's laser messages say where each beam went in the sensor's own
frame; the paper's ring is what the robot sees from its own centre. A
:class:`Sweep` is the stage between: one whole scan in the robot's base
frame (REP 103: x forward, y left, angles counter-clockwise), each beam with
its origin (the sensor's position in the base frame), its direction and its
range (cleaned as :func:`novelty.io.scans.clean_ranges` does), with the
robot's pose in the world at the scan's time. :func:`read_sweeps` reads them
from a recording; :func:`sweep_ring` (or a :class:`RingMaker`, which keeps
the sectors of a geometry it has seen) reduces one to the paper's ring:

- each beam's end point is ``origin + range * (cos angle, sin angle)``; its
  bearing from the base frame's origin is ``atan2`` of the end point and its
  range ``hypot`` (a beam with ``+inf`` keeps its own direction and ``+inf``;
  NaN stays NaN);
- the bearings are cut into sectors and each sector's beams reduced as
  :func:`novelty.io.scans.sector_index` and
  :func:`novelty.io.scans.reduce_sectors` do. Where every origin is zero the
  bearings are the beams' own angles, and the ring is exactly
  :func:`novelty.io.scans.laser_ring`'s.

Where a sensor is not at the base frame's origin, a sector's reduced range
is the distance from the robot's centre to what the beams hit, as a sonar
at the centre would report it; the default ``limits`` are then the span of
the beams' directions, and a beam whose end point's bearing falls outside
them is left out.

References
----------
REP 103, "Standard Units of Measure and Coordinate Conventions"; REP 105,
"Coordinate Frames for Mobile Platforms" (the base frame ``base_link``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from .carmen import CarmenLog
from .messages import LaserScan, Pose
from .rosbag import POSE_TYPES, SCAN_TYPES, Bag, converted, is_bag
from .scans import _check_reduce, _checked_limits, _sectors_within, clean_ranges, reduce_sectors, \
    scan_limits, sector_index

__all__ = ["Sweep", "read_sweeps", "sweep_ring", "RingMaker", "scan_sweep", "CARMEN_SUFFIXES", "CARMEN_LASERS",
           "LASER_TYPES"]

#: File names taken for CARMEN logs (``.clf``: the "CARMEN log file" of some data sets).
CARMEN_SUFFIXES = (".log", ".log.gz", ".clf", ".clf.gz", ".carmen", ".carmen.gz")
#: The CARMEN messages that are laser scans.
CARMEN_LASERS = ("FLASER", "RLASER", "ROBOTLASER1")
#: The bag message types read as sweeps.
LASER_TYPES = ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/MultiEchoLaserScan", "sensor_msgs/msg/PointCloud2")


@dataclass(frozen=True, eq=False)
class Sweep:
    """One whole scan of the robot's surroundings, in its base frame (REP 103: x forward, y left, ccw).

    Attributes
    ----------
    time : float
        The scan's time (s): its first beam's, as ``LaserScan.stamp``.
    origins : ndarray of shape (n_beams, 2)
        Each beam's origin: the sensor's position in the base frame (m).
    angles : ndarray of shape (n_beams,)
        Each beam's direction in the base frame (rad).
    ranges : ndarray of shape (n_beams,)
        Cleaned as :func:`novelty.io.scans.clean_ranges` does (a range in m,
        ``+inf`` nothing seen, NaN no information), along the beam from its origin.
    pose : ndarray of shape (3,) or None
        The base frame's pose (x, y, yaw) in the world frame (odom or map)
        at ``time``, or None.
    frame : str
        The base frame's name (``base_link``, ...; "" when unknown, e.g. a CARMEN log).
    source : str
        Where the beams came from (topic(s), CARMEN message name).
    spread : ndarray of shape (n_beams,) or None
        Each beam's full cone angle (rad): None (or 0) for a laser, a
        sonar's field of view.
    """

    time: float
    origins: np.ndarray
    angles: np.ndarray
    ranges: np.ndarray
    pose: np.ndarray | None
    frame: str = ""
    source: str = ""
    spread: np.ndarray | None = None


# ------------------------------------------------------------------ reading
def read_sweeps(path, topic: str | Sequence[str] | None = None, *, pose_topic: str | None = None,
                base_frame: str | None = None, fov: float = math.pi) -> Iterator[Sweep]:
    """The recording's laser scans as sweeps in the robot's base frame, one at a time.

    Parameters
    ----------
    path : str or Path
        A CARMEN log (plain or gzipped) or a bag (``.bag``, ``.db3``, ``.mcap``).
    topic : str or sequence of str, optional
        The scans: a CARMEN message (default ``FLASER``; ``RLASER``,
        ``ROBOTLASER1``) or a bag's ``LaserScan`` or ``PointCloud2`` topic
        (default: its only one).
    pose_topic : str, optional
        Where poses come from: a CARMEN log's own corrected poses (None) or
        ``ODOM``; a bag's ``Odometry``, ``PoseStamped`` or ``tf`` topic, the
        latest pose before each scan.
    base_frame : str, optional
        The robot's frame, whose transforms a ``tf`` pose topic gives
        (default ``base_link``).
    fov : float, default=pi
        The field of view (rad) of CARMEN's ``FLASER``/``RLASER``, which do not state it.
    """
    if is_bag(path):
        with Bag(path) as bag:
            topics = bag_scan_topics(bag, topic)
            yield from _bag_sweeps(bag, topics, pose_topic, base_frame or "base_link")
        return
    if not Path(path).name.lower().endswith(CARMEN_SUFFIXES):
        raise ValueError(f"{path} is neither a CARMEN log ({', '.join(CARMEN_SUFFIXES)}) nor a bag "
                         "(.bag, .db3, .mcap, a ROS 2 bag folder).")
    yield from _carmen(path, topic or "FLASER", pose_topic, fov)


def bag_scan_topics(bag: Bag, topic) -> list[str]:
    """The scans' topics: those named, or the bag's only scan topic (``LaserScan``, ``PointCloud2``, ``Range``)."""
    if topic is not None:
        topics = [topic] if isinstance(topic, str) else list(topic)
        bag.check(topics)
        return topics
    scans = [t for t, kind in bag.types.items() if kind in SCAN_TYPES]
    if len(scans) != 1:
        listing = ", ".join(f"{t} ({k})" for t, k in bag.types.items()) or "none"
        raise ValueError(f"Name the scans' topic of {bag.path} (topic=, --topic); its topics: {listing}.")
    return scans


def check_pose_topic(bag: Bag, pose_topic: str | None) -> None:
    """Refuse a pose topic that does not hold poses."""
    if pose_topic is None:
        return
    bag.check([pose_topic])
    if bag.types[pose_topic] not in POSE_TYPES:
        raise ValueError(f"pose_topic {pose_topic} must hold poses (one of {', '.join(POSE_TYPES)}); it "
                         f"holds {bag.types[pose_topic]}.")


def _bag_sweeps(bag: Bag, topics: list[str], pose_topic: str | None, base_frame: str) -> Iterator[Sweep]:
    kinds = {bag.types[t] for t in topics}
    if not kinds <= set(LASER_TYPES):
        raise ValueError(f"Sweeps are read from LaserScan, MultiEchoLaserScan or PointCloud2 topics; "
                         f"{holds(topics, kinds)}.")
    check_pose_topic(bag, pose_topic)
    messages = bag.messages(topics + ([pose_topic] if pose_topic else []), nonempty=topics)
    yield from _sweeps(converted(messages, base_frame), use_own_pose=False)


def holds(topics, kinds) -> str:
    """``/a holds T`` or ``/a, /b hold T, U``."""
    return f"{', '.join(topics)} {'holds' if len(topics) == 1 else 'hold'} {', '.join(sorted(kinds))}"


def _carmen(path, topic: str, pose_topic: str | None, fov: float) -> Iterator[Sweep]:
    if topic not in CARMEN_LASERS:
        raise ValueError(f"A CARMEN log's scans are one of {', '.join(CARMEN_LASERS)}; got {topic!r}.")
    if pose_topic not in (None, "ODOM"):
        raise ValueError(f"A CARMEN log's poses are the scans' own (None) or ODOM; got {pose_topic!r}.")
    log = CarmenLog(path, messages=(topic,) + ((pose_topic,) if pose_topic else ()), fov=fov)
    count = 0
    for sweep in _sweeps(iter(log), use_own_pose=pose_topic is None):
        count += 1
        yield sweep
    if count == 0:
        held = ", ".join(f"{name} ({n})" for name, n in log.skipped.most_common()) or "no messages"
        raise ValueError(f"{path} holds no {topic} messages; it holds: {held}.")


def _sweeps(messages, use_own_pose: bool) -> Iterator[Sweep]:
    latest: np.ndarray | None = None
    geometry = _Geometry()
    for msg in messages:
        if isinstance(msg, Pose):
            latest = np.array([msg.x, msg.y, msg.theta])
            continue
        if not isinstance(msg, LaserScan):
            raise ValueError(f"Expected laser scans on the scans' topic; got a {type(msg).__name__}.")
        yield scan_sweep(msg, msg.pose if use_own_pose else latest, geometry=geometry)


class _Geometry:
    """The last laser geometry's beam angles and origins, shared by the sweeps of that geometry."""

    def __init__(self):
        self.key = None
        self.arrays: tuple[np.ndarray, np.ndarray] | None = None

    def of(self, scan: LaserScan) -> tuple[np.ndarray, np.ndarray]:
        key = (len(scan.ranges), scan.angle_min, scan.angle_increment, scan.origin)
        if key != self.key:
            angles = scan.angles
            origins = np.empty((len(angles), 2))
            origins[:] = scan.origin
            angles.flags.writeable = origins.flags.writeable = False
            self.key, self.arrays = key, (angles, origins)
        return self.arrays


def scan_sweep(scan: LaserScan, pose=None, frame: str = "", *, geometry: _Geometry | None = None) -> Sweep:
    """A laser scan whose angles are the robot's as a sweep: its beams from ``scan.origin``."""
    angles, origins = (geometry or _Geometry()).of(scan)
    return Sweep(scan.stamp, origins, angles, clean_ranges(scan.ranges, scan.range_min, scan.range_max),
                 pose, frame, scan.source)


# ------------------------------------------------------------------ rings
def sweep_ring(sweep: Sweep, n_sectors: int = 16, reduce="min", limits=None, front: float = 0.0,
               clip: float | None = None) -> np.ndarray:
    """A sweep as a ring of ``n_sectors`` ranges seen from the base frame's origin (see the module docstring).

    Examples
    --------
    >>> zero = np.zeros((3, 2))
    >>> centred = Sweep(0.0, zero, np.deg2rad([-60.0, 0.0, 60.0]), np.array([2.0, 1.0, np.inf]), None)
    >>> sweep_ring(centred, 3).tolist()
    [2.0, 1.0, inf]
    >>> ahead = Sweep(0.0, zero + [0.5, 0.0], centred.angles, centred.ranges, None)
    >>> sweep_ring(ahead, 3).round(3).tolist()   # the laser 0.5 m ahead: what it sees 1 m ahead is 1.5 m away
    [2.291, 1.5, inf]
    """
    return RingMaker(n_sectors, reduce, limits, front, clip)(sweep)


class RingMaker:
    """:func:`sweep_ring` with its parameters fixed, keeping the sectors of the geometries it has met.

    The beams' sectors depend on their directions alone where every origin
    is zero: they are worked out once for a geometry (the same ``angles``
    array, or equal ones) and reused.
    """

    def __init__(self, n_sectors: int = 16, reduce="min", limits=None, front: float = 0.0,
                 clip: float | None = None):
        _check_reduce(reduce)
        self.n_sectors, self.reduce, self.front, self.clip = n_sectors, reduce, float(front), clip
        self.limits = None if limits is None else _checked_limits(limits)
        self._known: list[_Sectors] = []

    def __call__(self, sweep: Sweep) -> np.ndarray:
        geometry = self._geometry(sweep.angles)
        origins = sweep.origins
        if origins is geometry.origins or not np.any(origins):
            if not getattr(origins, "flags", origins).writeable:   # a reader's shared, read-only origins:
                geometry.origins = origins                           # the next sweep's need no test
            if self.reduce == "min":
                return geometry.nearest(sweep.ranges, self.clip)
            return reduce_sectors(sweep.ranges, geometry.index, self.n_sectors, self.reduce, self.clip)
        bearings, ranges = _seen_from_centre(np.asarray(origins, dtype=np.float64), geometry.angles,
                                             np.asarray(sweep.ranges, dtype=np.float64))
        low, high = geometry.limits
        index = _sectors_within(low + np.mod(bearings - self.front - low, 2 * math.pi), low, high, self.n_sectors)
        if self.reduce == "min":
            inside = index >= 0
            ring = np.full(self.n_sectors, np.inf)
            np.fmin.at(ring, index[inside], ranges[inside] if self.clip is None else np.minimum(ranges[inside],
                                                                                                 self.clip))
            return ring
        return reduce_sectors(ranges, index, self.n_sectors, self.reduce, self.clip)

    def _geometry(self, angles) -> _Sectors:
        """The sectors of ``angles`` by direction (cached)."""
        for known in self._known:
            if known.angles is angles or (known.angles.shape == np.shape(angles)
                                          and np.array_equal(known.angles, angles)):
                return known
        sectors = _Sectors(np.asarray(angles, dtype=np.float64), self.n_sectors, self.limits, self.front)
        self._known = [sectors] + self._known[:3]   # a few sensors' geometries
        return sectors


class _Sectors:
    """A geometry's beams by sector: their index, and their order for reducing a sector at a time."""

    def __init__(self, angles: np.ndarray, n_sectors: int, limits, front: float):
        self.angles, self.origins = angles, None
        # raises where the beams cannot fill the sectors
        self.index = sector_index(angles, n_sectors, limits, front)
        self.limits = limits if limits is not None else scan_limits(angles, front)
        inside = np.flatnonzero(self.index >= 0)
        self.order = inside[np.argsort(self.index[inside], kind="stable")]
        if np.array_equal(self.order, np.arange(len(angles))):
            self.order = None   # the beams are in sector order already (a single scan): no gathering
        self.starts = np.searchsorted(self.index[inside][np.argsort(self.index[inside], kind="stable")],
                                      np.arange(n_sectors))

    def nearest(self, ranges: np.ndarray, clip: float | None) -> np.ndarray:
        """Each sector's nearest valid range (``+inf`` where none): ``reduce_sectors(..., "min")``'s values."""
        r = ranges if self.order is None else ranges[self.order]
        ring = np.fmin.reduceat(r, self.starts)   # fmin passes NaN (no information) over
        ring[np.isnan(ring)] = np.inf
        return ring if clip is None else np.minimum(ring, clip)


def _seen_from_centre(origins: np.ndarray, angles: np.ndarray, ranges: np.ndarray):
    """Each beam's end point as a bearing and a range from the base frame's origin."""
    hit = np.isfinite(ranges)
    r = np.where(hit, ranges, 0.0)
    x = origins[:, 0] + r * np.cos(angles)
    y = origins[:, 1] + r * np.sin(angles)
    return np.where(hit, np.arctan2(y, x), angles), np.where(hit, np.hypot(x, y), ranges)
