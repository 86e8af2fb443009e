"""Exploration tasks: a sequence of runs in which features appear, recur and change.

- :mod:`~novelty.tasks.exploration.tours`: the named tasks
  (``exploration-tour``, ``exploration-open-door``, ``exploration-patrol``);
- :mod:`~novelty.tasks.exploration.recurrence`: tasks of objects that come
  and go (``exploration-irregular``, ``exploration-return``,
  ``exploration-moving``);
- :mod:`~novelty.tasks.exploration.runs`: building an exploration from
  runs, simulated (:func:`simulate_exploration`) or recorded
  (:func:`from_runs`, also :func:`novelty.tasks.exploration.from_runs`).

They are evaluated by the benchmark's exploration protocol
(:mod:`novelty.bench.exploration`).

Shares its name with ``novelty/bench/exploration/``: the exploration protocol lives in the benchmark
beside the hold-out protocol, its tasks among the tasks.
"""

from .recurrence import irregular, moving, returning
from .runs import FAMILIAR, Leg, exposures, from_runs, simulate_exploration
from .tours import open_door, paper_tour, patrol

__all__ = ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
           "simulate_exploration", "irregular", "returning", "moving"]
