"""ROS 1 bags (``.bag``, format 2.0), read from the format's documented layout, every stated size checked first.

- :mod:`~novelty.io.ros1.bag1`: the bag's records, connections and index,
  and its messages' bytes in record-time order (:class:`Bag1`);
- :mod:`~novelty.io.ros1.chunks`: a chunk inflated only as far as the
  messages asked for need.

Messages are decoded by :mod:`novelty.io.ros`; :class:`novelty.io.bags.rosbag.Bag`
opens a bag of either kind.
"""

from .bag1 import Bag1, BagFormatError

__all__ = ["Bag1", "BagFormatError"]
