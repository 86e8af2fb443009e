"""Novelty in the world frame: a map whose cells habituate, reading scans with the robot's pose.

- the ``points`` input it reads, one row a scan: the robot's pose, the
  paper's ring, and each sector's end point in the world frame
  (:mod:`novelty.io.scans.points`, where scans become it; its names are
  importable from here too);
- :mod:`~novelty.maps.habituating_map`: :class:`HabituatingMap`, the paper's
  architecture with the world's grid cells as its units (ours), registered as
  ``habituating-map``; :func:`map_explore`, its settings for a robot that
  explores (ours), registered as ``map-explore``.
"""

from ..io.scans.points import POSE_COLUMNS, check_points, points_columns, ring_points, split_points
from .habituating_map import MAP_EXPLORE, HabituatingMap, map_explore

__all__ = ["HabituatingMap", "MAP_EXPLORE", "map_explore", "POSE_COLUMNS", "check_points", "points_columns", "ring_points", "split_points"]
