"""Novelty in the world frame: maps of the world whose cells habituate, reading scans with the robot's pose.

- the ``points`` input they read, one row a scan: the robot's pose, the
  paper's ring, and each sector's end point in the world frame
  (:mod:`novelty.io.scans.points`, where scans become it; its names are
  importable from here too);
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

from ..io.scans.points import POSE_COLUMNS, check_points, points_columns, ring_points, split_points
from .cells import WorldCells
from .habituating_map import HABITUATING_MAP, MAP_EXPLORE, HabituatingMap, habituating_map, map_explore

__all__ = ["HabituatingMap", "WorldCells", "habituating_map", "map_explore", "HABITUATING_MAP", "MAP_EXPLORE",
           "POSE_COLUMNS", "check_points", "points_columns", "ring_points", "split_points"]
