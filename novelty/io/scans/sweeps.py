"""Whole scans in the robot's base frame, one message at a time: the step every reader and a live node share.

A laser message says where each beam went in the sensor's own frame; the
paper's ring is what the robot sees from its own centre. A
:class:`~novelty.io.ros.messages.Sweep` is the stage between: one whole
scan in the robot's base frame (REP 103: x forward, y left, angles
counter-clockwise), each beam with its origin (the sensor's position in the
base frame), its direction and its range (cleaned as
:func:`novelty.io.scans.ranges.clean_ranges` does), with the robot's pose
in the world at the scan's time.

One message's path, the same for a recording's reader and a live node::

    LaserScan (whole: a scanner's fragments joined by novelty.io.scans.assembly.Assembler)
      + the sensor's mount in the base frame (novelty.io.frames.mounts.Mount: from tf, or the user's)
      + the robot's pose at the scan's time (or None)
      -> SweepMaker (or scan_sweep for one message)                 a Sweep
      -> novelty.io.scans.merge.Merger                               several sensors' sweeps made one
      -> novelty.io.scans.sweep_rings.RingMaker                      the paper's ring
         or novelty.io.scans.points.sweep_points                     the points input's row

- :class:`SweepMaker` places a scan's beams through its sensor's mount
  (:meth:`novelty.io.frames.mounts.Mount.beams`): a centred sensor's beams
  as the scan gives them, any other's origins, directions and range scale
  worked out once for a geometry and mount and kept; a point cloud is
  placed point by point, then flattened all round
  (:func:`novelty.io.ros.clouds.cloud_scan`). A bag's reader
  (:mod:`novelty.io.recording.bag_sweeps`) calls it for each whole scan.
- :func:`scan_sweep` is a scan whose angles are the robot's already, its
  beams from ``scan.origin`` (a CARMEN log's laser), or with ``mount=`` one
  message through a :class:`SweepMaker`.

References
----------
REP 103, "Standard Units of Measure and Coordinate Conventions"; REP 105,
"Coordinate Frames for Mobile Platforms" (the base frame ``base_link``).
"""

from __future__ import annotations

import numpy as np

from ..frames.mounts import Mount
from ..ros.clouds import cloud_scan
from ..ros.messages import LaserScan, Sweep
from ..ros.quaternions import matrix
from .ranges import clean_ranges

__all__ = ["Sweep", "SweepMaker", "scan_sweep", "SweepGeometry"]


class SweepMaker:
    """Whole scans (or point clouds) and their sensors' mounts as sweeps in the base frame ``frame``.

    Keeps, for each topic's beam geometry (count, first angle, spacing) and
    mount, the beams' origins and directions (read-only, shared by that
    geometry's sweeps, so that a ring maker reuses its sectors) and their
    range scale.

    Examples
    --------
    >>> scan = LaserScan(0.0, np.array([1.0, 2.0, np.inf]), angle_min=-np.pi / 2, angle_increment=np.pi / 2)
    >>> sweep = SweepMaker("base_link")(scan, Mount.planar(x=0.5), None, "/scan")
    >>> sweep.origins[0].tolist(), sweep.ranges.tolist(), sweep.frame
    ([0.5, 0.0], [1.0, 2.0, inf], 'base_link')
    """

    def __init__(self, frame: str = ""):
        self.frame = frame
        self.clean_into = None   # compiled, imported at the first scan
        self.geometry: dict[tuple, tuple] = {}

    def __call__(self, scan: LaserScan, mount: Mount, pose, source: str) -> Sweep:
        """The whole ``scan`` of ``source`` (a topic), its sensor placed by ``mount``, as a sweep."""
        key = (source, len(scan.ranges), scan.angle_min, scan.angle_increment)
        known = self.geometry.get(key)
        if known is None or known[0].placement != mount.placement:
            if mount.centred:   # the beams as the scan gives them: a centred laser's ring as it always was
                origins, angles, scale = np.zeros((len(scan.ranges), 2)), scan.angles, None
            else:
                origins, angles, scale = mount.beams(scan.angles)
                scale = None if np.all(scale == 1.0) else scale
            for a in (origins, angles):
                a.flags.writeable = False
            known = self.geometry[key] = (mount, origins, angles, scale)
        _, origins, angles, scale = known
        if self.clean_into is None:
            # deferred: numba's import (about half a second) is paid at the first scan, not by importing
            # novelty.io nor by a recording refused before it
            from ._sweep_kernels import clean_into

            self.clean_into = clean_into
        ranges = np.empty(len(scan.ranges))
        self.clean_into(scan.ranges, scan.range_min, scan.range_max, ranges)   # as clean_ranges, in one pass
        if scale is not None:
            ranges = ranges * scale
        return Sweep(scan.stamp, origins, angles, ranges, pose, self.frame, source)

    def cloud(self, stamp: float, points: np.ndarray, mount: Mount, pose, source: str) -> Sweep:
        """A point cloud's points (sensor frame) placed by ``mount``, then flattened all round from the origin."""
        placement = mount.placement
        points = points @ matrix(placement.rotation).T + np.asarray(placement.translation)
        flat = cloud_scan(points, stamp, source=source)
        angles = flat.angles
        return Sweep(stamp, np.zeros((len(angles), 2)), angles, flat.ranges, pose, self.frame, source)


class SweepGeometry:
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


def scan_sweep(scan: LaserScan, pose=None, frame: str = "", *, mount: Mount | None = None,
               geometry: SweepGeometry | None = None) -> Sweep:
    """One whole laser scan as a sweep in the base frame: the per-message step (module docstring).

    Without ``mount`` the scan's angles are the robot's already and its
    beams start at ``scan.origin`` (a CARMEN log's laser); ``geometry``
    keeps a geometry's arrays between the scans of a reader. With
    ``mount``, the beams are placed through it as :class:`SweepMaker` does.

    Examples
    --------
    >>> scan = LaserScan(1.5, np.array([1.0, -np.inf]), angle_min=0.0, angle_increment=np.pi / 2, range_min=0.2)
    >>> sweep = scan_sweep(scan)
    >>> sweep.time, sweep.angles.round(3).tolist(), sweep.ranges.tolist()
    (1.5, [0.0, 1.571], [1.0, 0.2])
    """
    if mount is not None:
        return SweepMaker(frame)(scan, mount, pose, scan.source)
    angles, origins = (geometry or SweepGeometry()).of(scan)
    return Sweep(scan.stamp, origins, angles, clean_ranges(scan.ranges, scan.range_min, scan.range_max),
                 pose, frame, scan.source)
