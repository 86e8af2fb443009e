"""Online k-means (MacQueen 1967): winner-take-all, a fixed number of units.

For each input ``x`` the unit of least squared Euclidean distance wins and
alone moves towards the input; nothing else learns, and no unit is ever added
or removed. With ``learning_rate="count"`` each unit is the running mean of
the inputs it has won (MacQueen's rule), its initial position counting as
one input::

    n_s <- n_s + 1
    w_s <- w_s + (x - w_s) / n_s

and with a constant learning rate eta it follows a moving average that keeps
adapting::

    w_s <- w_s + eta * (x - w_s)

It is the simplest baseline for the clusterer of a novelty filter: what the
topology (SOM, GNG, GWR) and the growth (GNG, GWR) of the others add.

References
----------
MacQueen, J. (1967). Some methods for classification and analysis of
multivariate observations. Proc. 5th Berkeley Symposium on Mathematical
Statistics and Probability, vol. 1, 281-297.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import StateError, check_array_state
from .._validation import Interval, Options
from . import _graph
from .base import NO_GROWTH, NO_UNITS, Clusterer, Growth, Match

__all__ = ["OnlineKMeans"]


class OnlineKMeans(Clusterer):
    """Online k-means (MacQueen): the winner alone moves to the running mean of its inputs.

    Parameters
    ----------
    n_clusters : int, default=10
        Number of units k.
    learning_rate : "count" or float, default="count"
        "count": 1 / n_s, the number of inputs the winner has stood for
        (MacQueen); a float in (0, 1]: that constant rate.
    init : {"sample", "uniform"}, default="sample"
        Initial units: random rows of the first batch (distinct where it has
        enough rows), or drawn uniformly in ``init_range``.
    init_range : tuple of float, default=(0.0, 1.0)
        Range of the uniform initialisation.

    Attributes
    ----------
    weights_ : ndarray of shape (n_clusters, n_features)
        Unit prototypes.
    counts_ : ndarray of shape (n_clusters,), dtype int64
        n_s: inputs each unit stands for (its initial position counts as one).

    References
    ----------
    MacQueen (1967).

    Examples
    --------
    >>> import numpy as np
    >>> km = OnlineKMeans(n_clusters=2).initialize(np.array([[0.0], [1.0]]), random_state=0)
    >>> for x in ([0.2], [0.9], [0.1]):
    ...     _ = km.learn_one(np.array(x))
    >>> sorted(np.round(km.weights_.ravel(), 3).tolist())   # the means of {0, .2, .1} and {1, .9}
    [0.1, 0.95]
    """

    _parameter_rules = {
        "n_clusters": Interval(numbers.Integral, 1, None),
        "learning_rate": (Options(("count",)), Interval(numbers.Real, 0, 1, closed="right")),
        "init": Options(("sample", "uniform")),
    }

    def __init__(self, n_clusters=10, learning_rate="count", init="sample", init_range=(0.0, 1.0)):
        self.n_clusters = n_clusters
        self.learning_rate = learning_rate
        self.init = init
        self.init_range = init_range

    def _validate_params(self) -> None:
        super()._validate_params()
        _graph.check_init_range(self)

    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        self.weights_ = _graph.initial_weights(X, rng, self.n_clusters, self.init, self.init_range)
        self.counts_ = np.ones(self.n_clusters, dtype=np.int64)

    def match(self, x: np.ndarray) -> Match:
        d = ((self.weights_ - x) ** 2).sum(axis=1)
        s = int(np.argmin(d))
        return Match(s, float(d[s]), NO_UNITS)

    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        s = match.winner
        self.counts_[s] += 1
        rate = 1.0 / self.counts_[s] if self.learning_rate == "count" else self.learning_rate
        self.weights_[s] += rate * (x - self.weights_[s])
        return NO_GROWTH

    def _check_state(self) -> None:
        super()._check_state()
        n = self.weights_.shape[0]
        if n != self.n_clusters:
            raise StateError(f"OnlineKMeans.weights_ has {n} units; n_clusters is {self.n_clusters}.")
        counts = check_array_state(self, "counts_", 1, "iu", shape=(n,))
        if np.any(counts < 1):
            raise StateError("OnlineKMeans.counts_ must be at least 1 (the initial position counts).")
