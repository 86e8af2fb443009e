"""Novelty in the world frame: scans read with the robot's pose, and maps of the world whose cells habituate.

- :mod:`~novelty.maps.points`: the ``points`` input, one row a scan: the
  robot's pose, the paper's ring, and each sector's end point in the world
  frame (from a recording's sweeps: :func:`novelty.io.objects.points.sweep_points`;
  from a sonar ring at known bearings: :func:`~novelty.maps.points.ring_points`);
- :mod:`~novelty.maps.grid_walk` (the cells a ray passes through),
  :mod:`~novelty.maps.scan_rays` (a scan as rays) and
  :mod:`~novelty.maps.tiles` (cells held in tiles, with a bound): what every
  grid of the world reads with;
- :mod:`~novelty.maps.cells`: :class:`WorldCells`, the world's grid cells as
  a clusterer's units, several winners a scan (ours), registered as the
  clusterer ``world-cells``;
- :mod:`~novelty.maps.habituating_map`: :class:`HabituatingMap`, world cells
  composed with any synapse (ours); its presets ``habituating-map``
  (:func:`habituating_map`) and ``map-explore`` (:func:`map_explore`).
"""

from .cells import WorldCells
from .habituating_map import HABITUATING_MAP, MAP_EXPLORE, HabituatingMap, habituating_map, map_explore
from .points import POSE_COLUMNS, check_points, points_columns, ring_points, split_points

__all__ = ["HabituatingMap", "WorldCells", "habituating_map", "map_explore", "HABITUATING_MAP", "MAP_EXPLORE",
           "POSE_COLUMNS", "check_points", "points_columns", "ring_points", "split_points"]
