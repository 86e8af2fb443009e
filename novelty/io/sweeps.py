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
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from .carmen import CarmenLog
from .messages import LaserScan, Pose, Sweep
from .bag_sweeps import LASER_TYPES, bag_sweeps
from .mounts import Mount, parse_mount
from .report import ReadReport
from .rosbag import SCAN_TYPES, Bag, is_bag
from .scans import clean_ranges
from .sweep_rings import RingMaker

__all__ = ["Sweep", "read_sweeps", "sweep_ring", "RingMaker", "scan_sweep", "bag_scan_topics", "mount_options",
           "reading_given",
           "CARMEN_SUFFIXES", "CARMEN_LASERS", "LASER_TYPES"]

#: File names taken for CARMEN logs (``.clf``: the "CARMEN log file" of some data sets).
CARMEN_SUFFIXES = (".log", ".log.gz", ".clf", ".clf.gz", ".carmen", ".carmen.gz")
#: The CARMEN messages that are laser scans.
CARMEN_LASERS = ("FLASER", "RLASER", "ROBOTLASER1")


# ------------------------------------------------------------------ reading
def read_sweeps(path, topic: str | Sequence[str] | None = None, *, pose_topic: str | None = None,
                base_frame: str | None = None, fov: float = math.pi, fragments="auto", mounts=None,
                echo: str = "first", tolerance: float = 0.1, report: ReadReport | None = None) -> Iterator[Sweep]:
    """The recording's laser scans as sweeps in the robot's base frame, one at a time.

    A bag's scans are read as :mod:`novelty.io.bag_sweeps` says: fragments
    assembled into whole scans, each sensor placed through its mount, poses
    looked up at each scan's time in the tf tree or a pose topic, several
    sensors merged.

    Parameters
    ----------
    path : str or Path
        A CARMEN log (plain or gzipped) or a bag (``.bag``, ``.db3``, ``.mcap``).
    topic : str or sequence of str, optional
        The scans: a CARMEN message (default ``FLASER``; ``RLASER``,
        ``ROBOTLASER1``), or a bag's ``LaserScan``, ``MultiEchoLaserScan`` or
        ``PointCloud2`` topic (default: its only one); several topics (one a
        sensor) are merged into one sweep.
    pose_topic : str, optional
        Where poses come from: a CARMEN log's own corrected poses (None) or
        ``ODOM`` (the latest before each scan); a bag's ``Odometry``,
        ``PoseStamped`` or ``tf`` topic (default: ``/tf`` when it holds a
        moving chain to the base frame), interpolated at each scan's time.
    base_frame : str, optional
        The robot's frame in a bag's tf tree (default: REP 105's ``base_link``,
        else ``base_footprint``).
    fov : float, default=pi
        The field of view (rad) of CARMEN's ``FLASER``/``RLASER``, which do not state it.
    fragments : "auto" or int, default="auto"
        Messages a revolution of a scanner that splits them (:mod:`novelty.io.assembly`): detected, or
        stated; 1 turns assembly off.
    mounts : Mount, str, or dict of topic to Mount or str, optional
        Where a bag's sensor sits when the bag holds no transform for it (or to override the bag's):
        :class:`novelty.io.mounts.Mount`, or ``"X,Y,YAW[,flipped]"`` (m, m, degrees); a dict maps
        topics to mounts, a single mount is every topic's.
    echo : {"first", "last", "strongest"}, default="first"
        The echo of a ``MultiEchoLaserScan``'s beams read.
    tolerance : float, default=0.1
        Seconds within which several sensors' sweeps are merged into one.
    report : ReadReport, optional
        Filled with what the reading found and chose (scans assembled, frames, mounts, poses).
    """
    if is_bag(path):
        with Bag(path) as bag:
            topics = bag_scan_topics(bag, topic)
            yield from bag_sweeps(bag, topics, pose_topic=pose_topic, base_frame=base_frame, fragments=fragments,
                                  mounts=mount_options(mounts), echo=echo, tolerance=tolerance, report=report)
        return
    if not Path(path).name.lower().endswith(CARMEN_SUFFIXES):
        raise ValueError(f"{path} is neither a CARMEN log ({', '.join(CARMEN_SUFFIXES)}) nor a bag "
                         "(.bag, .db3, .mcap, a ROS 2 bag folder).")
    yield from _carmen(path, topic or "FLASER", pose_topic, fov)


def mount_options(mounts) -> dict:
    """``mounts`` as a dict of topic (None: every topic) to :class:`~novelty.io.mounts.Mount`."""
    if mounts is None:
        return {}
    if isinstance(mounts, (str, Mount)):
        mounts = [mounts]
    if isinstance(mounts, dict):
        return {topic: parse_mount(m)[1] if isinstance(m, str) else m for topic, m in mounts.items()}
    out = {}
    for m in mounts:
        topic, mount = parse_mount(m) if isinstance(m, str) else (None, m)
        out[topic] = mount
    return out


def reading_given(fragments="auto", mounts=None, echo: str = "first") -> dict:
    """The options of :func:`read_sweeps` given otherwise than by default, as a task's metadata keeps them.

    Only these enter it, so that a task made before they existed keeps its digest.

    >>> reading_given(mounts="/rear=-0.3,0,180,flipped", echo="last")
    {'mounts': {'/rear': 'x=-0.3 m, y=0 m, yaw=180 deg, upside down, from option'}, 'echo': 'last'}
    """
    given = {}
    if fragments != "auto":
        given["fragments"] = fragments
    if mounts is not None:
        given["mounts"] = {topic or "every scan topic": m.describe() for topic, m in mount_options(mounts).items()}
    if echo != "first":
        given["echo"] = echo
    return given


def bag_scan_topics(bag: Bag, topic) -> list[str]:
    """The scans' topics: those named, or the bag's only scan topic (``LaserScan``, ``PointCloud2``, ``Range``)."""
    if topic is not None:
        topics = [topic] if isinstance(topic, str) else list(topic)
        bag.check(topics)
        return topics
    scans = [t for t, kind in bag.types.items() if kind in SCAN_TYPES]
    if len(scans) != 1:
        raise ValueError(f"Name the scans' topic of {bag.path} (topic=, --topic); its topics: {bag.listing()}.")
    return scans


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
