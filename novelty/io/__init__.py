"""Robot recordings and tables of scans in: one folder per layer, and these names over them.

The layers, each a folder that imports only those listed before it:

- :mod:`novelty.io.ros`: the message types every reader returns
  (:class:`LaserScan`, :class:`RangeReading`, :class:`Pose`,
  :class:`Transform`, :class:`Sweep`) and ROS messages decoded from their
  bytes, every stated size checked against a cap;
- the formats, a folder each: :mod:`novelty.io.ros1` (ROS 1 bags, read
  from the format's documented layout), :mod:`novelty.io.ros2` (ROS 2
  bags, ``.db3`` and ``.mcap``, through the optional ``rosbags``, their
  inflation checked first), :mod:`novelty.io.carmen` (CARMEN logs, plain
  or gzipped), :mod:`novelty.io.tables` (every CSV, NPZ and MAT reader, and
  CSV lines as they arrive);
- :mod:`novelty.io.bags`: a bag of either kind opened, its messages
  decoded (:func:`read_bag`), and what a reading found (``ReadReport``);
- :mod:`novelty.io.frames`: the tf tree, each sensor's mount, the robot's
  poses;
- :mod:`novelty.io.scans`: from a message to the paper's ring, one
  message at a time (the step a file reader and a live node share): ranges
  cleaned, fragments assembled, sweeps in the robot's base frame, merged,
  cut into sectors, rings and the ``points`` input;
- :mod:`novelty.io.recording`: a whole recording read, as a
  :class:`Reading` says (:func:`read_sweeps`, :func:`read_rings`,
  :func:`read_recording`).

A new format is a new folder beside the others, and a line in
:mod:`novelty.io.recording` where a recording's name says its format. Every
reader is a generator: it reads the file as the messages are asked for, a
message at a time.
"""

from .bags.rosbag import BagError, bag_topics, read_bag
from .carmen import CarmenError, CarmenLog, read_carmen
from .recording import Reading, Ring, is_recording, read_recording, read_rings, read_sweeps
from .ros.messages import LaserScan, Pose, RangeReading, Sweep, Transform
from .scans import RingMaker, SweepMaker, clean_ranges, laser_ring, scan_sweep, sweep_ring
from .scans.sonar_rings import sonar_rings

__all__ = ["CarmenLog", "CarmenError", "read_carmen", "BagError", "bag_topics", "read_bag", "LaserScan",
           "RangeReading", "Pose", "Transform", "Ring", "read_rings", "read_recording", "is_recording", "clean_ranges",
           "laser_ring", "sonar_rings", "Sweep", "read_sweeps", "sweep_ring", "Reading", "SweepMaker", "scan_sweep",
           "RingMaker"]
