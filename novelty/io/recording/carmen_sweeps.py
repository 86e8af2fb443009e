"""A CARMEN log's laser messages as sweeps in the robot's base frame.

A CARMEN laser message's angles are the robot's already (a
``ROBOTLASER1`` states the laser's offset, ``scan.origin``), and its
messages carry the robot's corrected pose; ``pose_topic="ODOM"`` takes the
latest odometry before each scan instead. Each scan becomes a sweep by the
scans layer's one-message step, :func:`novelty.io.scans.sweeps.scan_sweep`.
"""

from __future__ import annotations

from typing import Iterator

import numpy as np

from ..carmen.log import CarmenLog
from ..ros.messages import LaserScan, Pose, Sweep
from ..scans.sweeps import SweepGeometry, scan_sweep

__all__ = ["carmen_sweeps", "CARMEN_SUFFIXES", "CARMEN_LASERS"]

#: File names taken for CARMEN logs (``.clf``: the "CARMEN log file" of some data sets).
CARMEN_SUFFIXES = (".log", ".log.gz", ".clf", ".clf.gz", ".carmen", ".carmen.gz")
#: The CARMEN messages that are laser scans.
CARMEN_LASERS = ("FLASER", "RLASER", "ROBOTLASER1")


def carmen_sweeps(path, topic: str | None, pose_topic: str | None, fov: float) -> Iterator[Sweep]:
    """The sweeps of the CARMEN log ``path``: its ``topic`` laser (default ``FLASER``), posed as ``pose_topic`` says."""
    topic = topic or "FLASER"
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
    geometry = SweepGeometry()
    for msg in messages:
        if isinstance(msg, Pose):
            latest = np.array([msg.x, msg.y, msg.theta])
            continue
        if not isinstance(msg, LaserScan):
            raise ValueError(f"Expected laser scans on the scans' topic; got a {type(msg).__name__}.")
        yield scan_sweep(msg, msg.pose if use_own_pose else latest, geometry=geometry)
