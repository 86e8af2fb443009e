"""ROS 2 bags (SQLite ``.db3``, MCAP ``.mcap``, a bag folder), read through ``rosbags`` once their inflation is checked.

- :mod:`~novelty.io.ros2.bag2`: :class:`Bag2`, a bag's topics and its
  messages' bytes, through the optional package ``rosbags`` (the ``ros`` extra);
- :mod:`~novelty.io.ros2.inflation`: every compressed part (an MCAP chunk,
  a file, the messages of the topics read) checked against its cap before
  ``rosbags`` inflates it (:class:`StoredBag`).

Messages are decoded by :mod:`novelty.io.ros`; :class:`novelty.io.bags.rosbag.Bag`
opens a bag of either kind.
"""

from .bag2 import Bag2
from .inflation import MAX_INFLATION, StoredBag, check_inflation

__all__ = ["Bag2", "StoredBag", "check_inflation", "MAX_INFLATION"]
