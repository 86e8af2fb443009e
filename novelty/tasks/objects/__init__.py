"""Virtual objects placed in a real recording: the paper's question (something new in a known place) on real scans.

- :mod:`~novelty.tasks.objects.shapes`: boxes, cylinders and wall segments in
  the world frame of the recording's poses, each present from ``start`` to ``end``;
- :mod:`~novelty.tasks.objects.raycast`: the objects cast into a sweep (each
  beam's range the nearer of the recorded one and the object's surface
  along it; a sonar's cone sees its nearest point);
- :mod:`~novelty.tasks.objects.casting`: which scans see which object, and the
  robot's passes of it (first sight, then every later exposure);
- :mod:`~novelty.tasks.objects.placement`: objects from the user's CSV or TOML
  file, drawn by a seed beside the path, refused inside what the robot saw
  as solid or on its path;
- :mod:`~novelty.tasks.objects.object_tasks`: an inspection (hold-out) task and an
  exploration task from any recording with poses (registered as
  ``inspection-objects`` and ``exploration-objects``);
  :mod:`novelty.tasks.radish` those of the three Radish logs
  (``inspection-objects-radish-intel``, ... ``exploration-objects-radish-csail``).
"""

from .casting import Cast, cast_all, passes, sightings
from .object_tasks import exploration_task, inspection_task, object_rings
from .placement import check_objects, draw_objects, read_objects, refusals
from .raycast import Injection, beam_ranges, cone_range, inject, world_beams
from .shapes import SHAPES, Box, Cylinder, Wall

__all__ = ["Box", "Cylinder", "Wall", "SHAPES", "Injection", "inject", "beam_ranges", "cone_range", "world_beams",
           "Cast", "cast_all", "sightings", "passes", "read_objects", "refusals", "check_objects", "draw_objects",
           "inspection_task", "exploration_task", "object_rings"]
