"""The ROS message layer, shared by both bag formats: the types every reader returns, and their decoding.

- :mod:`~novelty.io.ros.messages`: :class:`LaserScan`, :class:`RangeReading`,
  :class:`Pose`, :class:`Transform` (the fields of ROS's messages; a CARMEN
  log's readings are these types too) and :class:`Sweep`, the whole scan
  in the robot's base frame that the scans layer makes of them;
- :mod:`~novelty.io.ros.caps`: every size a message or chunk states,
  checked against a cap before it is read, and where a message came from;
- :mod:`~novelty.io.ros.wire`: reading a message's bytes field by field
  (ROS 1's serialization and ROS 2's CDR);
- :mod:`~novelty.io.ros.quaternions`: ``geometry_msgs/Quaternion``
  arithmetic (x, y, z, w): the heading a pose's orientation gives, and what
  the frames above compose;
- :mod:`~novelty.io.ros.clouds`: ``sensor_msgs/PointCloud2``'s points, and
  a cloud flattened into a scan all round;
- :mod:`~novelty.io.ros.decoders`: each message type read here, from its bytes.

The formats (:mod:`novelty.io.ros1`, :mod:`novelty.io.ros2`,
:mod:`novelty.io.carmen`) and everything above them import from here;
nothing here imports them.
"""

from .caps import MessageError, Where
from .messages import LaserScan, Pose, RangeReading, Sweep, Transform

__all__ = ["LaserScan", "RangeReading", "Pose", "Transform", "Sweep", "MessageError", "Where"]
