"""The exploration protocol: features met for the first time, then again and again.

- :mod:`~novelty.exploration.tasks`: exploration tasks (runs in order, every
  scan labelled with the tracked feature it perceives and its exposure count);
- :mod:`~novelty.exploration.metrics`: first-encounter detection,
  habituation over exposures, false alarms, re-detection, integrated novelty
  per run.

The streaming harness that scores each scan before learning it is
:mod:`novelty.bench.prequential`; ``[suite] protocol = "exploration"`` runs it
from a suite file.
"""

from .tasks import FAMILIAR, Leg, exposures, from_runs, open_door, paper_tour, patrol, simulate_exploration

__all__ = ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
           "simulate_exploration"]
