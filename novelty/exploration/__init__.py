"""Explorations: build one from your own runs, or take a named one.

The exploration tasks are datasets (:mod:`novelty.datasets.exploration`;
``novelty.datasets.load("exploration-tour")``); their evaluation, every scan
scored then learned in order, is the benchmark's exploration protocol
(:mod:`novelty.bench.exploration`; ``novelty.bench.run(..., protocol="exploration")``).
This package keeps the short names a script uses:

>>> import numpy as np
>>> from novelty.exploration import from_runs
>>> runs = [np.random.default_rng(i).random((20, 4)) for i in range(3)]
>>> task = from_runs(runs, [[None] * 20, [None] * 15 + ["box"] * 5, ["box"] * 5 + [None] * 15])
>>> int(task.y.sum())
5
"""

from ..datasets.exploration import (FAMILIAR, Leg, exposures, from_runs, irregular, moving, open_door,
                                    paper_tour, patrol, returning, simulate_exploration)

__all__ = ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
           "simulate_exploration", "irregular", "returning", "moving"]
