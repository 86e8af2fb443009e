"""A robot recording (a CARMEN log or a ROS bag) as rings of ranges, then as a :class:`~novelty.data.Dataset`.

:func:`read_rings` streams one :class:`Ring` a scan: a laser scan read as a
sweep in the robot's base frame and reduced to sectors
(:mod:`novelty.io.sweeps`) or one reading of every sonar
(:func:`novelty.io.sonar_rings.sonar_rings`), with its time and the robot's pose
when the recording has one. :func:`read_recording` collects them into a
dataset of the paper's inputs (threshold, normalise, invert:
:func:`novelty.sonar.preprocess`), with the time, pose and distance
travelled of every scan.

Which messages: in a CARMEN log ``topic`` is a laser message (``FLASER``
by default, ``RLASER``, ``ROBOTLASER1``), whose messages carry the robot's
pose; ``pose_topic="ODOM"`` takes the odometry instead. In a bag ``topic``
is a ``LaserScan`` or ``PointCloud2`` topic, a ``Range`` topic (all sonars on it, told apart
by their frames) or several ``Range`` topics (one a sonar); ``pose_topic``
an ``Odometry``, ``PoseStamped`` or ``tf`` topic (the transforms of
``base_frame``), the latest pose before each ring.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from ..data import Dataset
from ..sonar.preprocessing import PAPER_THRESHOLD, preprocess
from .bag_sweeps import bag_sweeps, holds
from .posing import Posing
from .report import ReadReport
from .rosbag import SCAN_TYPES, Bag, is_bag
from .sonar_rings import sonar_rings
from .sweeps import CARMEN_LASERS, CARMEN_SUFFIXES, RingMaker, bag_scan_topics, mount_options, read_sweeps
from .tf import TfError

__all__ = ["Ring", "read_rings", "read_recording", "is_recording", "CARMEN_SUFFIXES", "CARMEN_LASERS"]


@dataclass(frozen=True, eq=False)
class Ring:
    """One ring of ranges (m, ``+inf`` where nothing was seen), its time (s) and the robot's pose or None."""

    time: float
    ranges: np.ndarray
    pose: np.ndarray | None


def is_recording(path) -> bool:
    """Whether ``path`` names a recording read here: a CARMEN log or a bag, by its name."""
    name = Path(path).name.lower()
    return is_bag(path) or name.endswith(CARMEN_SUFFIXES)


def read_rings(path, topic: str | Sequence[str] | None = None, *, sectors: int = 16, reduce="min",
               limits=None, front: float = 0.0, clip: float | None = None, pose_topic: str | None = None,
               sensors=None, max_span: float | None = None, base_frame: str | None = None, fragments="auto",
               mounts=None, echo: str = "first", tolerance: float = 0.1,
               report: ReadReport | None = None) -> Iterator[Ring]:
    """The recording's rings, one at a time (see the module docstring).

    Laser scans and point clouds are read as sweeps in the robot's base
    frame (:func:`novelty.io.sweeps.read_sweeps`: whole scans, mounts, poses,
    several sensors merged), each reduced to a ring
    (:func:`novelty.io.sweeps.sweep_ring`); sonar ``Range`` readings are
    gathered into rings of one reading a sonar (:func:`novelty.io.sonar_rings.sonar_rings`),
    in the order of their mounting angles from the tf tree where it places
    every sonar's frame, counter-clockwise from the robot's front.

    Parameters
    ----------
    path : str or Path
        A CARMEN log (plain or gzipped) or a bag (``.bag``, ``.db3``, ``.mcap``).
    topic : str or sequence of str, optional
        The scans' topic(s) or CARMEN message (default: ``FLASER``, or a bag's
        only ``LaserScan``, ``MultiEchoLaserScan``, ``PointCloud2`` or ``Range`` topic).
    sectors, reduce, limits, front, clip
        How a sweep becomes a ring (:func:`novelty.io.sweeps.sweep_ring`).
    pose_topic, base_frame, fragments, mounts, echo, tolerance, report
        As :func:`novelty.io.sweeps.read_sweeps`.
    sensors, max_span
        How sonar readings gather into rings (:func:`novelty.io.sonar_rings.sonar_rings`).
    """
    make_ring = RingMaker(sectors, reduce, limits, front, clip)
    options = dict(pose_topic=pose_topic, base_frame=base_frame, fragments=fragments, mounts=mounts, echo=echo,
                   tolerance=tolerance, report=report)
    if is_bag(path):
        with Bag(path) as bag:
            topics = bag_scan_topics(bag, topic)
            kinds = {bag.types[t] for t in topics}
            if kinds == {"sensor_msgs/msg/Range"}:
                yield from _bag_sonar(bag, topics, pose_topic, base_frame, sensors, max_span,
                                      report if report is not None else ReadReport())
                return
            if not kinds <= set(SCAN_TYPES) or "sensor_msgs/msg/Range" in kinds:
                raise ValueError("The scans' topics must be LaserScan, MultiEchoLaserScan, PointCloud2 or Range "
                                 f"topics, lasers or sonars; {holds(topics, kinds)}.")
            options["mounts"] = mount_options(mounts)
            for sweep in bag_sweeps(bag, topics, **options):
                yield Ring(sweep.time, make_ring(sweep), sweep.pose)
        return
    for sweep in read_sweeps(path, topic, **options):
        yield Ring(sweep.time, make_ring(sweep), sweep.pose)


def _bag_sonar(bag: Bag, topics: list[str], pose_topic, base_frame, sensors, max_span,
               report: ReadReport) -> Iterator[Ring]:
    posing = Posing(bag, pose_topic, base_frame, report, moving_mounts=False)
    by_topic = len(topics) > 1   # one topic a sonar, named by its topic; else the sonars told apart by frame

    def readings(messages):
        for topic, _, msg in messages:
            if not posing.feed(msg):
                yield replace(msg, sensor=topic) if by_topic or not msg.sensor else msg

    if sensors is None:
        sensors = _mounting_angles(bag, topics, posing, readings, report)
    order = sensors if sensors is not None else (topics if by_topic else None)
    for time, ranges in sonar_rings(readings(bag.messages(topics + posing.topics, nonempty=topics)), order,
                                    max_span):
        yield Ring(time, ranges, posing.pose(time))


def _mounting_angles(bag: Bag, topics, posing: Posing, readings, report: ReadReport) -> dict | None:
    """Each sonar's mounting angle in [0, 2 pi) from the front, where the tf tree places every sonar's frame."""
    frames = {}
    for reading in itertools.islice(readings(bag.messages(topics)), 200):
        frames.setdefault(reading.sensor, reading.frame)
    placed = {}
    for sensor, frame in frames.items():
        try:
            placed[sensor] = posing.tree.lookup(posing.base, frame, 0.0).planar[2] % (2 * math.pi)
        except TfError:
            pass
    if placed and len(placed) == len(frames):
        report.notes.append("sonars in the order of their mounting angles from tf: " + ", ".join(
            f"{s} {math.degrees(a):.0f} deg" for s, a in sorted(placed.items(), key=lambda kv: kv[1])))
        return placed
    if placed:
        report.notes.append(f"the tf tree places {len(placed)} of {len(frames)} sonars "
                            f"(not {', '.join(sorted(set(frames) - set(placed)))}): sonars in name order")
    return None


def read_recording(path, topic=None, *, threshold: float | None = PAPER_THRESHOLD, limit: int | None = None,
                   **options) -> Dataset:
    """The recording as a dataset of rings: preprocessed as the paper's, with time, poses and distance.

    Parameters
    ----------
    path, topic, **options
        As :func:`read_rings`.
    threshold : float or None, default=4.0
        The paper's preprocessing threshold (m); ``None`` keeps the ranges
        in metres (``+inf`` where a sector saw nothing).
    limit : int, optional
        Read at most this many rings (nothing of the file beyond them).

    Returns
    -------
    Dataset
        ``X`` the rings; ``columns["time"]`` the times (s); ``poses`` and
        ``distance`` (the path length travelled, m) where every ring has a pose
        (the scans before the pose topic's first message are left out).
    """
    rings = list(itertools.islice(read_rings(path, topic, **options), limit))
    first_pose = next((i for i, r in enumerate(rings) if r.pose is not None), 0)
    rings = rings[first_pose:]   # scans before the first pose have no place on the path
    if not rings:
        raise ValueError(f"{path}: no scans read.")
    ranges = np.array([r.ranges for r in rings])
    X = ranges if threshold is None else preprocess(ranges, threshold)
    poses = None
    distance = None
    if all(r.pose is not None for r in rings):
        poses = np.array([r.pose for r in rings], dtype=np.float64)
        steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
        distance = np.concatenate([[0.0], np.cumsum(steps)])
    metadata = {"source": str(path), "topic": topic, "skipped_before_first_pose": first_pose, "sectors": options.get("sectors", 16),
                "reduce": options.get("reduce", "min"),
                "encoding": "ranges (m)" if threshold is None else "1 - min(r, T) / T"}
    if threshold is not None:
        metadata["threshold_m"] = float(threshold)
    return Dataset(Path(path).name, X, poses=poses, distance=distance,
                   columns={"time": np.array([r.time for r in rings])}, metadata=metadata)
