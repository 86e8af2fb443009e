"""k nearest neighbours: novelty as the distance to the k-th nearest training input.

With the n training inputs ``x_1, ..., x_n`` and ``d_1(x) <= ... <= d_k(x)``
the Euclidean distances from ``x`` to the k nearest of them, the raw novelty
is

    r(x) = d_k(x)                              method="largest"          (1)
    r(x) = (d_1(x) + ... + d_k(x)) / k         method="mean"             (2)

(1) is Ramaswamy, Rastogi & Shim's (2000) outlier score, the distance to the
k-th nearest neighbour; (2) is Angiulli & Pizzuti's (2002) weight, divided
by k. A new input has every training input as a candidate neighbour, so a
copy of a training input counts its twin at distance 0. The comparable scale
(:mod:`novelty.baselines._calibration`) is calibrated on the training inputs'
own scores, each computed without the input itself (its k nearest among the
other n - 1), which are not biased low as in-sample scores are.

The defaults, ``n_neighbors=5`` and ``method="largest"``, are those of PyOD's
``KNN``, which ADBench reports as KNN (Han et al. 2022): this detector scores
as that model does. Distances are computed as a k-d tree computes them
(scikit-learn's ``NearestNeighbors(algorithm="kd_tree")``; PyOD's ``KNN``
queried a tree too in the version ADBench used): the squared differences
summed feature by feature, so that a copy of a training input is at distance
exactly 0. A
brute-force search through the expanded form ``||x||^2 - 2 x.x_i + ||x_i||^2``
(scikit-learn's choice beyond 15 features) leaves such a copy up to about
1e-8 away, which breaks the many ties of a table bootstrapped with copies of
its rows (ADBench's small tables) at random and moves the ROC AUC.

Model files hold the training inputs (``samples_``), which define the model:
loading rebuilds the tree. The model grows with the training set (n x d
floats); scoring costs a tree query of k neighbours per input.

References
----------
Ramaswamy, S., Rastogi, R. & Shim, K. (2000). Efficient algorithms for
mining outliers from large data sets. Proc. SIGMOD 2000, 427-438.

Angiulli, F. & Pizzuti, C. (2002). Fast outlier detection in high
dimensional spaces. Proc. PKDD 2002, LNCS 2431, 15-27.

Han, S., Hu, X., Huang, H., Jiang, M. & Zhao, Y. (2022). ADBench: anomaly
detection benchmark. NeurIPS 2022 Datasets and Benchmarks track.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.neighbors import NearestNeighbors

from .._component import StateError, check_array_state
from .._validation import Interval, Options
from ._calibration import CalibratedDetector

__all__ = ["KNNDetector"]

#: how the k distances make the score: equations (1) and (2)
METHODS = ("largest", "mean")


class KNNDetector(CalibratedDetector):
    """Distance to the k-th nearest training input (or the mean of the k nearest).

    Parameters
    ----------
    n_neighbors : int, default=5
        k: the neighbours a score looks at; fitting needs more training
        inputs than k (each input's own score counts k others).
    method : {"largest", "mean"}, default="largest"
        The k-th distance, equation (1), or the mean of the k, equation (2).
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    samples_ : ndarray of shape (n_samples, n_features)
        The training inputs.
    reference_ : ndarray
        Calibration of the comparable scale (each training input's score
        without itself).

    References
    ----------
    Ramaswamy, Rastogi & Shim (2000), equation (1); Angiulli & Pizzuti
    (2002), equation (2).

    Examples
    --------
    >>> import numpy as np
    >>> X = np.array([[0.0], [1.0], [2.0], [4.0]])
    >>> det = KNNDetector(n_neighbors=2).fit(X)
    >>> det.raw_novelty([[0.0], [10.0]]).tolist()     # the 2nd nearest: 1 away, 8 away
    [1.0, 8.0]
    >>> KNNDetector(n_neighbors=2, method="mean").fit(X).raw_novelty([[10.0]]).tolist()
    [7.0]
    """

    _parameter_rules = {
        "n_neighbors": Interval(numbers.Integral, 1, None),
        "method": Options(METHODS),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, n_neighbors=5, method="largest", threshold=0.95, contamination="auto"):
        self.n_neighbors = n_neighbors
        self.method = method
        self.threshold = threshold
        self.contamination = contamination

    def _fit_model(self, X: np.ndarray) -> None:
        if X.shape[0] <= self.n_neighbors:
            raise ValueError(
                f"KNNDetector needs more training inputs than n_neighbors={self.n_neighbors} (each input's own "
                f"score counts {self.n_neighbors} others); got n_samples = {X.shape[0]}."
            )
        self.samples_ = X.copy()
        self._tree = self._index()

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        if hasattr(self, "samples_"):
            self._tree = self._index()

    def _index(self) -> NearestNeighbors:
        """The k-d tree of the training inputs (exact distances: see the module notes)."""
        return NearestNeighbors(n_neighbors=self.n_neighbors, algorithm="kd_tree").fit(self.samples_)

    def _score(self, distances: np.ndarray) -> np.ndarray:
        """Equation (1) or (2) of each row of k distances, nearest first."""
        return distances[:, -1] if self.method == "largest" else distances.mean(axis=1)

    def _raw(self, X: np.ndarray) -> np.ndarray:
        return self._score(self._tree.kneighbors(X, return_distance=True)[0])

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        # Without X, scikit-learn leaves each training input out of its own neighbours.
        return self._score(self._tree.kneighbors(return_distance=True)[0])

    def _check_state(self) -> None:
        super()._check_state()
        samples = check_array_state(self, "samples_", 2, shape=(None, self.n_features_in_))
        if samples.shape[0] <= self.n_neighbors:
            raise StateError(f"KNNDetector.samples_ holds {samples.shape[0]} inputs; n_neighbors="
                             f"{self.n_neighbors} needs more.")
