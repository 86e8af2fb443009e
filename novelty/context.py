"""Sequence context: any detector given the recent past, in streaming and batch alike (ours).

The paper scores each scan alone. A feature coming into view is a sequence
of scans none of which need be new alone; this stage wraps any registered
detector and gives it a context of the recent past in two composable ways:

- **delay embedding** (before the detector): the detector sees, instead of
  the scan ``x_t``, the vector of the last ``delay`` scans ``lag`` apart,

      z_t = (x_t, x_{t-lag}, ..., x_{t-(delay-1) lag})                   (1)

  or, with ``differences=True``, the scan and its changes,

      z_t = (x_t, x_t - x_{t-lag}, ..., x_t - x_{t-(delay-1) lag})      (1')

  the method of delays of Packard et al. (1980) and Takens (1981), which
  turns a sequence into points whose neighbourhoods are neighbourhoods of
  whole trajectories. Before ``(delay - 1) lag`` scans have been seen, the
  missing ones are the first scan (a robot that stood still);
- **leaky integration** (after the detector): the novelty reported is an
  exponentially weighted moving average of the detector's novelty ``n_t``,

      y_t = (1 - smoothing) y_{t-1} + smoothing n_t,   y_0 = n_0          (2)

  (Roberts 1959), so that a run of moderately novel scans adds up while a
  single odd scan is damped. ``smoothing=1`` reports ``n_t`` unchanged.

The defaults (``delay=1``, ``smoothing=1``) leave the detector as it is.
Every scan's novelty is taken before it is learned, as for any detector;
:meth:`~novelty.detector.NoveltyDetector.novelty` (pure scoring) reads the
rows of a batch as the scans that follow the ones learned, in order, and
changes nothing. Streaming one scan at a time and in batches give the same
novelty. The wrapped detector keeps its own speed: the embedding is one
vectorised numpy step a batch and (2) is one linear filter
(``scipy.signal.lfilter``), so a compiled detector stays compiled.

References
----------
Packard, N. H., Crutchfield, J. P., Farmer, J. D. & Shaw, R. S. (1980).
Geometry from a time series. Physical Review Letters, 45(9), 712-716.

Takens, F. (1981). Detecting strange attractors in turbulence. In Dynamical
Systems and Turbulence, Lecture Notes in Mathematics 898, 366-381. Springer.

Roberts, S. W. (1959). Control chart tests based on geometric moving
averages. Technometrics, 1(3), 239-250.
"""

from __future__ import annotations

import numbers

import numpy as np
from scipy.signal import lfilter

from ._component import StateError, check_array_state
from ._validation import Instance, Interval
from .detector import NoveltyDetector
from .registry import build

__all__ = ["SequenceContext", "delay_embed", "leaky_integrate", "MAX_DELAY", "MAX_SPAN", "MAX_HISTORY"]

#: the most scans in an embedding (1): the wrapped detector sees ``delay`` times the features
MAX_DELAY = 1024
#: the most scans of history an embedding keeps, ``(delay - 1) * lag``: about a day of scans at 10 Hz
MAX_SPAN = 2**20
#: the most values of history (scans of history x features: 2**27 float64, 1 GiB), checked
#: against the first batch's features before the history is made
MAX_HISTORY = 2**27


def delay_embed(X: np.ndarray, past: np.ndarray, delay: int, lag: int, differences: bool) -> np.ndarray:
    """Rows of (1) or (1') for the scans ``X`` that follow the scans ``past`` (oldest first).

    ``past`` holds at least ``(delay - 1) * lag`` scans (the first scan repeated
    where there were fewer).

    >>> X = np.array([[3.0], [4.0]]); past = np.array([[1.0], [2.0]])
    >>> delay_embed(X, past, 3, 1, False).tolist()
    [[3.0, 2.0, 1.0], [4.0, 3.0, 2.0]]
    >>> delay_embed(X, past, 2, 2, True).tolist()
    [[3.0, 2.0], [4.0, 2.0]]
    """
    if delay == 1:
        return X
    span = (delay - 1) * lag
    seq = np.concatenate([past[past.shape[0] - span:], X])
    n = X.shape[0]
    parts = [X]
    for j in range(1, delay):
        earlier = seq[span - j * lag:span - j * lag + n]
        parts.append(X - earlier if differences else earlier)
    return np.hstack(parts)


def leaky_integrate(novelty: np.ndarray, level: float | None, smoothing: float) -> np.ndarray:
    """(2) over ``novelty`` from the level ``level`` (None: start at the first value).

    >>> leaky_integrate(np.array([1.0, 0.0, 0.0]), None, 0.5).tolist()
    [1.0, 0.5, 0.25]
    >>> leaky_integrate(np.array([1.0]), 0.0, 0.25).tolist()
    [0.25]
    """
    if smoothing == 1 or novelty.size == 0:
        return novelty
    start = novelty[0] if level is None else level
    out, _ = lfilter([smoothing], [1.0, smoothing - 1.0], novelty, zi=[(1.0 - smoothing) * start])
    return out


class SequenceContext(NoveltyDetector):
    """A detector given the recent past: delay embedding before it, leaky integration after it.

    Parameters
    ----------
    detector : str or NoveltyDetector, default="gwr-explore-wang-hsu"
        The detector given context: a registry name or an instance (cloned).
    delay : int in [1, 1024], default=1
        Scans in the embedding (1): 1 is the scan alone.
    lag : int, default=1
        Scans between the embedded ones. The history they make,
        ``(delay - 1) * lag`` scans, is at most :data:`MAX_SPAN` scans and
        :data:`MAX_HISTORY` values (refused before anything is allocated).
    differences : bool, default=False
        Embed the changes (1') instead of the earlier scans (1).
    smoothing : float in (0, 1], default=1.0
        The weight of the newest novelty in (2); 1 is no integration.
    threshold : float, default=0.5
        Novelty above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    detector_ : NoveltyDetector
        The wrapped detector, fitted on the embedded scans.
    history_ : ndarray of shape ((delay - 1) * lag, n_features)
        The last scans learned, oldest first.
    level_ : float
        The last integrated novelty y_t of (2).
    n_features_in_ : int
        Number of features of a scan (before embedding).

    References
    ----------
    Packard et al. (1980), Takens (1981): the method of delays, (1);
    Roberts (1959): the exponentially weighted moving average, (2).

    Examples
    --------
    >>> import numpy as np
    >>> det = SequenceContext("nearest-memory", delay=2, smoothing=0.5)
    >>> out = det.stream(np.random.default_rng(0).random((50, 3)))
    >>> det.detector_.n_features_in_, det.history_.shape
    (6, (1, 3))
    """

    _parameter_rules = {
        "detector": Instance((str, NoveltyDetector), "a detector name or a NoveltyDetector instance"),
        "delay": Interval(numbers.Integral, 1, MAX_DELAY),
        "lag": Interval(numbers.Integral, 1, MAX_SPAN),
        "differences": Instance((bool, np.bool_), "a bool"),
        "smoothing": Interval(numbers.Real, 0, 1, closed="right"),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, detector="gwr-explore-wang-hsu", delay=1, lag=1, differences=False, smoothing=1.0,
                 threshold=0.5, contamination="auto"):
        self.detector = detector
        self.delay = delay
        self.lag = lag
        self.differences = differences
        self.smoothing = smoothing
        self.threshold = threshold
        self.contamination = contamination

    @property
    def supports_online(self) -> bool:
        """Whether the wrapped detector learns online."""
        inner = getattr(self, "detector_", None) or build("detector", self.detector)
        return bool(inner.supports_online)

    def _span(self) -> int:
        return (self.delay - 1) * self.lag

    def _validate_params(self) -> None:
        super()._validate_params()
        if self._span() > MAX_SPAN:  # each within its rule, the history they make is not
            raise ValueError(f"SequenceContext keeps (delay - 1) * lag scans of history, at most {MAX_SPAN}; "
                             f"delay={self.delay} and lag={self.lag} make {self._span()}. Use a shorter lag "
                             "or fewer scans in the embedding.")

    def _embed(self, X: np.ndarray) -> np.ndarray:
        return delay_embed(X, self.history_, self.delay, self.lag, bool(self.differences))

    # ------------------------------------------------------------------- hooks
    def _start(self, X: np.ndarray) -> None:
        if self._span() * X.shape[1] > MAX_HISTORY:  # before anything is allocated
            raise ValueError(f"SequenceContext would keep {self._span()} scans of {X.shape[1]} features of "
                             f"history, more than {MAX_HISTORY} values (1 GiB); use a shorter lag or fewer "
                             "scans in the embedding.")
        self.detector_ = build("detector", self.detector)
        self.history_ = np.repeat(X[:1], self._span(), axis=0)
        self.level_ = None
        self.detector_._validate_params()
        self.detector_._begin(delay_embed(X[:1], self.history_, self.delay, self.lag, bool(self.differences)))

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        raw = self.detector_._finite(self.detector_._learn(self._embed(X), dt))
        out = leaky_integrate(raw, self.level_, self.smoothing)
        span = self._span()
        if span:
            self.history_ = np.concatenate([self.history_, X])[-span:]
        self.level_ = float(out[-1])
        return out

    def _finish_fit(self, X: np.ndarray) -> None:
        # the wrapped detector's own end of a fit (a baseline calibrates on its training
        # scores), on the scans embedded as they were learned, from the first one
        start = np.repeat(X[:1], self._span(), axis=0)
        self.detector_._finish_fit(delay_embed(X, start, self.delay, self.lag, bool(self.differences)))

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        raw = self.detector_._novelty(self._embed(X))
        return leaky_integrate(raw, self.level_, self.smoothing)

    def _first_novelty(self) -> float:
        return build("detector", self.detector)._first_novelty()

    def _check_state(self) -> None:
        super()._check_state()
        if not isinstance(getattr(self, "detector_", None), NoveltyDetector):
            raise StateError("SequenceContext.detector_ must be a detector.")
        check_array_state(self, "history_", 2, shape=(self._span(), self.n_features_in_))
        if not hasattr(self, "level_"):
            raise StateError("SequenceContext state is missing 'level_' (None before anything is learned).")
        level = self.level_
        if level is not None and not (isinstance(level, numbers.Real) and np.isfinite(level)):
            raise StateError(f"SequenceContext.level_ must be None or a finite number; got {level!r}.")
        if self.detector_.n_features_in_ != self.n_features_in_ * self.delay:
            raise StateError("SequenceContext.detector_ does not see delay x n_features_in_ features.")
