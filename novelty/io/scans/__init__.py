"""From range messages to the paper's ring: invalid readings, sweeps in the robot's frame, sectors, rings, points.

The paper's novelty filter takes a ring of ranges, one a sensor around the
robot (16 sonars, Marsland et al. 2000, section 4.1). A robot's recording
holds laser scans (hundreds of beams, from lasers anywhere on the robot,
maybe in fragments) or one ``Range`` message a sonar. One message's way to
a ring, the same for a recording's reader and a live node
(:mod:`~novelty.io.scans.sweeps` draws it):

1. **Invalid readings** (:mod:`~novelty.io.scans.ranges`): ``+inf``,
   ``-inf``, NaN and out-of-range values by REP 117.
2. **Whole scans** (:mod:`~novelty.io.scans.assembly`): a scanner's
   fragments of one revolution joined.
3. **Sweeps** (:mod:`~novelty.io.scans.sweeps`): a whole scan and its
   sensor's mount as beams in the robot's base frame
   (:class:`~novelty.io.scans.sweeps.SweepMaker`, :func:`~novelty.io.scans.sweeps.scan_sweep`);
   several sensors' sweeps merged (:mod:`~novelty.io.scans.merge`).
4. **Rings** (:mod:`~novelty.io.scans.sweep_rings`): a sweep's beams seen
   from the robot's centre, cut into sectors and reduced
   (:mod:`~novelty.io.scans.sectors`: the nearest echo, as a sonar's cone,
   a mean, a median or a percentile); sonar readings gathered into rings
   (:mod:`~novelty.io.scans.sonar_rings`); the same as a scikit-learn
   transformer (:mod:`~novelty.io.scans.laser_sectors`).
5. **The points input** (:mod:`~novelty.io.scans.points`): the robot's
   pose, the ring and each sector's end point in the world, one row a scan.

Then the paper's preprocessing (:class:`novelty.sonar.SonarPreprocessor`:
threshold, normalise, invert).

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
of an environment using habituation. Proc. SAB 2000, section 4.1.
ROS Enhancement Proposal 117, "Informational Distance Measurements".
"""

from .ranges import clean_ranges
from .sectors import REDUCTIONS, SNAP, all_round, reduce_sectors, scan_limits, sector_index
from .sweep_rings import RingMaker, laser_ring, sweep_ring
from .sweeps import SweepMaker, scan_sweep

__all__ = ["clean_ranges", "sector_index", "scan_limits", "all_round", "reduce_sectors", "laser_ring", "REDUCTIONS",
           "SNAP", "RingMaker", "sweep_ring", "SweepMaker", "scan_sweep"]
