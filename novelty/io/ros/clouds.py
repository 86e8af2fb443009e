"""Point clouds (``sensor_msgs/PointCloud2``): their points read whatever their layout, flattened all round.

:func:`cloud_points` reads a message's points (fields x, y and z, of any
of PointField's datatypes, at any offsets in a point, points padded in a
row, rows padded in the data), its layout checked against the caps and the
data first (known datatypes, each field within its point, the points within
a row, the rows within the data). :func:`cloud_scan` makes of the points a
planar scan all round: their angles about the sensor's (or, once placed,
the robot's) z axis cut into beams, each beam the horizontal range of its
nearest point, so that the cloud reduces to a ring as a laser scan does
(:mod:`novelty.io.scans`).
"""

from __future__ import annotations

import math

import numpy as np

from . import caps
from .messages import LaserScan
from .wire import Cursor

__all__ = ["cloud_scan", "cloud_points", "POINT_TYPES"]

#: PointField datatypes (sensor_msgs/PointField) as numpy's
POINT_TYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}


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


def cloud_points(c: Cursor, topic: str = "", options: dict | None = None) -> tuple[float, str, np.ndarray]:
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
