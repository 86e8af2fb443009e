"""The detector that answers each question of "Which detector?", named once.

The guide's generated answers (``benchmarks/which_detector.py``, which says
how each was chosen and what was measured of it), the command line's examples
and the quick benchmark's verdict read the names from here, so that they name
the same detector for the same question.

>>> ANSWERS["frozen"]
'kmeans-stanley'
"""

from __future__ import annotations

__all__ = ["ANSWERS", "FROZEN", "LEARNING", "NO_POSE", "PAPER", "LONG_TERM", "BASELINE"]

#: to learn a clean area, freeze, then flag what differs
FROZEN = "kmeans-stanley"
#: a robot that keeps learning: flag a feature at first sight, then let it grow familiar (the robot's pose
#: with each scan: the points input)
LEARNING = "map-explore"
#: the same on a robot that does not know its pose (the sonar ring alone)
NO_POSE = "gwr-explore-wang-hsu"
#: the paper's exact behaviour (Marsland, Nehmzow & Shapiro 2000)
PAPER = "hsom"
#: long-term habituation: a feature that returns settles lower each time
LONG_TERM = "gwr-explore-wang-hsu"
#: a baseline to beat
BASELINE = "parzen"

#: the answers by the key of their question (the regions ``which-detector/<key>`` of the guide)
ANSWERS = {"frozen": FROZEN, "learning": LEARNING, "no-pose": NO_POSE, "paper": PAPER, "long-term": LONG_TERM,
           "baseline": BASELINE}
