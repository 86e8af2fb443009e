"""An example novelty plugin: Hartigan's leader clusterer.

Registered through the ``novelty.clusterers`` entry point in this package's
``pyproject.toml``; nothing here imports novelty's registry.
"""

from __future__ import annotations

import numbers

import numpy as np

from novelty import Clusterer
from novelty._validation import Interval
from novelty.clusterers.base import NO_GROWTH, NO_UNITS, Growth, Match

__all__ = ["LeaderClusterer"]


class LeaderClusterer(Clusterer):
    """Hartigan's leader clusterer: a new unit wherever no unit is within `radius`.

    For each input ``x`` the nearest unit ``s`` wins. If ``|x - w_s| > radius``
    a new unit is placed at ``x``; otherwise the winner moves towards it,
    ``w_s <- w_s + eta (x - w_s)``. Units are never removed.

    Parameters
    ----------
    radius : float, default=0.5
        Largest Euclidean distance at which an existing unit stands for an input.
    eta : float, default=0.1
        Learning rate of the winner, in [0, 1].

    References
    ----------
    Hartigan, J. A. (1975). Clustering Algorithms. Wiley, chapter 3.

    Examples
    --------
    >>> import numpy as np
    >>> c = LeaderClusterer(radius=0.5).initialize(np.zeros((1, 2)))
    >>> _ = c.learn_one(np.array([0.1, 0.0])); _ = c.learn_one(np.array([2.0, 0.0]))
    >>> c.n_units_
    2
    """

    _parameter_rules = {
        "radius": Interval(numbers.Real, 0, None, closed="neither"),
        "eta": Interval(numbers.Real, 0, 1),
    }

    def __init__(self, radius=0.5, eta=0.1):
        self.radius = radius
        self.eta = eta

    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        self.weights_ = X[:1].copy()  # the first input leads the first cluster

    def match(self, x: np.ndarray) -> Match:
        d = ((self.weights_ - x) ** 2).sum(axis=1)
        s = int(np.argmin(d))
        return Match(s, float(d[s]), NO_UNITS)

    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        if match.distance > self.radius ** 2:
            self.weights_ = np.vstack([self.weights_, x])
            self.unit_ids_ = np.append(self.unit_ids_, self._new_unit_ids(1))
            return Growth(added=1)
        self.weights_[match.winner] += self.eta * (x - self.weights_[match.winner])
        return NO_GROWTH
