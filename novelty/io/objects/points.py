"""A recording's sweeps as the ``points`` input: the pose, the paper's ring and each sector's end point in the world.

:mod:`novelty.maps.points` defines the layout (``x, y, heading``, ``n``
nearness values, ``n`` end points' x, then y). From a sweep
(:class:`novelty.io.sweeps.Sweep`: beams in the base frame, mounts
included, and the robot's pose):

- the ring: :func:`novelty.io.sweeps.sweep_ring` with the nearest echo,
  preprocessed as the paper does (``1 - min(r, T) / T``), the same values
  as the ring input :func:`~novelty.io.objects.tasks.object_rings` gives;
- each sector's end point: that of the sector's nearest beam (the sectors
  cut by the beams' directions, :func:`novelty.io.scans.sector_index`; the
  ring's own where the sensor sits at the base frame's origin, as in the
  Radish logs), moved into the world frame by the pose; a sector whose
  nearest echo lies beyond ``T`` (or that has none) ends ``T`` from the
  robot's centre along the direction of that beam (of its middle beam if
  none returned).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ...maps.points import points_columns
from ...sonar.preprocessing import preprocess
from ..scans import sector_index
from ..sweeps import RingMaker

__all__ = ["sweep_points", "points_columns"]


def sweep_points(sweeps: Sequence, sectors: int = 16, threshold: float = 4.0) -> np.ndarray:
    """Each sweep (with its pose) as a ``points`` row of ``3 + 3 sectors`` columns (module docstring).

    Examples
    --------
    >>> from novelty.io.sweeps import Sweep
    >>> ahead = Sweep(0.0, np.zeros((4, 2)), np.deg2rad([-67.5, -22.5, 22.5, 67.5]),
    ...               np.array([1.0, 2.0, np.inf, 3.0]), np.array([10.0, 5.0, np.pi / 2]))
    >>> sweep_points([ahead], sectors=2).round(3).tolist()   # facing +y: 1 m to its right, 3 m ahead-left
    [[10.0, 5.0, 1.571, 0.75, 0.25, 10.924, 7.228, 5.383, 6.148]]
    """
    if isinstance(sectors, bool) or not isinstance(sectors, (int, np.integer)) or sectors < 1:
        raise ValueError(f"The points input needs one number of sectors (an int >= 1); got {sectors!r}.")
    maker = RingMaker(int(sectors), "min")
    rows = []
    for sweep in sweeps:
        if sweep.pose is None:
            raise ValueError(f"The sweep at t={sweep.time} has no pose: the points input places each echo in the "
                             "world frame (give the recording's poses, pose_topic=).")
        near = preprocess(maker(sweep), threshold)
        ends = _sector_ends(sweep, int(sectors), threshold)
        x, y, yaw = (float(v) for v in sweep.pose)
        c, s = math.cos(yaw), math.sin(yaw)
        world_x = x + c * ends[:, 0] - s * ends[:, 1]
        world_y = y + s * ends[:, 0] + c * ends[:, 1]
        heading = (yaw + math.pi) % (2 * math.pi) - math.pi
        rows.append(np.r_[x, y, heading, near, world_x, world_y])
    return np.array(rows, dtype=np.float64).reshape(-1, 3 + 3 * int(sectors))


def _sector_ends(sweep, sectors: int, threshold: float) -> np.ndarray:
    """Each sector's end point in the base frame: its nearest beam's echo, or ``threshold`` along it."""
    angles = np.asarray(sweep.angles, dtype=np.float64)
    ranges = np.asarray(sweep.ranges, dtype=np.float64)
    origins = np.asarray(sweep.origins, dtype=np.float64).reshape(-1, 2)
    echo = np.isfinite(ranges)
    unit = np.c_[np.cos(angles), np.sin(angles)]
    ends = origins + np.where(echo, ranges, 0.0)[:, None] * unit
    distance = np.where(echo, np.hypot(ends[:, 0], ends[:, 1]), np.inf)
    index = sector_index(angles, sectors)
    out = np.empty((sectors, 2))
    for k in range(sectors):
        beams = np.flatnonzero(index == k)
        j = beams[np.argmin(distance[beams])] if np.isfinite(distance[beams]).any() else beams[len(beams) // 2]
        if distance[j] <= threshold:
            out[k] = ends[j]
        else:
            direction = ends[j] if echo[j] else unit[j]
            out[k] = threshold * direction / np.hypot(*direction)
    return out
