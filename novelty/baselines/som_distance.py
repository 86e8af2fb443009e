"""Distance to the best-matching unit of a self-organising map (Ypma & Duin's family).

A map (by default the project's :class:`~novelty.clusterers.som.SOM`) is
trained on familiar inputs; its units then stand for the regions of input
space that are familiar. The raw novelty of ``x`` is its Euclidean distance
to the best-matching unit,

    r(x) = min_j ||x - w_j||                                              (1)

the "goodness of fit" of an input to the map of Ypma & Duin (1997), used
with a threshold for novelty detection by them and by Taylor & MacIntyre
(1998). It needs no habituation: a familiar region is one the map has
units in, however often it was seen. Any registered clusterer can stand in
for the SOM (``clusterer="gng"``, ``"gwr"``).

The map learns online (one input at a time, the novelty of each taken before
it is learned), so ``partial_fit`` and ``learn_one`` continue training. The
raw distance is put on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration`. Model files hold the map as a nested
component: saving is supported.

References
----------
Ypma, A. & Duin, R. P. W. (1997). Novelty detection using self-organizing
maps. In Progress in Connectionist-Based Information Systems, 1322-1325.
Springer.

Taylor, O. & MacIntyre, J. (1998). Adaptive local fusion systems for novelty
detection and diagnostics in condition monitoring. SPIE Proc. 3376.

Kohonen, T. (1993). Self-Organization and Associative Memory, 3rd ed. Springer.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import StateError
from .._validation import Instance, Interval
from ..registry import build
from ..clusterers.base import Clusterer
from ._calibration import CalibratedDetector

__all__ = ["SOMDistance"]


class SOMDistance(CalibratedDetector):
    """Novelty as the distance to the best-matching unit of a self-organising map.

    Parameters
    ----------
    clusterer : str, Clusterer or None, default=None
        The map. None is the paper's 10 x 10 SOM (learning rate 0.25, radius
        1, weights drawn uniformly in [0, 1], so inputs should be scaled to
        [0, 1] as the paper's were); a registry name or an instance (cloned).
        ``SOM(init="sample")`` initialises from the first batch instead, for
        inputs of any range (then streaming scan by scan and in batches
        start from different maps).
    n_epochs : int, default=1
        Passes over the data in :meth:`fit`.
    random_state : int or None, default=0
        Seed of the map's initialisation.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    clusterer_ : Clusterer
        The trained map.
    reference_ : ndarray
        Calibration of the comparable scale.

    References
    ----------
    Ypma & Duin (1997), equation (1); Kohonen (1993).

    Examples
    --------
    >>> import numpy as np
    >>> X = np.random.default_rng(0).random((300, 4))
    >>> det = SOMDistance(n_epochs=2).fit(X)
    >>> det.clusterer_.n_units_
    100
    >>> bool(det.raw_novelty([[3.0, 3.0, 3.0, 3.0]])[0] > det.raw_novelty(X).max())
    True
    """

    supports_online = True

    _parameter_rules = {
        "clusterer": Instance((str, Clusterer, type(None)), "a clusterer name, a Clusterer instance or None"),
        "n_epochs": Interval(numbers.Integral, 1, None),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, clusterer=None, n_epochs=1, random_state=0, threshold=0.95, contamination="auto"):
        self.clusterer = clusterer
        self.n_epochs = n_epochs
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    def _new_clusterer(self) -> Clusterer:
        return build("clusterer", "som" if self.clusterer is None else self.clusterer)

    def _start(self, X: np.ndarray) -> None:
        super()._start(X)
        self.clusterer_ = self._new_clusterer().initialize(X, self.random_state)

    def _learn_one_raw(self, x: np.ndarray) -> float:
        match = self.clusterer_.match(x)
        self.clusterer_.adapt(x, match)
        return float(np.sqrt(match.distance))

    def _raw(self, X: np.ndarray) -> np.ndarray:
        _, dist = self.clusterer_.winners(X)
        return np.sqrt(dist)

    def _check_state(self) -> None:
        super()._check_state()
        if not isinstance(getattr(self, "clusterer_", None), Clusterer):
            raise StateError("SOMDistance.clusterer_ must be a clusterer.")
        if self.clusterer_.weights_.shape[1] != self.n_features_in_:
            raise StateError("SOMDistance.clusterer_ does not match n_features_in_.")
