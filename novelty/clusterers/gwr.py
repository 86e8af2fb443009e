"""The Grow-When-Required network of Marsland, Shapiro & Nehmzow (2002).

A topology-learning network like Growing Neural Gas, but one that adds a unit
whenever an input is matched badly by a unit that has already learned (fired
often), instead of at fixed intervals: it grows while the inputs show it
something new and stops when they do not.

Every unit has a weight vector ``w`` and a firing counter ``h`` that starts
at ``h0 = 1`` and habituates each time the unit or one of its neighbours
wins; units are joined by edges that carry an age. For each input ``x``
(steps numbered as in the paper's statement of the algorithm; steps 1-3 are
the initialisation, drawing an input and computing the distances):

4. find the best-matching unit s and the second-best t (squared Euclidean
   distance);
5. connect s and t with an edge of age 0 (or reset the age of theirs);
6. the activity of the best-matching unit::

       a = exp(-||x - w_s||)

7. if ``a < a_T`` (``activity_threshold``) and ``h_s < h_T``
   (``habituation_threshold``), add a unit r between the input and s::

       w_r = (w_s + x) / 2

   connected to s and to t, and remove the edge s-t;
8. otherwise move s and its neighbours i, in proportion to their counters::

       w_s <- w_s + epsilon_b * h_s * (x - w_s)
       w_i <- w_i + epsilon_n * h_i * (x - w_i)

9. age every edge of s by one;
10. habituate the firing counters of s (time constant tau_b) and of its
    neighbours i (tau_n), with stimulus S = 1::

        h_s(t) = h0 - S / alpha_b * (1 - exp(-alpha_b * t / tau_b))
        h_i(t) = h0 - S / alpha_n * (1 - exp(-alpha_n * t / tau_n))

11. remove the edges older than ``max_age``, then the units left without
    edges.

The firing counters are a bank of habituating synapses, one per unit: the
project's :class:`~novelty.habituation.stanley.StanleySynapse` by default,
held as ``firing_`` and advanced with its ``step`` (winner s, neighbours i),
``grow`` and ``shrink``. The closed form of step 10 is the solution of
Stanley's equation tau dh/dt = alpha (h0 - h) - S from h(0) = h0 after t
firings, which is what ``method="exact"`` computes one firing at a time
(exp(-alpha/tau) per firing composes to exp(-alpha t / tau)); so the default
counter is ``StanleySynapse(method="exact")`` with tau_b = 3.33 (winner),
tau_n = 14.3 (neighbours), alpha = 1.05, h0 = 1: after its first win a
counter is 0.7425 (the Euler step of the 2000 paper would give 0.6997), and a
unit must win 10 times in a row before h_s < h_T = 0.1. The paper has one
alpha for each of winner and neighbours (both 1.05); a Synapse bank has one
alpha for both. Any other synapse (by registry name or instance) can serve as
the counter; ``others="forget"`` makes counters recover when not stimulated.

The counters count firings, not time: each is one step (dt = 1) whatever
timestamps the caller gives the filter.

Which units learn with the winner, as reported by
:meth:`GrowWhenRequired.match`: its neighbours after step 5, that is its
current neighbours and t. (They do move in step 8 unless a unit is added.)

References
----------
Marsland, S., Shapiro, J. & Nehmzow, U. (2002). A self-organising network
that grows when required. Neural Networks, 15(8-9), 1041-1058.

Stanley, J. C. (1976). Computer simulation of a model of habituation.
Nature, 261, 146-148.

One module although it is long (nearly half of it documentation): the
published algorithm's ten steps, our options for novelty and their checks are
read side by side with the paper; the compiled steps are in ``_gwr_steps``.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..distances import squared_distances
from .._component import MAX_COUNT, KernelSpec, StateError
from ..habituation.stanley import StanleySynapse
from .._validation import Bounds, Instance, Interval, Options
from ..habituation.base import Synapse
from ..match_scale import ScaleCalibration
from ..registry import build
from . import _graph
from .base import Clusterer, Growth, Match, move_towards

__all__ = ["GrowWhenRequired"]

#: Scans of the first batch that calibrate ``activity_threshold="auto"`` in a
#: GWR used alone (a habituating filter's own ``calibration_scans`` default).
_CALIBRATION_SCANS = 200


class GrowWhenRequired(Clusterer):
    """Marsland's Grow-When-Required network: a unit is added where a familiar unit matches badly.

    Parameters
    ----------
    activity_threshold : float or "auto", default=0.85
        a_T: a unit is added when the winner's activity exp(-||x - w_s||)
        falls below it (step 7). The paper tunes a_T to each data set; 0.85
        means an input farther than -ln(0.85) = 0.16 from every unit is new,
        about 4 % of the diameter of the unit cube of 16 sonar readings.
        ``"auto"`` (ours) calibrates it from the data as
        ``a_T = exp(-d_T)`` with the insertion radius
        ``d_T = insertion_radius * sigma``, sigma a match scale
        (:mod:`novelty.match_scale`): in a habituating filter, the filter's
        (see :meth:`calibrate`); alone, the 0.9 quantile of the
        nearest-distinct distances within the first batch's first 200 scans
        (no growth while that is unknown).
    insertion_radius : float, default=1.0
        Ours, used with ``activity_threshold="auto"`` only: the insertion
        radius d_T in units of the match scale sigma, so that it does not
        depend on the scale of the inputs. An input farther than
        ``insertion_radius * sigma`` from its winner is new (step 7); a
        larger radius grows fewer units, so that a recurring input is
        matched by the unit its first occurrence made.
    habituation_threshold : float, default=0.1
        h_T: ... and the winner's firing counter is below it, that is the
        winner has fired often (step 7). The paper: 0.1.
    firing_condition : bool, default=True
        Whether step 7 requires ``h_s < h_T`` (the paper). False (ours):
        an input is given a unit whenever its activity is below a_T, even if
        the winner has not fired often.
    new_unit_wins : bool, default=False
        Ours. The new unit added for an input stands for it as its winner:
        its firing counter fires once for it (tau_b, after step 10), in a
        habituating filter its synapse habituates once for it, and the
        input's novelty is that of the new unit (a fresh synapse's), both
        while learning and when scoring without learning
        (:meth:`grows_for`). False: the paper (the new unit starts
        unhabituated; the novelty is the old winner's).
    epsilon_b : float, default=0.1
        Learning rate of the winner (step 8), scaled by its counter h_s.
    epsilon_n : float, default=0.01
        Learning rate of the neighbours (step 8), scaled by their counters.
        The paper requires 0 < epsilon_n < epsilon_b < 1; 0.1 and 0.01 are
        the values usual in GWR work.
    max_age : int, default=50
        a_max: edges older than this are removed (step 11).
    max_units : int or None, default=None
        No unit is added once the network has this many (None: no limit,
        as in the paper); a badly matched input then adapts the winner.
    firing : str, Synapse or None, default=None
        The firing counters: a synapse registry name (built with that
        synapse's defaults) or an instance (cloned). None is the paper's
        counter, ``StanleySynapse(method="exact")`` with tau_winner = 3.33
        (tau_b), tau_neighbour = 14.3 (tau_n), alpha = 1.05, y0 = 1 (h0).
    init : {"sample", "uniform"}, default="sample"
        The two initial units: distinct random rows of the first batch (the
        paper: "at random from the input distribution"), or drawn uniformly
        in ``init_range``.
    init_range : tuple of float, default=(0.0, 1.0)
        Range of the uniform initialisation.

    Attributes
    ----------
    weights_ : ndarray of shape (n_units, n_features)
        Unit prototypes w.
    firing_ : Synapse
        The firing counters; ``firing_.efficacy_`` of shape (n_units,) is h.
    activity_threshold_ : float
        The a_T in use (``activity_threshold``, or calibrated; 0.0: no
        growth until a scale is known).
    edge_ages_ : ndarray of shape (n_units, n_units), dtype int32
        Age of the edge between two units, -1 where there is none; symmetric.
    unit_ids_ : ndarray of shape (n_units,)
        Stable unit ids; a new unit gets ``next_unit_id_``.

    References
    ----------
    Marsland, Shapiro & Nehmzow (2002), the algorithm's steps 4-11; Stanley (1976).

    Examples
    --------
    >>> import numpy as np
    >>> gwr = GrowWhenRequired().initialize(np.zeros((1, 2)), random_state=0)
    >>> x = np.array([1.0, 0.0])          # far from both units: activity < a_T
    >>> [gwr.learn_one(x)[1].added for _ in range(11)]   # but the winner must fire often first
    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]
    >>> gwr.n_units_, np.round(gwr.weights_[-1], 3).tolist()   # w_r = (w_s + x) / 2
    (3, [0.664, 0.0])
    """

    _parameter_rules = {
        "activity_threshold": (Interval(numbers.Real, 0, 1), Options(("auto",))),
        "insertion_radius": Interval(numbers.Real, 0, None, closed="neither"),
        "habituation_threshold": Interval(numbers.Real, 0, None),
        "firing_condition": Options((True, False)),
        "new_unit_wins": Options((True, False)),
        "epsilon_b": Interval(numbers.Real, 0, 1),
        "epsilon_n": Interval(numbers.Real, 0, 1),
        "max_age": Interval(numbers.Integral, 1, MAX_COUNT),
        "max_units": Interval(numbers.Integral, 2, MAX_COUNT, allow_none=True),
        "firing": (Options((None,)), Instance((str, Synapse), "a synapse name or a Synapse instance")),
        "init": Options(("sample", "uniform")),
        "init_range": Bounds(),
    }

    _capabilities = frozenset({"nearest-unit"})  # match: the first unit of least distance

    _kernel = KernelSpec(
        steps="novelty.clusterers._gwr_steps",
        params=("activity_threshold_", "habituation_threshold", "epsilon_b", "epsilon_n",
                "max_age", "max_units", "firing_condition", "new_unit_wins", "firing_"),
        arrays=("firing_.efficacy_", "edge_ages_", "unit_ids_"),
        square=("edge_ages_",),
        counters=("next_unit_id_",),
        # activity_threshold, insertion_radius and firing act through activity_threshold_
        # and firing_
        ignores=("activity_threshold", "insertion_radius", "firing", "init", "init_range"),
        nested=(("firing_", "novelty.habituation._stanley_steps"),),
        fitted=(("activity_threshold_", float),),
    )

    def __init__(
        self,
        activity_threshold=0.85,
        habituation_threshold=0.1,
        epsilon_b=0.1,
        epsilon_n=0.01,
        max_age=50,
        max_units=None,
        firing=None,
        init="sample",
        init_range=(0.0, 1.0),
        firing_condition=True,
        new_unit_wins=False,
        insertion_radius=1.0,
    ):
        self.activity_threshold = activity_threshold
        self.insertion_radius = insertion_radius
        self.habituation_threshold = habituation_threshold
        self.firing_condition = firing_condition
        self.new_unit_wins = new_unit_wins
        self.epsilon_b = epsilon_b
        self.epsilon_n = epsilon_n
        self.max_age = max_age
        self.max_units = max_units
        self.firing = firing
        self.init = init
        self.init_range = init_range

    def _new_firing_counters(self) -> Synapse:
        if self.firing is None:
            return StanleySynapse(method="exact")
        return build("synapse", self.firing)

    # ------------------------------------------------------------------ step 1
    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        self.weights_ = _graph.initial_weights(X, rng, 2, self.init, self.init_range)
        self.edge_ages_ = _graph.empty_graph(2)
        self.firing_ = self._new_firing_counters().initialize(2)
        if self.activity_threshold == "auto":
            # The first scans only: the nearest-neighbour distances cost the square
            # of their number (a long first batch is slow: docs/guide/performance.md).
            first = X[:_CALIBRATION_SCANS]
            self.calibrate(ScaleCalibration(first, first.shape[0], 0.9).scale)
        else:
            self.activity_threshold_ = float(self.activity_threshold)

    @property
    def uses_match_scale(self) -> bool:
        return self.activity_threshold == "auto"

    def calibrate(self, scale: float | None) -> None:
        """Set a_T = exp(-insertion_radius * scale) when ``activity_threshold="auto"`` (None: 0, no growth)."""
        if self.activity_threshold == "auto":
            self.activity_threshold_ = 0.0 if scale is None else float(np.exp(-self.insertion_radius * scale))

    def grows_for(self, rows: np.ndarray, distances: np.ndarray) -> np.ndarray | None:
        """With ``new_unit_wins``: the inputs step 7 would give a new unit (else None)."""
        if not self.new_unit_wins:
            return None
        grow = np.exp(-np.sqrt(distances)) < self.activity_threshold_
        if self.firing_condition:
            grow &= self.firing_.efficacy_[rows] < self.habituation_threshold
        if self.max_units is not None and self.n_units_ >= self.max_units:
            grow[:] = False
        return grow

    # ---------------------------------------------------------------- steps 3-4
    def match(self, x: np.ndarray) -> Match:
        d = squared_distances(self.weights_, x)
        s = int(np.argmin(d))
        d_s = float(d[s])
        d[s] = np.inf
        t = int(np.argmin(d))
        nb = _graph.neighbours(self.edge_ages_, s)
        if not np.any(nb == t):
            nb = np.sort(np.append(nb, t))
        return Match(s, d_s, nb, t)

    # --------------------------------------------------------------- steps 5-11
    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        s, t = match.winner, match.runner_up
        if t < 0:  # a Match made elsewhere, without the runner-up this network needs
            t = self.match(x).runner_up
        h = self.firing_.efficacy_
        _graph.connect(self.edge_ages_, s, t)                            # step 5
        activity = np.exp(-np.sqrt(squared_distances(x, self.weights_[s])))  # step 6
        added = 0
        if (activity < self.activity_threshold_
                and (h[s] < self.habituation_threshold or not self.firing_condition)
                and (self.max_units is None or self.n_units_ < self.max_units)):
            r = self._append_unit(0.5 * (self.weights_[s] + x))         # step 7
            A = self.edge_ages_
            _graph.connect(A, r, s)
            _graph.connect(A, r, t)
            _graph.disconnect(A, s, t)
            added = 1
        else:
            W = self.weights_                                            # step 8
            nb = _graph.neighbours(self.edge_ages_, s)
            W[s] = move_towards(W[s], x, self.epsilon_b * h[s])
            W[nb] = move_towards(W[nb], x, self.epsilon_n * h[nb, None])
        _graph.age_edges(self.edge_ages_, s)                             # step 9
        self.firing_.step(s, _graph.neighbours(self.edge_ages_, s))      # step 10
        if added and self.new_unit_wins:
            self.firing_.fire(self.n_units_ - 1)
        removed = _graph.prune(self.edge_ages_, s, self.max_age)         # step 11
        if removed.size:
            self._delete_units(removed)
        return Growth(added, removed, new_winner=bool(added) and self.new_unit_wins)

    # -------------------------------------------------------------- structure
    def _append_unit(self, weight: np.ndarray) -> int:
        self.weights_ = np.vstack([self.weights_, weight[None, :]])
        self.edge_ages_ = _graph.add_units(self.edge_ages_, 1)
        self.firing_.grow(1)
        self.unit_ids_ = np.append(self.unit_ids_, self._new_unit_ids(1))
        return self.n_units_ - 1

    def _delete_units(self, rows: np.ndarray) -> None:
        self.weights_ = np.delete(self.weights_, rows, axis=0)
        self.edge_ages_ = _graph.delete_units(self.edge_ages_, rows)
        self.firing_.shrink(rows)
        self.unit_ids_ = np.delete(self.unit_ids_, rows)

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Every edge once: ``(pairs, ages)`` with pairs of rows ``i < j``."""
        return _graph.edge_list(self.edge_ages_)

    def activity(self, X) -> np.ndarray:
        """The activity exp(-||x - w_s||) of the best-matching unit for each row of ``X`` (step 6)."""
        _, d = self.winners(np.atleast_2d(np.asarray(X, dtype=np.float64)))
        return np.exp(-np.sqrt(d))

    def _check_state(self) -> None:
        super()._check_state()
        n = self.weights_.shape[0]
        if n < 2:
            raise StateError("GrowWhenRequired needs at least two units.")
        _graph.check_graph(self, "edge_ages_", n)
        firing = getattr(self, "firing_", None)
        if not isinstance(firing, Synapse):
            raise StateError("GrowWhenRequired state is missing its firing counters 'firing_'.")
        if firing.n_units_ != n:
            raise StateError(f"GrowWhenRequired.firing_ has {firing.n_units_} counters for {n} units.")
        if not hasattr(self, "activity_threshold_") and self.activity_threshold != "auto":
            self.activity_threshold_ = float(self.activity_threshold)  # a file from before "auto"
        a_t = getattr(self, "activity_threshold_", None)
        if isinstance(a_t, bool) or not isinstance(a_t, numbers.Real) or not 0 <= a_t <= 1:
            raise StateError(f"GrowWhenRequired.activity_threshold_ must be a number in [0, 1]; got {a_t!r}.")
        firing.check_efficacy(1.0)  # step 10 presents S = 1
