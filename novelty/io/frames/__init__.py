"""Where things are: the tf tree, each sensor's mount on the robot, and the robot's poses in a recording.

- :mod:`~novelty.io.frames.tf`: a transform tree as tf2 keeps one
  (:class:`TfBuffer`: static and moving frames, chained lookups at a time,
  interpolated), and :class:`Placement`, a rigid transform;
- :mod:`~novelty.io.frames.mounts`: where a sensor sits on the robot
  (:class:`Mount`: from tf, the user's option, or assumed) and its beams
  moved into the robot's base frame;
- :mod:`~novelty.io.frames.posing`: a bag's frames (its tree, the robot's
  base frame in it) and where the robot's poses come from (:class:`Posing`).

Quaternion arithmetic is the message layer's (:mod:`novelty.io.ros.quaternions`):
the decoders read headings from orientations with it.
"""

from .mounts import MAX_TILT, Mount, parse_mount
from .posing import Posing
from .tf import Placement, TfBuffer, TfError

__all__ = ["TfBuffer", "TfError", "Placement", "Mount", "MAX_TILT", "parse_mount", "Posing"]
