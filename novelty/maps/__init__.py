"""Novelty in the world frame: scans read with the robot's pose, and a map whose cells habituate.

- :mod:`~novelty.maps.points`: the ``points`` input, one row a scan: the
  robot's pose, the paper's ring, and each sector's end point in the world
  frame (from a recording's sweeps: :func:`novelty.io.objects.points.sweep_points`;
  from a sonar ring at known bearings: :func:`~novelty.maps.points.ring_points`);
- :mod:`~novelty.maps.habituating_map`: :class:`HabituatingMap`, the paper's
  architecture with the world's grid cells as its units (ours), registered as
  ``habituating-map``; :func:`map_explore`, its settings for a robot that
  explores (ours), registered as ``map-explore``.
"""

from .habituating_map import MAP_EXPLORE, HabituatingMap, map_explore
from .points import POSE_COLUMNS, check_points, points_columns, ring_points, split_points

__all__ = ["HabituatingMap", "MAP_EXPLORE", "map_explore", "POSE_COLUMNS", "check_points", "points_columns", "ring_points", "split_points"]
