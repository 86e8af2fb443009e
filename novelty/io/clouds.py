"""A point cloud (``sensor_msgs/PointCloud2``) flattened into a planar scan all round.

A 3-D lidar's points become the beams of a planar scan: their angles about
the sensor's (or, once placed, the robot's) z axis cut into beams, each
beam the horizontal range of its nearest point, so that the cloud reduces
to a ring as a laser scan does (:mod:`novelty.io.scans`).
"""

from __future__ import annotations

import math

import numpy as np

from .messages import LaserScan

__all__ = ["cloud_scan"]


def cloud_scan(points, stamp: float, resolution: float = math.pi / 180, z_limits=None,
               source: str = "") -> LaserScan:
    """A point cloud flattened into a planar scan all round: each beam the nearest point in its angle.

    The points' angles about the sensor's z axis are cut into beams of
    ``resolution`` radians from -pi; a beam's range is the horizontal
    distance of its nearest point, ``+inf`` where no point falls (no
    return). Points with a non-finite coordinate, and outside ``z_limits``
    (m, e.g. to leave out the floor), are dropped.

    Examples
    --------
    >>> scan = cloud_scan([[1.0, 0.0, 0.0], [2.0, 0.0, 0.5], [0.0, -3.0, 0.0]], 0.0, resolution=np.pi / 2)
    >>> np.rad2deg(scan.angles).tolist(), scan.ranges.tolist()
    ([-180.0, -90.0, 0.0, 90.0], [inf, 3.0, 1.0, inf])
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    keep = np.all(np.isfinite(p), axis=1)
    if z_limits is not None:
        keep &= (p[:, 2] >= z_limits[0]) & (p[:, 2] <= z_limits[1])
    p = p[keep]
    n = int(round(2 * math.pi / resolution))
    beam = np.floor((np.arctan2(p[:, 1], p[:, 0]) + math.pi) / resolution).astype(np.intp) % n
    ranges = np.full(n, np.inf)
    np.minimum.at(ranges, beam, np.hypot(p[:, 0], p[:, 1]))
    return LaserScan(stamp, ranges, angle_min=-math.pi, angle_increment=2 * math.pi / n, source=source)
