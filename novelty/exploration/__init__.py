"""The exploration tasks: features met for the first time, then again and again.

- :mod:`~novelty.exploration.tasks`: exploration tasks (runs in order, every
  scan labelled with the tracked feature it perceives and its exposure count);
- :mod:`~novelty.exploration.objects`: tasks of objects that come and go
  (irregular recurrence, a long absence, a move);
- :mod:`~novelty.exploration.runs`: the runs they are built from.

Their evaluation is the benchmark's: :mod:`novelty.bench.prequential` scores
each scan before learning it (``[suite] protocol = "exploration"`` runs it
from a suite file), with the metrics of
:mod:`novelty.bench.exploration_metrics` (first-encounter detection,
habituation over exposures, false alarms, re-detection, integrated novelty
per run), summarised by :mod:`novelty.bench.exploration_summary` and drawn by
:mod:`novelty.bench.exploration_plots`.
"""

from .objects import irregular, moving, returning
from .tasks import FAMILIAR, Leg, exposures, from_runs, open_door, paper_tour, patrol, simulate_exploration

__all__ = ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
           "simulate_exploration", "irregular", "returning", "moving"]
