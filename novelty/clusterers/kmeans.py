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

With ``init="first"`` the units are placed on the inputs themselves, as
MacQueen places them (the first k inputs are the first k means). The network
starts with one unit on the first input (standing for no input yet:
``n_s = 0``, so that learning that input leaves it there with ``n_s = 1``);
while there are fewer than k units, a later input farther than the
placement radius ``r`` from every unit (any distinct input when ``r = 0``)
becomes a unit of its own (``n_s = 1``) that stands for it as its winner
(``Growth.new_winner``)::

    if n_units < k and min_u ||x - w_u|| > r:   w_new = x,  n_new = 1

and any other input is learned by its winner. ``r = 0`` is MacQueen's start;
``r > 0`` is Hartigan's (1975) leader rule, a new unit for an input no unit
stands for, so that units follow a stream to new places instead of being all
spent on its beginning (ours: the rule capped at k units and combined with
MacQueen's running means). ``placement_radius="auto"`` takes ``r`` from the
match scale of a habituating filter (:meth:`calibrate`; 0 until known). A
stream learned scan by scan and the same scans learned in batches place the
same units. Scoring without learning reads the units placed so far
(:meth:`Clusterer.grows_for` answers None): an input is ranked by how well it
matches them, also when learning it would place a unit.

References
----------
MacQueen, J. (1967). Some methods for classification and analysis of
multivariate observations. Proc. 5th Berkeley Symposium on Mathematical
Statistics and Probability, vol. 1, 281-297.

Hartigan, J. A. (1975). Clustering Algorithms. Wiley, chapter 3 (the leader
algorithm).
"""

from __future__ import annotations

import numbers

import numpy as np

from ..distances import squared_distances
from .._component import KernelSpec, StateError, check_array_state
from .._validation import Bounds, Interval, Options
from . import _graph
from .base import NO_GROWTH, NO_UNITS, Clusterer, Growth, Match, move_towards

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
    init : {"sample", "uniform", "first"}, default="sample"
        Initial units: random rows of the first batch (distinct where it has
        enough rows), drawn uniformly in ``init_range``, or ``"first"``: the
        first ``n_clusters`` inputs learned that are farther than
        ``placement_radius`` from every unit, one unit at a time (see the
        module).
    placement_radius : float >= 0 or "auto", default=0.0
        r, with ``init="first"`` only: an input is placed as a new unit when
        it is farther than r from every unit. 0: every distinct input
        (MacQueen 1967); > 0: Hartigan's (1975) leader rule; ``"auto"``
        (ours): the match scale of the habituating filter the network is in
        (see :meth:`calibrate`).
    init_range : tuple of float, default=(0.0, 1.0)
        Range of the uniform initialisation.

    Attributes
    ----------
    weights_ : ndarray of shape (n_units, n_features)
        Unit prototypes: ``n_clusters`` of them, or with ``init="first"``
        one per distinct input placed so far (at most ``n_clusters``).
    counts_ : ndarray of shape (n_units,), dtype int64
        n_s: inputs each unit stands for (an initial position drawn by
        ``"sample"`` or ``"uniform"`` counts as one).
    placement_radius_ : float
        r in use (``placement_radius``, or the calibrated scale).

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
        "init": Options(("sample", "uniform", "first")),
        "init_range": Bounds(),
        "placement_radius": (Options(("auto",)), Interval(numbers.Real, 0, None)),
    }

    _capabilities = frozenset({"nearest-unit"})  # match: the first unit of least distance

    _kernel = KernelSpec(
        steps="novelty.clusterers._kmeans_steps",
        # init: only "first" changes learning; placement_radius acts through placement_radius_
        params=("n_clusters", "learning_rate", "init", "placement_radius_"),
        arrays=("counts_", "unit_ids_"),
        counters=("next_unit_id_",),
        ignores=("init_range",),
        fitted=(("placement_radius_", float),),
    )

    def __init__(self, n_clusters=10, learning_rate="count", init="sample", init_range=(0.0, 1.0),
                 placement_radius=0.0):
        self.n_clusters = n_clusters
        self.learning_rate = learning_rate
        self.init = init
        self.init_range = init_range
        self.placement_radius = placement_radius

    def _validate_params(self) -> None:
        super()._validate_params()
        if self.init != "first" and self.placement_radius != 0:
            raise ValueError(
                f"The 'placement_radius' parameter of OnlineKMeans places units with init='first' "
                f"only; got placement_radius={self.placement_radius!r} with init={self.init!r}."
            )

    @property
    def uses_match_scale(self) -> bool:
        return self.placement_radius == "auto"

    def calibrate(self, scale: float | None) -> None:
        """Set r to the match scale when ``placement_radius="auto"`` (None: 0, every distinct input)."""
        if self.placement_radius == "auto":
            self.placement_radius_ = 0.0 if scale is None else float(scale)

    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        self.placement_radius_ = 0.0 if self.placement_radius == "auto" else float(self.placement_radius)
        if self.init == "first":
            self.weights_ = X[:1].copy()
            self.counts_ = np.zeros(1, dtype=np.int64)
            return
        self.weights_ = _graph.initial_weights(X, rng, self.n_clusters, self.init, self.init_range)
        self.counts_ = np.ones(self.n_clusters, dtype=np.int64)

    def _placing(self) -> bool:
        return self.init == "first" and self.n_units_ < self.n_clusters

    def match(self, x: np.ndarray) -> Match:
        d = squared_distances(self.weights_, x)
        s = int(np.argmin(d))
        return Match(s, float(d[s]), NO_UNITS)

    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        r = self.placement_radius_
        if self._placing() and match.distance > 0.0 and match.distance > r * r:
            self.weights_ = np.vstack([self.weights_, x[None, :]])
            self.counts_ = np.append(self.counts_, np.int64(1))
            self.unit_ids_ = np.append(self.unit_ids_, self._new_unit_ids(1))
            return Growth(added=1, new_winner=True)
        s = match.winner
        self.counts_[s] += 1
        rate = 1.0 / self.counts_[s] if self.learning_rate == "count" else self.learning_rate
        self.weights_[s] = move_towards(self.weights_[s], x, rate)
        return NO_GROWTH

    def _check_state(self) -> None:
        super()._check_state()
        n = self.weights_.shape[0]
        if n != self.n_clusters and not (self.init == "first" and n < self.n_clusters):
            raise StateError(f"OnlineKMeans.weights_ has {n} units; n_clusters is {self.n_clusters}.")
        counts = check_array_state(self, "counts_", 1, "iu", shape=(n,))
        if not hasattr(self, "placement_radius_"):  # a model file written before the radius existed
            self.placement_radius_ = 0.0
        r = self.placement_radius_
        if isinstance(r, bool) or not isinstance(r, numbers.Real) or not 0 <= r < np.inf:
            raise StateError(f"OnlineKMeans.placement_radius_ must be a finite number >= 0; got {r!r}.")
        least = 0 if self.init == "first" else 1
        if np.any(counts < least):
            raise StateError(f"OnlineKMeans.counts_ must be at least {least}"
                             + (" (the initial position counts)." if least else "."))
