"""A robot recording (a CARMEN log or a ROS bag) as sweeps, as rings, then as a :class:`~novelty.data.Dataset`.

Every reader takes a :class:`~novelty.io.recording.reading.Reading`: which
messages are the scans and where the poses come from, how they become
sweeps, rings or the ``points`` input.

- :func:`read_sweeps` streams a recording's laser scans as sweeps in the
  robot's base frame: a bag's as :mod:`novelty.io.recording.bag_sweeps`
  reads them (fragments assembled, each sensor placed through its mount,
  poses from the tf tree or a pose topic, several sensors merged), a
  CARMEN log's as :mod:`novelty.io.recording.carmen_sweeps` does.
- :func:`read_rings` streams one :class:`Ring` a scan: a sweep reduced to
  sectors (:class:`~novelty.io.scans.sweep_rings.RingMaker`) or one reading
  of every sonar (:func:`novelty.io.scans.sonar_rings.sonar_rings`), with
  its time and the robot's pose when the recording has one.
- :func:`read_recording` collects the rings into a dataset of the paper's
  inputs (threshold, normalise, invert: :func:`novelty.sonar.preprocess`),
  with the time, pose and distance travelled of every scan.

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
from typing import Iterator

import numpy as np

from ...data import Dataset
from ...sonar.preprocessing import preprocess
from ..bags.report import ReadReport
from ..bags.rosbag import SCAN_TYPES, Bag, is_bag
from ..frames.posing import Posing
from ..frames.tf import TfError
from ..ros.messages import Sweep
from ..scans.sonar_rings import sonar_rings
from ..scans.sweep_rings import RingMaker
from .bag_sweeps import bag_sweeps, holds
from .carmen_sweeps import CARMEN_LASERS, CARMEN_SUFFIXES, carmen_sweeps
from .reading import Reading, reading_of

__all__ = ["Ring", "read_sweeps", "read_rings", "read_recording", "is_recording", "bag_scan_topics",
           "CARMEN_SUFFIXES", "CARMEN_LASERS"]


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


def read_sweeps(path, reading: Reading | None = None, *, report: ReadReport | None = None,
                **options) -> Iterator[Sweep]:
    """The recording's laser scans as sweeps in the robot's base frame, one at a time (module docstring).

    Parameters
    ----------
    path : str or Path
        A CARMEN log (plain or gzipped) or a bag (``.bag``, ``.db3``, ``.mcap``).
    reading : Reading, optional
        Which scans and poses, and how a bag's scans are read (``topic``,
        ``pose_topic``, ``base_frame``, ``fragments``, ``mounts``, ``echo``,
        ``tolerance``; ``fov`` for CARMEN's ``FLASER``/``RLASER``).
    report : ReadReport, optional
        Filled with what the reading found and chose (scans assembled, frames, mounts, poses).
    **options
        Deprecated: the options as keywords (and the topic as the second
        argument), which a :class:`FutureWarning` asks to give as a :class:`Reading`.
    """
    reading = reading_of("read_sweeps", reading, options)
    if is_bag(path):
        with Bag(path) as bag:
            yield from bag_sweeps(bag, bag_scan_topics(bag, reading.topics), reading, report)
        return
    if not Path(path).name.lower().endswith(CARMEN_SUFFIXES):
        raise ValueError(f"{path} is neither a CARMEN log ({', '.join(CARMEN_SUFFIXES)}) nor a bag "
                         "(.bag, .db3, .mcap, a ROS 2 bag folder).")
    _no_mounts(reading, f"{path} is a CARMEN log, whose lasers are read as it records them")
    yield from carmen_sweeps(path, reading.topics, reading.pose_topic, reading.fov)


def _no_mounts(reading: Reading, why: str) -> None:
    """Refuse mounts where no laser of a bag is placed by them (rather than leave them unread)."""
    if reading.mounts:
        raise ValueError(f"A mount places a bag's laser on the robot; {why}, and no mount would be read: give "
                         "none (--mount, mounts=).")


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


def read_rings(path, reading: Reading | None = None, *, report: ReadReport | None = None,
               **options) -> Iterator[Ring]:
    """The recording's rings, one at a time (see the module docstring).

    Laser scans and point clouds are read as sweeps in the robot's base
    frame (:func:`read_sweeps`: whole scans, mounts, poses, several sensors
    merged), each reduced to a ring of ``reading.sectors`` sectors
    (:class:`~novelty.io.scans.sweep_rings.RingMaker`: ``reduce``,
    ``limits``, ``front``, ``clip``); sonar ``Range`` readings are gathered
    into rings of one reading a sonar (:func:`novelty.io.scans.sonar_rings.sonar_rings`:
    ``sensors``, ``max_span``), in the order of their mounting angles from
    the tf tree where it places every sonar's frame, counter-clockwise from
    the robot's front.

    Parameters
    ----------
    path : str or Path
        A CARMEN log (plain or gzipped) or a bag (``.bag``, ``.db3``, ``.mcap``).
    reading : Reading, optional
        How the recording is read (default: ``Reading()``).
    report : ReadReport, optional
        Filled with what the reading found and chose.
    **options
        Deprecated: the options as keywords (and the topic as the second
        argument), which a :class:`FutureWarning` asks to give as a :class:`Reading`.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "tiny.log")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("FLASER 4 1.0 2.0 3.0 8.0 0.0 0.0 0.0 0.0 0.0 0.0 10.0 robot 10.0\\n")
    >>> [(ring.time, ring.ranges.tolist()) for ring in read_rings(path, Reading(sectors=2))]
    [(10.0, [1.0, 3.0])]
    """
    reading = reading_of("read_rings", reading, options)
    make_ring = RingMaker(reading.sectors, reading.reduce, reading.limits, reading.front, reading.clip)
    if is_bag(path):
        with Bag(path) as bag:
            topics = bag_scan_topics(bag, reading.topics)
            kinds = {bag.types[t] for t in topics}
            if kinds == {"sensor_msgs/msg/Range"}:
                yield from _bag_sonar(bag, topics, reading, report if report is not None else ReadReport())
                return
            if not kinds <= set(SCAN_TYPES) or "sensor_msgs/msg/Range" in kinds:
                raise ValueError("The scans' topics must be LaserScan, MultiEchoLaserScan, PointCloud2 or Range "
                                 f"topics, lasers or sonars; {holds(topics, kinds)}.")
            for sweep in bag_sweeps(bag, topics, reading, report):
                yield Ring(sweep.time, make_ring(sweep), sweep.pose)
        return
    for sweep in read_sweeps(path, reading, report=report):
        yield Ring(sweep.time, make_ring(sweep), sweep.pose)


def _bag_sonar(bag: Bag, topics: list[str], reading: Reading, report: ReadReport) -> Iterator[Ring]:
    _no_mounts(reading, f"{', '.join(topics)} {'holds' if len(topics) == 1 else 'hold'} sonars' Range readings")
    posing = Posing(bag, reading.pose_topic, reading.base_frame, report, moving_mounts=False)
    by_topic = len(topics) > 1   # one topic a sonar, named by its topic; else the sonars told apart by frame

    def readings(messages):
        for topic, where, msg in messages:
            if not posing.feed(msg, where):
                yield replace(msg, sensor=topic) if by_topic or not msg.sensor else msg

    sensors = reading.sonar_order
    if sensors is None:
        sensors = _mounting_angles(bag, topics, posing, readings, report)
    order = sensors if sensors is not None else (topics if by_topic else None)
    for time, ranges in sonar_rings(readings(bag.messages(topics + posing.topics, nonempty=topics)), order,
                                    reading.max_span):
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


def read_recording(path, reading: Reading | None = None, *, limit: int | None = None,
                   report: ReadReport | None = None, **options) -> Dataset:
    """The recording as a dataset of rings: preprocessed as the paper's, with time, poses and distance.

    Parameters
    ----------
    path : str or Path
        As :func:`read_rings`.
    reading : Reading, optional
        How the recording is read (:func:`read_rings`); its ``threshold`` is
        the paper's preprocessing threshold (m), ``None`` keeping the ranges
        in metres (``+inf`` where a sector saw nothing).
    limit : int, optional
        Read at most this many rings (nothing of the file beyond them).
    report : ReadReport, optional
        Filled with what the reading found and chose.
    **options
        Deprecated: the options as keywords (and the topic as the second
        argument), which a :class:`FutureWarning` asks to give as a :class:`Reading`.

    Returns
    -------
    Dataset
        ``X`` the rings; ``columns["time"]`` the times (s); ``poses`` and
        ``distance`` (the path length travelled, m) where every ring has a pose
        (the scans before the pose topic's first message are left out).
    """
    reading = reading_of("read_recording", reading, options)
    threshold = reading.threshold
    rings = list(itertools.islice(read_rings(path, reading, report=report), limit))
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
    metadata = {"source": str(path), "topic": reading.topics, "skipped_before_first_pose": first_pose,
                "sectors": reading.sectors, "reduce": reading.reduce,
                "encoding": "ranges (m)" if threshold is None else "1 - min(r, T) / T"}
    if threshold is not None:
        metadata["threshold_m"] = float(threshold)
    return Dataset(Path(path).name, X, poses=poses, distance=distance,
                   columns={"time": np.array([r.time for r in rings])}, metadata=metadata)
