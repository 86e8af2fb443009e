"""Perfect memory: novelty as the distance to the nearest scan seen before.

The reference against which an exploring detector's memory is measured. It
keeps every scan it learns, verbatim, and the raw novelty of ``x`` is the
Euclidean distance to the nearest of them,

    r(x) = min_{j <= n - k} ||x - m_j||                                  (1)

where ``m_1, ..., m_n`` are the scans learned so far, oldest first, and the
``k = exclude_recent`` most recent ones are left out. Leaving them out asks
"was this seen before the last k scans?": consecutive scans of a moving
robot are close to each other whatever they perceive, so with ``k = 0`` a
new feature coming into view is partly matched by the scan just before.
While no scan is eligible (``n <= k``) the raw novelty is ``inf`` and the
novelty 1.0: nothing is familiar yet.

This is the 1-nearest-neighbour novelty score (the distance to the nearest
training point, the simplest of the distance-based detectors reviewed by
Pimentel et al., 2014, section 4.1; Markou & Singh, 2003), learned online:
each scan is scored before it joins the memory. It never forgets and never
generalises, so on an exploration it shows what remembering everything is
worth: a feature met again is as familiar as its nearest earlier scan.

Memory grows by one scan a scan learned (``n_scans x n_features`` float64s,
128 bytes a 16-sensor scan) and each scan costs ``O(n d)`` to score. With
``max_memory = M`` only the last ``M`` scans are kept (first in, first out):
the memory and the cost a scan are then bounded, and a scan not met within
the last ``M`` is forgotten.

The raw distance is put on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration` (``raw_novelty`` gives the distance).

References
----------
Pimentel, M. A. F., Clifton, D. A., Clifton, L. & Tarassenko, L. (2014). A
review of novelty detection. Signal Processing, 99, 215-249.

Markou, M. & Singh, S. (2003). Novelty detection: a review -- part 1:
statistical approaches. Signal Processing, 83(12), 2481-2497.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import StateError, check_array_state
from .._validation import Interval
from ._calibration import CalibratedDetector

__all__ = ["NearestMemory"]

# Rows of a batch compared at once: bounds the (rows x memory x features) difference array.
_CHUNK_ELEMENTS = 1 << 22


class NearestMemory(CalibratedDetector):
    """Novelty as the distance to the nearest scan learned before (a perfect memory).

    Parameters
    ----------
    exclude_recent : int, default=0
        ``k`` in (1): the most recent scans left out of the comparison.
    max_memory : int or None, default=None
        Keep only the last ``max_memory`` scans (first in, first out); None
        keeps every scan. Must exceed ``exclude_recent``.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    memory_ : ndarray of shape (n_kept, n_features)
        The scans kept, oldest first.
    reference_ : ndarray
        Calibration of the comparable scale.
    n_features_in_ : int
        Number of features.

    References
    ----------
    Pimentel et al. (2014), section 4.1: the nearest-neighbour distance, (1).

    Examples
    --------
    >>> det = NearestMemory()
    >>> det.stream([[0.0, 0.0], [3.0, 4.0]]).tolist()       # the first scan: nothing familiar yet
    [1.0, 1.0]
    >>> det.raw_novelty([[0.0, 1.0], [3.0, 4.0]]).tolist()  # distances to (0, 0) and (3, 4)
    [1.0, 0.0]
    """

    supports_online = True
    _scores_itself = True  # distance 0 to itself in memory: the scale takes each before it was learned

    _parameter_rules = {
        "exclude_recent": Interval(numbers.Integral, 0, None),
        "max_memory": Interval(numbers.Integral, 1, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, exclude_recent=0, max_memory=None, threshold=0.95, contamination="auto"):
        self.exclude_recent = exclude_recent
        self.max_memory = max_memory
        self.threshold = threshold
        self.contamination = contamination

    def _validate_params(self) -> None:
        super()._validate_params()
        if self.max_memory is not None and self.max_memory <= self.exclude_recent:
            raise ValueError(
                f"The 'max_memory' parameter of NearestMemory must exceed exclude_recent "
                f"({self.exclude_recent}), or no kept scan could ever be compared. Got {self.max_memory} instead."
            )

    # ------------------------------------------------------------------ memory
    def _start(self, X: np.ndarray) -> None:
        super()._start(X)
        self.memory_ = np.empty((0, X.shape[1]))
        self._rebuild_scratch()

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        # A buffer with room to grow, so that learning a scan does not copy the memory.
        self._store = self.memory_.copy()
        self._n = self.memory_.shape[0]

    def _remember(self, x: np.ndarray) -> None:
        n, cap = self._n, self._store.shape[0]
        if self.max_memory is not None and n >= self.max_memory:
            keep = self._store[n - self.max_memory + 1:n].copy()
            self._store[:keep.shape[0]] = keep
            n = keep.shape[0]
        elif n == cap:
            grown = np.empty((max(16, 2 * cap), self._store.shape[1]))
            grown[:n] = self._store[:n]
            self._store = grown
        self._store[n] = x
        self._n = n + 1
        self.memory_ = self._store[:self._n]

    def _eligible(self) -> np.ndarray:
        return self.memory_[:max(0, self.memory_.shape[0] - self.exclude_recent)]

    # ----------------------------------------------------------------- scoring
    def _raw(self, X: np.ndarray) -> np.ndarray:
        eligible = self._eligible()
        if eligible.shape[0] == 0:
            return np.full(X.shape[0], np.inf)
        out = np.empty(X.shape[0])
        rows = max(1, _CHUNK_ELEMENTS // (eligible.shape[0] * X.shape[1]))
        for start in range(0, X.shape[0], rows):
            diff = X[start:start + rows, None, :] - eligible[None, :, :]
            out[start:start + rows] = np.einsum("ijk,ijk->ij", diff, diff).min(axis=1)
        return np.sqrt(out)

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        # As the base's online loop, but a scan with nothing to compare with scores 1.0
        # and stays out of the calibration (its raw distance is infinite).
        out = np.empty(X.shape[0])
        for i in range(X.shape[0]):
            raw = self._raw(X[i:i + 1])
            out[i] = self._scale(raw)[0]
            if np.isfinite(raw[0]):
                self._push_reference(float(raw[0]))
            self._remember(X[i])
        return out

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        # After a fit every training scan is in memory (distance 0 to itself): calibrate on
        # the scores each had when it was learned, which the stream already collected.
        return self.reference_

    def _check_state(self) -> None:
        super()._check_state()
        memory = check_array_state(self, "memory_", 2)
        if memory.shape[1] != self.n_features_in_:
            raise StateError(f"NearestMemory.memory_ must have {self.n_features_in_} columns; "
                             f"got shape {memory.shape}.")
        if self.max_memory is not None and memory.shape[0] > self.max_memory:
            raise StateError(f"NearestMemory.memory_ holds {memory.shape[0]} scans, more than "
                             f"max_memory={self.max_memory}.")
