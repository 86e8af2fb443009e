"""A bag of either kind, opened and read: its topics, and their messages decoded; what a reading found.

- :mod:`~novelty.io.bags.rosbag`: :class:`Bag` opens a ROS 1 bag
  (:mod:`novelty.io.ros1`) or a ROS 2 bag (:mod:`novelty.io.ros2`, through
  ``rosbags``) and gives its messages decoded (:mod:`novelty.io.ros`);
  :func:`read_bag` reads topics as a stream of messages;
- :mod:`~novelty.io.bags.report`: :class:`ReadReport`, what a reading found
  and chose (scans assembled, frames, mounts, poses), for the console.
"""

from .report import ReadReport
from .rosbag import Bag, BagError, bag_topics, is_bag, read_bag

__all__ = ["Bag", "BagError", "bag_topics", "is_bag", "read_bag", "ReadReport"]
