"""The habituating novelty filter: a clusterer composed with a synapse bank.

Marsland, Nehmzow & Shapiro (2000), section 2: each input is presented to a
clustering network; every unit connects to an output neuron through a
habituating synapse; the efficacy of the winner's synapse is the novelty of
the input. For each scan, in order:

1. the clusterer finds the winner (and the units that learn with it);
2. the novelty is the winner's efficacy *before* this scan is learned;
3. when learning, the winner's and neighbours' synapses habituate (stimulus
   S = 1) and the clusterer adapts, possibly adding or removing units, which
   the synapse bank follows.

With learning off (the paper's non-learning runs) the output is a pure
function of the state, computed for a whole batch at once.

The per-scan loop is :func:`learn_stream`, on plain arrays, in one place.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.base import clone

from . import _kernels
from ._validation import Instance, Interval
from .clusterers.base import Clusterer
from .detector import NoveltyDetector
from .habituation.base import Synapse
from .registry import InvalidParameterError, check_parameters

__all__ = ["HabituatingFilter", "learn_stream", "hsom"]


def learn_stream(clusterer: Clusterer, synapse: Synapse, X: np.ndarray, dt: np.ndarray,
                 stimulus: float = 1.0) -> np.ndarray:
    """Present the rows of ``X`` in order, learning; return each row's novelty.

    This is the reference implementation of the filter's learning loop: the
    readable version any faster kernel must reproduce.
    """
    novelty = np.empty(X.shape[0])
    for i in range(X.shape[0]):
        x = X[i]
        match = clusterer.match(x)
        novelty[i] = synapse.efficacy_[match.winner]
        # Habituate on the rows of this match before the network may renumber them.
        synapse.step(match.winner, match.neighbours, stimulus, dt[i])
        growth = clusterer.adapt(x, match)
        if growth.removed.size:
            synapse.shrink(growth.removed)
        if growth.added:
            synapse.grow(growth.added)
    return novelty


class HabituatingFilter(NoveltyDetector):
    """A novelty filter made of any clusterer and any habituating synapse.

    Parameters
    ----------
    clusterer : str or Clusterer, default="som"
        The clustering network, by registry name (with its defaults) or as an
        instance (cloned in ``fit``; its parameters are reachable as
        ``clusterer__<name>`` for ``set_params`` and grid searches).
    synapse : str or Synapse, default="stanley"
        The synapse model, by name or instance.
    threshold : float, default=0.5
        Novelty above which :meth:`predict` calls a scan novel.
    stimulus : float, default=1.0
        Stimulus S presented to the winning neighbourhood's synapses.
    n_epochs : int, default=1
        Passes over the data in :meth:`fit` (the robot's repeated runs).
    random_state : int, numpy Generator or None, default=0
        Seed of the clusterer's initialisation.

    Attributes
    ----------
    clusterer_ : Clusterer
        The fitted network.
    synapse_ : Synapse
        The fitted synapse bank, one synapse per unit of ``clusterer_``.
    n_features_in_ : int
        Number of features of the inputs.

    References
    ----------
    Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
    of an environment using habituation. Proc. SAB 2000, section 2.

    Examples
    --------
    >>> import numpy as np
    >>> import novelty
    >>> det = novelty.make("hsom")
    >>> scan = np.full(16, 0.5)
    >>> [round(det.score_learn_one(scan), 4) for _ in range(4)]
    [1.0, 0.6997, 0.4941, 0.3533]
    """

    _parameter_rules = {
        "clusterer": Instance((str, Clusterer), "a clusterer name or a Clusterer instance"),
        "synapse": Instance((str, Synapse), "a synapse name or a Synapse instance"),
        "threshold": Interval(numbers.Real, None, None),
        "stimulus": Interval(numbers.Real, 0, None),
        "n_epochs": Interval(numbers.Integral, 1, None),
    }

    def __init__(self, clusterer="som", synapse="stanley", threshold=0.5, stimulus=1.0,
                 n_epochs=1, random_state=0):
        self.clusterer = clusterer
        self.synapse = synapse
        self.threshold = threshold
        self.stimulus = stimulus
        self.n_epochs = n_epochs
        self.random_state = random_state

    # ------------------------------------------------------------ construction
    @classmethod
    def from_params(cls, clusterer="som", synapse="stanley", **params):
        """Build a filter from component names and one flat set of parameters.

        Each parameter goes to whichever of the filter, the clusterer or the
        synapse takes it; ``clusterer__name`` / ``synapse__name`` settle a name
        both components take.

        >>> det = HabituatingFilter.from_params("som", "stanley", n_rows=5, alpha=1.2)
        >>> det.clusterer.n_rows, det.synapse.alpha
        (5, 1.2)
        """
        from .registry import clusterers, synapses

        own_names = cls._get_param_names()
        own = {k: params.pop(k) for k in list(params) if k in own_names}
        parts = {"clusterer": (clusterer, clusterers), "synapse": (synapse, synapses)}
        routed: dict[str, dict] = {"clusterer": {}, "synapse": {}}
        valid: dict[str, list[str]] = {}
        for part, (spec, registry) in parts.items():
            if isinstance(spec, str):
                valid[part] = registry.parameters(spec) or []
            else:
                valid[part] = list(spec.get_params(deep=False))
        for key, value in params.items():
            part, _, name = key.partition("__")
            if name and part in routed:
                check_parameters(f"{part} {parts[part][0]!r}", {name: value}, valid[part])
                routed[part][name] = value
                continue
            takers = [p for p in routed if key in valid[p]]
            if len(takers) > 1:
                raise InvalidParameterError(
                    f"Parameter '{key}' is taken by both the clusterer and the synapse; "
                    f"write clusterer__{key} or synapse__{key}."
                )
            if not takers:
                all_valid = own_names + [n for p in routed for n in valid[p]]
                check_parameters("the habituating filter", {key: value}, all_valid)
            routed[takers[0]][key] = value
        built = {}
        for part, (spec, registry) in parts.items():
            if isinstance(spec, str):
                built[part] = registry.make(spec, **routed[part])
            else:
                built[part] = clone(spec).set_params(**routed[part])
        return cls(clusterer=built["clusterer"], synapse=built["synapse"], **own)

    def _component(self, spec, kind: str):
        from .registry import clusterers, synapses

        registry = clusterers if kind == "clusterer" else synapses
        return registry.make(spec) if isinstance(spec, str) else clone(spec)

    # ------------------------------------------------------------------- hooks
    def _start(self, X: np.ndarray) -> None:
        clusterer = self._component(self.clusterer, "clusterer")
        synapse = self._component(self.synapse, "synapse")
        clusterer.initialize(X, self.random_state)
        synapse.initialize(clusterer.n_units_)
        self.clusterer_ = clusterer
        self.synapse_ = synapse

    # The three hooks below first ask novelty._kernels for a compiled kernel for
    # this (clusterer, synapse) pair (issue 7); a kernel gives the same results
    # as the reference code after it, which runs when there is none.
    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        kernel = _kernels.learner(self.clusterer_, self.synapse_)
        if kernel is not None:
            return kernel(self.clusterer_, self.synapse_, X, dt, float(self.stimulus))
        return learn_stream(self.clusterer_, self.synapse_, X, dt, float(self.stimulus))

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        kernel = _kernels.scorer(self.clusterer_, self.synapse_)
        if kernel is not None:
            return kernel(self.clusterer_, self.synapse_, X)
        rows, _ = self.clusterer_.winners(X)
        return self.synapse_.efficacy_[rows]

    def _novelty_one(self, x: np.ndarray) -> float:
        kernel = _kernels.scorer(self.clusterer_, self.synapse_)
        if kernel is not None:
            return float(kernel(self.clusterer_, self.synapse_, x[None, :])[0])
        return float(self.synapse_.efficacy_[self.clusterer_.match(x).winner])

    def winners(self, X) -> np.ndarray:
        """Stable ids of the winning units of ``X``, without learning."""
        self._check_fitted()
        from ._validation import check_batch

        rows, _ = self.clusterer_.winners(check_batch(X, self, self.n_features_in_))
        return self.clusterer_.unit_ids_[rows]

    def _first_novelty(self) -> float:
        # A first perception wins a unit whose synapse has not habituated: y0.
        return float(self._component(self.synapse, "synapse").initialize(1).efficacy_[0])

    @property
    def resting_novelty(self) -> float:
        """The novelty of a fully familiar input (the output neuron's resting activity)."""
        synapse = self.synapse_ if hasattr(self, "synapse_") else self._component(self.synapse, "synapse")
        return synapse.resting_efficacy

    def _check_state(self) -> None:
        from ._component import StateError

        super()._check_state()
        if self.synapse_.n_units_ != self.clusterer_.n_units_:
            raise StateError(
                f"The synapse bank has {self.synapse_.n_units_} synapses but the clusterer "
                f"has {self.clusterer_.n_units_} units."
            )
        if self.clusterer_.weights_.shape[1] != self.n_features_in_:
            raise StateError("The clusterer's weights do not match n_features_in_.")


def hsom(**params) -> HabituatingFilter:
    """The paper's Habituating SOM: a 10 x 10 Kohonen map with Stanley synapses.

    Every default is the value of Marsland, Nehmzow & Shapiro (2000): map
    10 x 10, learning rate 0.25, neighbourhood radius 1 (the 8 grid
    neighbours), both constant; tau = 3.33 (winner) and 14.3 (neighbours),
    alpha = 1.05, y0 = 1, explicit Euler steps, no forgetting.
    Parameters are routed as in :meth:`HabituatingFilter.from_params`.
    """
    return HabituatingFilter.from_params(clusterer="som", synapse="stanley", **params)
