"""Fritzke's Growing Neural Gas: a network that learns the topology of its inputs.

Units carry a weight vector ``w`` and an accumulated error ``E``, and are
joined by edges that carry an age. For each input ``x`` (steps as numbered in
Fritzke 1995, section 3):

2. find the nearest unit s1 and the second-nearest s2 (squared Euclidean
   distance);
3. age every edge of s1 by one;
4. accumulate the squared distance in the winner's error::

       E_s1 <- E_s1 + ||x - w_s1||^2

5. move s1 and its topological neighbours n (the units it has an edge to)
   towards the input::

       w_s1 <- w_s1 + epsilon_b * (x - w_s1)
       w_n  <- w_n  + epsilon_n * (x - w_n)

6. connect s1 and s2 with an edge of age 0 (or reset the age of theirs);
7. remove the edges older than ``max_age``, then the units left without edges;
8. every ``insertion_interval`` (lambda) inputs, unless ``max_units`` are
   reached: take the unit q of largest error and its neighbour f of largest
   error, put a new unit r halfway between them, replace the edge q-f by q-r
   and r-f, and share out the error::

       w_r = (w_q + w_f) / 2
       E_q <- alpha * E_q,   E_f <- alpha * E_f,   E_r = E_q

9. let every error decay::

       E <- (1 - beta) * E

The network starts (step 0) with two units and no edges. The units that learn
with the winner, reported by :meth:`GrowingNeuralGas.match`, are its
topological neighbours at the time of the input (before step 6).

References
----------
Fritzke, B. (1995). A growing neural gas network learns topologies. In
G. Tesauro, D. S. Touretzky & T. K. Leen (eds.), Advances in Neural
Information Processing Systems 7, 625-632. MIT Press.

Fritzke, B. (1997). Some competitive learning methods. Technical report,
Institute for Neural Computation, Ruhr-Universitaet Bochum (the error decay
written as E <- E - beta * E).
"""

from __future__ import annotations

import numbers

import numpy as np

from ..distances import squared_distances
from .._component import MAX_COUNT, KernelSpec, StateError, check_array_state, check_int_state
from .._validation import Bounds, Interval, Options
from . import _graph
from .base import Clusterer, Growth, Match, move_towards

__all__ = ["GrowingNeuralGas"]


class GrowingNeuralGas(Clusterer):
    """Fritzke's Growing Neural Gas: units and edges inserted where the error is largest.

    Parameters
    ----------
    epsilon_b : float, default=0.2
        Learning rate of the winner (step 5). Fritzke (1995): 0.2.
    epsilon_n : float, default=0.006
        Learning rate of the winner's topological neighbours (step 5).
        Fritzke (1995): 0.006.
    insertion_interval : int, default=100
        lambda: a unit is inserted after every ``insertion_interval`` inputs
        (step 8). Fritzke (1995): 100.
    insertion_error_decay : float, default=0.5
        alpha: the factor applied to the errors of q and f when a unit is
        inserted between them (step 8). Fritzke (1995): 0.5.
    error_decay : float, default=0.0005
        beta: the fraction of every error lost after each input (step 9),
        E <- (1 - beta) E. Fritzke (1997) uses 0.0005; Fritzke (1995) writes
        the factor as d = 0.995, which is ``error_decay=0.005``.
    max_age : int, default=50
        a_max: edges older than this are removed (step 7). Fritzke (1995): 50.
    max_units : int, default=100
        No unit is inserted once the network has this many.
    init : {"sample", "uniform"}, default="sample"
        The two initial units: distinct random rows of the first batch (the
        paper: "at random positions according to P(x)"), or drawn uniformly
        in ``init_range``.
    init_range : tuple of float, default=(0.0, 1.0)
        Range of the uniform initialisation.

    Attributes
    ----------
    weights_ : ndarray of shape (n_units, n_features)
        Unit prototypes w.
    errors_ : ndarray of shape (n_units,)
        Accumulated error E of each unit.
    edge_ages_ : ndarray of shape (n_units, n_units), dtype int32
        Age of the edge between two units, -1 where there is none; symmetric.
    n_inputs_ : int
        Inputs learned so far (the count lambda divides).
    unit_ids_ : ndarray of shape (n_units,)
        Stable unit ids; a new unit gets ``next_unit_id_``.

    References
    ----------
    Fritzke (1995), section 3, steps 0-9; Fritzke (1997) for beta.

    Examples
    --------
    >>> import numpy as np
    >>> X = np.random.default_rng(0).random((500, 2))
    >>> gng = GrowingNeuralGas(insertion_interval=50).initialize(X, random_state=0)
    >>> for x in X:
    ...     _ = gng.learn_one(x)
    >>> gng.n_units_                      # two, plus one every 50 inputs
    12
    >>> bool(np.all((gng.edge_ages_ >= 0).any(axis=1)))   # no unit without an edge
    True
    """

    _parameter_rules = {
        "epsilon_b": Interval(numbers.Real, 0, 1),
        "epsilon_n": Interval(numbers.Real, 0, 1),
        "insertion_interval": Interval(numbers.Integral, 1, MAX_COUNT),
        "insertion_error_decay": Interval(numbers.Real, 0, 1),
        "error_decay": Interval(numbers.Real, 0, 1),
        "max_age": Interval(numbers.Integral, 1, MAX_COUNT),
        "max_units": Interval(numbers.Integral, 2, MAX_COUNT),
        "init": Options(("sample", "uniform")),
        "init_range": Bounds(),
    }

    _capabilities = frozenset({"nearest-unit"})  # match: the first unit of least distance

    _kernel = KernelSpec(
        steps="novelty.clusterers._gng_steps",
        params=("epsilon_b", "epsilon_n", "insertion_interval", "insertion_error_decay",
                "error_decay", "max_age", "max_units"),
        arrays=("errors_", "edge_ages_", "unit_ids_"),
        square=("edge_ages_",),
        counters=("n_inputs_", "next_unit_id_"),
        ignores=("init", "init_range"),
    )

    def __init__(
        self,
        epsilon_b=0.2,
        epsilon_n=0.006,
        insertion_interval=100,
        insertion_error_decay=0.5,
        error_decay=0.0005,
        max_age=50,
        max_units=100,
        init="sample",
        init_range=(0.0, 1.0),
    ):
        self.epsilon_b = epsilon_b
        self.epsilon_n = epsilon_n
        self.insertion_interval = insertion_interval
        self.insertion_error_decay = insertion_error_decay
        self.error_decay = error_decay
        self.max_age = max_age
        self.max_units = max_units
        self.init = init
        self.init_range = init_range

    # ------------------------------------------------------------------ step 0
    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        self.weights_ = _graph.initial_weights(X, rng, 2, self.init, self.init_range)
        self.errors_ = np.zeros(2)
        self.edge_ages_ = _graph.empty_graph(2)
        self.n_inputs_ = 0

    # ------------------------------------------------------------------ step 2
    def match(self, x: np.ndarray) -> Match:
        d = squared_distances(self.weights_, x)
        s1 = int(np.argmin(d))
        d1 = float(d[s1])
        d[s1] = np.inf
        s2 = int(np.argmin(d))
        return Match(s1, d1, _graph.neighbours(self.edge_ages_, s1), s2)

    # ---------------------------------------------------------------- steps 3-9
    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        s1, s2 = match.winner, match.runner_up
        if s2 < 0:  # a Match made elsewhere, without the runner-up this network needs
            s2 = self.match(x).runner_up
        W, A = self.weights_, self.edge_ages_
        nb = _graph.neighbours(A, s1)
        _graph.age_edges(A, s1)                                          # step 3
        self.errors_[s1] += float(squared_distances(x, W[s1]))          # step 4
        W[s1] = move_towards(W[s1], x, self.epsilon_b)                   # step 5
        W[nb] = move_towards(W[nb], x, self.epsilon_n)
        _graph.connect(A, s1, s2)                                        # step 6
        removed = _graph.prune(A, s1, self.max_age)                      # step 7
        if removed.size:
            self._delete_units(removed)
        self.n_inputs_ += 1
        added = 0
        if self.n_inputs_ % self.insertion_interval == 0 and self.n_units_ < self.max_units:
            self._insert_unit()                                          # step 8
            added = 1
        self.errors_ *= 1.0 - self.error_decay                           # step 9
        return Growth(added, removed)

    def _insert_unit(self) -> None:
        E, A = self.errors_, self.edge_ages_
        q = int(np.argmax(E))
        nq = _graph.neighbours(A, q)
        f = int(nq[np.argmax(E[nq])])
        E[q] *= self.insertion_error_decay
        E[f] *= self.insertion_error_decay
        w_r = 0.5 * (self.weights_[q] + self.weights_[f])
        r = self._append_unit(w_r, E[q])
        A = self.edge_ages_
        _graph.disconnect(A, q, f)
        _graph.connect(A, q, r)
        _graph.connect(A, r, f)

    # -------------------------------------------------------------- structure
    def _append_unit(self, weight: np.ndarray, error: float) -> int:
        self.weights_ = np.vstack([self.weights_, weight[None, :]])
        self.errors_ = np.append(self.errors_, error)
        self.edge_ages_ = _graph.add_units(self.edge_ages_, 1)
        self.unit_ids_ = np.append(self.unit_ids_, self._new_unit_ids(1))
        return self.n_units_ - 1

    def _delete_units(self, rows: np.ndarray) -> None:
        self.weights_ = np.delete(self.weights_, rows, axis=0)
        self.errors_ = np.delete(self.errors_, rows)
        self.edge_ages_ = _graph.delete_units(self.edge_ages_, rows)
        self.unit_ids_ = np.delete(self.unit_ids_, rows)

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Every edge once: ``(pairs, ages)`` with pairs of rows ``i < j``."""
        return _graph.edge_list(self.edge_ages_)

    def _check_state(self) -> None:
        super()._check_state()
        n = self.weights_.shape[0]
        if n < 2:
            raise StateError("GrowingNeuralGas needs at least two units.")
        errors = check_array_state(self, "errors_", 1, shape=(n,))
        if np.any(errors < 0):
            raise StateError("GrowingNeuralGas.errors_ must not be negative.")
        _graph.check_graph(self, "edge_ages_", n)
        check_int_state(self, "n_inputs_")
