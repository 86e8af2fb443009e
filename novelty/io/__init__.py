"""Robot recordings in: CARMEN logs and ROS bags, laser and sonar messages to the paper's rings.

- :mod:`novelty.io.carmen`: CARMEN logs (``FLASER``, ``RLASER``,
  ``ROBOTLASER1``, ``ODOM``), plain or gzipped.
- :mod:`novelty.io.rosbag`: ROS 1 bags (read from the format's documented
  layout: :mod:`novelty.io.bag1`) and ROS 2 bags (``.db3``, ``.mcap``,
  through the optional package ``rosbags``, the ``ros`` extra); messages
  decoded field by field (:mod:`novelty.io.wire`, :mod:`novelty.io.decoders`),
  every stated size checked against :mod:`novelty.io.caps`.
- :mod:`novelty.io.messages`: the message types the readers return.
- :mod:`novelty.io.scans`: invalid readings by the ROS conventions, a laser
  scan reduced to sectors; :mod:`novelty.io.sectors` the same as a
  scikit-learn transformer; :mod:`novelty.io.sonar_rings` sonar readings
  gathered into rings.
- :mod:`novelty.io.sweeps`: whole scans in the robot's base frame, each
  beam with its origin and direction (:class:`~novelty.io.sweeps.Sweep`),
  and their rings seen from the robot's centre; what a bag's scans go
  through to become sweeps (:mod:`novelty.io.bag_sweeps`): fragments
  assembled (:mod:`novelty.io.assembly`), the tf tree, base frame and poses
  (:mod:`novelty.io.tf`, :mod:`novelty.io.posing`), sensors' mounts
  (:mod:`novelty.io.mounts`), several sensors merged (:mod:`novelty.io.merge`),
  what was found said in a :class:`~novelty.io.report.ReadReport`.
- :mod:`novelty.io.recording`: a recording as rings, or as a dataset of the
  paper's inputs with times, poses and distance travelled.
- :mod:`novelty.io.tasks`: runs, features marked from a CSV or places on a
  grid, visit counts from poses, and exploration tasks from recordings
  (the registered dataset ``recording``).
- :mod:`novelty.io.places`: places and visits from a robot's poses, and the
  exploration task of places met for the first time and again;
  :mod:`novelty.io.radish` that task on the Radish logs
  (``exploration-radish-intel``, ``-aces``, ``-csail``).

Every reader is a generator: it reads the file as the messages are asked
for, a message at a time.
"""

from .carmen import CarmenError, CarmenLog, read_carmen
from .messages import LaserScan, Pose, RangeReading, Transform
from .recording import Ring, is_recording, read_recording, read_rings
from .rosbag import BagError, bag_topics, read_bag
from .scans import clean_ranges, laser_ring
from .sonar_rings import sonar_rings
from .sweeps import Sweep, read_sweeps, sweep_ring

__all__ = ["CarmenLog", "CarmenError", "read_carmen", "BagError", "bag_topics", "read_bag", "LaserScan",
           "RangeReading", "Pose", "Transform", "Ring", "read_rings", "read_recording", "is_recording", "clean_ranges",
           "laser_ring", "sonar_rings", "Sweep", "read_sweeps", "sweep_ring"]
