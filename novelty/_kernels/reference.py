"""The reference engine: the filter's loop in numpy, readable, the specification.

Marsland, Nehmzow & Shapiro (2000), section 2: each input is presented to a
clustering network; every unit connects to an output neuron through a
habituating synapse; the efficacy of the winner's synapse is the novelty of
the input. For each scan, in order (:func:`learn_stream`):

1. the clusterer finds the winner (and the units that learn with it);
2. the novelty is the winner's efficacy *before* this scan is learned;
3. the winner's and neighbours' synapses habituate (stimulus S) and the
   clusterer adapts, possibly adding or removing units, which the synapse
   bank follows.

Without learning the novelty is a pure function of the state: each scan's
nearest unit and its efficacy (:meth:`ReferenceEngine.score`). The compiled
engine (:mod:`novelty._kernels.engine`) implements the same methods and must
give the same numbers, bit for bit.
"""

from __future__ import annotations

import numpy as np

from ..distances import squared_distances
from .._validation.scans import CLEARED
from .._component import engine_writes
from .interface import ONE, Engine

__all__ = ["ReferenceEngine", "learn_stream"]


def learn_stream(clusterer, synapse, X: np.ndarray, dt: np.ndarray, stimulus: float = 1.0,
                 distances: np.ndarray | None = None) -> np.ndarray:
    """Present the rows of ``X`` in order, learning; return each row's efficacy novelty.

    This is the filter's learning loop as the paper describes it: the readable
    version any faster one must reproduce. The novelty of a row is its winner's
    efficacy before the row is learned; a row the network gives a unit of its
    own (``Growth.new_winner``) has that new unit's (fresh) efficacy, and the
    new unit's synapse then fires for it. ``distances``, if given, receives
    each row's squared distance to its winner.
    """
    novelty = np.empty(X.shape[0])
    for i in range(X.shape[0]):
        x = X[i]
        match = clusterer.match(x)
        novelty[i] = synapse.efficacy_[match.winner]
        if distances is not None:
            distances[i] = match.distance
        # Habituate on the rows of this match before the network may renumber them.
        synapse.step(match.winner, match.neighbours, stimulus, dt[i])
        growth = clusterer.adapt(x, match)
        if growth.removed.size:
            synapse.shrink(growth.removed)
        if growth.added:
            synapse.grow(growth.added)
            if growth.new_winner:
                novelty[i] = synapse.efficacy_[-1]
                synapse.fire(synapse.n_units_ - 1, stimulus, dt[i])
    return novelty


class ReferenceEngine(Engine):
    """The engine interface (:mod:`.interface`) in numpy, on the parts' own arrays.

    ``why``: why the filter learns by it (``"reference (NOVELTY_NO_KERNELS)"``, ...);
    ``pending``: the kernels compiling meanwhile (:attr:`~.interface.Engine.pending`).
    """

    def __init__(self, clusterer, synapse, why: str = "reference", pending: tuple = ()):
        super().__init__(clusterer, synapse)
        self.why, self.pending = why, pending
        self.adopt()

    def adopt(self) -> None:
        """Make the parts' arrays writable where they are not (a read-only array set on a part
        is copied: the loop writes into them in place, as the compiled engine into its own)."""
        with engine_writes(self.parts):
            for part in self.parts:
                for name, value in list(vars(part).items()):
                    if type(value) is np.ndarray and name.endswith("_") and not value.flags.writeable:
                        setattr(part, name, value.copy())
        self.seen()

    # ------------------------------------------------------------- learning
    def learn(self, X, dt, stimulus, distances=None):
        self.check_scans(X)
        self.check_values()
        with engine_writes(self.parts):
            novelty = learn_stream(self.clusterer, self.synapse, X, dt, stimulus, distances)
        self.seen()  # its own changes
        return novelty

    def learn_one(self, x, stimulus) -> bool:
        if not self._takes(x):
            return False
        self.check_values()  # written in place since the last call: as every call checks them
        with engine_writes(self.parts):
            self.novelty1[0] = learn_stream(self.clusterer, self.synapse, x[None, :], ONE, stimulus,
                                            self.distance1)[0]
        self.seen()
        return True

    def _takes(self, x) -> bool:
        """The single-scan calls' check (as the compiled ones'): as many features as the units,
        a sum of squares within the norm bound with a margin; NaN, infinity and too large
        values all fail it (the general path then says which)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return x.shape[0] == self.width and np.dot(x, x) <= CLEARED

    def learn_calibrating(self, X, dt, stimulus, calibration, scale, distances=None):
        """Learn the rows of ``X`` while ``calibration`` (a
        :class:`~novelty.match_scale.ScaleCalibration`, not full) takes them, from the first.

        Returns ``(efficacy, scales, scale)``: the efficacy novelty of each row learned
        (``distances``, if given, receives its squared distance to its winner); for each row
        the calibration took, the scale in force when it was learned (None before one is
        known: the owner scores each calibrating row with the scale of the rows before it);
        and the scale after them. A clusterer that learns by the scale
        (``Clusterer.uses_match_scale``: GWR's ``"auto"`` radius) learns one row at a time,
        given each new scale (:meth:`calibrate`), up to the row that fills the calibration or
        after which this engine no longer :meth:`holds` the parts (a scale it could not take
        in place, a kernel ready since): the owner learns the rest with the engine then
        chosen. Any other clusterer learns every row in one call, since its learning does
        not read the scale.
        """
        at_once = not self.clusterer.uses_match_scale
        n = X.shape[0]
        efficacy = self.learn(X, dt, stimulus, distances) if at_once else np.empty(n)
        scales = []
        i = 0
        while i < n and not calibration.full:
            scales.append(scale)
            if not at_once:
                efficacy[i] = self.learn(X[i:i + 1], dt[i:i + 1], stimulus,
                                         None if distances is None else distances[i:i + 1])[0]
            if calibration.add(X[i]):
                scale = calibration.scale
                if not at_once:
                    self.calibrate(scale)
            i += 1
            if not (at_once or self.holds()):
                break
        return (efficacy if at_once else efficacy[:i]), scales, scale

    # -------------------------------------------------------------- scoring
    def nearest(self, X):
        """The winners as ``match`` finds them (``Clusterer.winners``) and their squared
        distances as ``match`` computes them (``winners`` may expand the square)."""
        self.check_scans(X)
        self.check_values()
        rows, _ = self.clusterer.winners(X)
        return rows, squared_distances(X, self.clusterer.weights_[rows])

    def score(self, X):
        rows, distances = self.nearest(X)
        return rows, distances, self.synapse.efficacy_[rows]

    def score_one(self, x) -> bool:
        if not self._takes(x):
            return False
        rows, distances, efficacy = self.score(x[None, :])
        self.scored1[:] = efficacy[0], distances[0], rows[0]
        return True
