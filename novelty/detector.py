"""The detector API every novelty detector offers: streaming and scikit-learn.

One sign convention inside the project: **higher novelty = more novel**.
scikit-learn's outlier conventions are translated here, at the edge:

- ``score_samples(X) = -novelty(X)`` (higher = more normal);
- ``decision_function(X) = score_samples(X) - offset_`` with
  ``offset_ = -threshold_``, so it is negative exactly where
  ``novelty(X) > threshold_``;
- ``predict(X)`` is -1 (novel) where ``novelty(X) > threshold_``, else +1.

PyOD's conventions hold as they are: ``decision_scores_`` (higher = more
abnormal, as our novelty), ``threshold_`` and ``labels_`` (1 outlier, 0 normal).

A subclass implements four hooks on validated float64 arrays:
:meth:`~NoveltyDetector._start` (fresh state shaped by the first batch),
:meth:`~NoveltyDetector._learn` (learn a batch in order, returning the novelty
each scan had before it was learned), :meth:`~NoveltyDetector._novelty` (pure
scoring) and optionally :meth:`~NoveltyDetector._novelty_one`.

Guarantees the base class gives every detector:

- ``fit`` (and the first call that learns) builds the new model aside and
  replaces the old one only when it succeeds: a fit that fails leaves the
  previous model intact;
- no method returns a novelty that is not finite (a damaged state raises
  :class:`~novelty._component.StateError` instead), so ``predict`` never
  calls a NaN normal;
- calls on one detector from several threads run one at a time (a lock per
  detector), so threads never see or leave half-updated state.

The base class is one module although it is long (a third of its lines
document the conventions): its entry points make the same checks in the
same order, those that learn build a first model aside before adopting it,
and read side by side they show that each keeps the guarantees above.
"""

from __future__ import annotations

import _thread
import functools
import math
import numbers
import sys
import threading
from abc import abstractmethod
from typing import Any

import numpy as np
from sklearn.base import OutlierMixin
from sklearn.exceptions import NotFittedError
from sklearn.utils.metaestimators import available_if

from . import persistence
from .river_composition import register_with_river, unlearned_river_scan
from ._component import Component, StateError, _is_state_name, check_array_state, check_int_state
from ._validation import (Interval, Options, check_batch, check_feature_names, check_one, check_timestamps,
                          frame_names, last_timestamp, scan_names, validate_parameters)

__all__ = ["NoveltyDetector", "CONTAMINATION"]

#: The rule for every detector's ``contamination`` parameter (as scikit-learn's and PyOD's).
CONTAMINATION = (Options(("auto",)), Interval(numbers.Real, 0, 0.5, closed="right"))
_CONTAMINATION_RULES = {"contamination": CONTAMINATION}

class _Lock(_thread.RLock):
    """A detector's re-entrant lock, kept in its ``__dict__`` (``_lock``, made on first use).

    A deep copy or a pickle of the detector gets a fresh, unheld lock (``__reduce__``), and a
    fit never adopts the lock of the clone it learned on (:meth:`NoveltyDetector._adopt`),
    so each detector waits only for itself; a shallow copy shares the lock as it shares the
    learned arrays it guards. Read from the instance's own dictionary: faster than a table keyed
    on the detector, weakly.
    """

    __slots__ = ()

    def __reduce__(self):
        return _Lock, ()


#: the name of a detector's lock in its ``__dict__`` (private: never a parameter or state)
_LOCK = "_lock"
_locks_guard = threading.Lock()


def _lock_of(detector) -> _Lock:
    lock = vars(detector).get(_LOCK)
    if lock is None:
        with _locks_guard:  # two threads asking first get the same lock
            lock = vars(detector).setdefault(_LOCK, _Lock())
    return lock


def _one_at_a_time(method):
    """Run ``method`` holding the detector's lock (calls from other threads wait)."""

    @functools.wraps(method)
    def locked(self, *args, **kwargs):
        with _lock_of(self):
            return method(self, *args, **kwargs)

    return locked


class NoveltyDetector(OutlierMixin, Component):
    """Base class of novelty detectors (abstract).

    Subclasses have a ``threshold`` parameter (on the novelty scale), a
    ``contamination`` parameter, and may have ``n_epochs`` (passes over the
    data in :meth:`fit`).

    The threshold in force, ``threshold_``, is ``threshold`` while
    ``contamination="auto"`` (the default). A float ``contamination`` (the
    expected fraction of outliers in the training data, in (0, 0.5], as in
    scikit-learn and PyOD) wins over ``threshold``: ``threshold_`` is then the
    (1 - contamination) quantile (numpy's linear interpolation) of
    ``decision_scores_``, the novelty of the training scans under the fitted
    model, so :meth:`predict` calls about that fraction of them novel (fewer
    where scores tie at the quantile: a scan is novel only strictly above
    it). Only :meth:`fit` records training scans; a detector that learned
    online only has no ``decision_scores_`` and needs ``contamination="auto"``.
    ``threshold_`` and ``labels_`` follow the parameters in force: changing
    ``threshold`` or ``contamination`` with ``set_params`` takes effect at once.

    Scans are arrays, or, one at a time, dicts as in River: a dict scan is
    read by key. The first scan learned fixes the features, in the sorted
    order of its keys (``feature_names_in_``); every later dict scan must
    have exactly these keys, in any order. A DataFrame with string column
    names fixes them in its column order, and later batches must have the
    same names in the same order (scikit-learn's rule).

    Before anything is learned, :meth:`score_one` returns the novelty of a
    first perception, so that River's score-then-learn loop works from the
    first scan: for a habituating filter, the efficacy of an unhabituated
    synapse (``y0``, 1.0 by default); for a baseline, the top of its
    calibrated scale, 1.0 (nothing is familiar yet). The batch scoring
    methods (:meth:`novelty`, ``score_samples``, ...) raise
    ``NotFittedError`` until the detector has learned something.

    Attributes
    ----------
    n_features_in_ : int
        Number of features seen in the first batch.
    feature_names_in_ : ndarray of shape (n_features,)
        Names of the features, when the first batch was a DataFrame with
        string column names or the first scan a dict (strings as an object
        array, integer keys as an int64 array). Saved with the model.
    last_time_ : float, int or None
        Timestamp of the last scan learned, when timestamps were given (an
        int when they were integers: epoch nanoseconds are held exactly).
    decision_scores_ : ndarray of shape (n_samples,)
        Novelty of each training scan of the last :meth:`fit`, under the
        fitted model (PyOD's name; higher = more abnormal). Saved with the model.
    threshold_ : float
        The threshold in force (see above).
    labels_ : ndarray of int of shape (n_samples,)
        1 where ``decision_scores_ > threshold_`` (outlier), else 0 (PyOD's
        convention; :meth:`predict` says -1 and +1).
    """

    _kind = "detector"
    #: River's flag of a model that learns from labels: a detector does not (novelty.river_composition)
    _supervised = False
    #: whether ``partial_fit`` / ``learn_one`` keep learning after ``fit``
    supports_online = True
    #: modules of optional dependencies the detector needs to fit (e.g. ``("pyod",)``)
    requires: tuple[str, ...] = ()

    # ------------------------------------------------------------- to implement
    @abstractmethod
    def _start(self, X: np.ndarray) -> None:
        """Create fresh learned state for inputs like ``X`` (parameters are valid)."""

    @abstractmethod
    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        """Learn ``X`` in order; return the novelty of each row before learning it."""

    @abstractmethod
    def _novelty(self, X: np.ndarray) -> np.ndarray:
        """Novelty of each row of ``X``; must not change any state."""

    def _novelty_one(self, x: np.ndarray) -> float:
        return float(self._novelty(x[None, :])[0])

    def _finish_fit(self, X: np.ndarray) -> None:
        """Called by :meth:`fit` after the last pass, before ``decision_scores_`` are taken."""

    def _first_novelty(self) -> float:
        """Novelty of a first perception, before anything is learned (parameters are valid)."""
        return 1.0

    def _novelty_bounds(self) -> tuple[float, float] | None:
        """The interval every novelty of the fitted model lies in, when the detector knows it.

        A model file's ``decision_scores_`` (which set ``threshold_``) are
        checked against it: scores that learning cannot produce are refused.
        """
        return None

    # ------------------------------------------------------------------ helpers
    def _is_fitted(self) -> bool:
        return hasattr(self, "n_features_in_")

    def _check_fitted(self) -> None:
        if not self._is_fitted():
            raise NotFittedError(
                f"This {type(self).__name__} instance is not fitted yet. Call 'fit', "
                "'partial_fit' or 'learn_one' with some data first."
            )

    def _elapsed(self, n: int, timestamps: Any) -> np.ndarray:
        if timestamps is None:
            return np.ones(n)
        return check_timestamps(timestamps, n, getattr(self, "last_time_", None))

    def _advance_clock(self, n: int, timestamps: Any) -> None:
        if timestamps is not None:
            self.last_time_ = last_timestamp(timestamps)
        elif getattr(self, "last_time_", None) is not None:
            self.last_time_ += float(n)

    def _begin(self, X: np.ndarray, names: np.ndarray | None = None) -> None:
        self._start(X)
        self.n_features_in_ = X.shape[1]
        if names is not None:
            self.feature_names_in_ = names
        elif hasattr(self, "feature_names_in_"):
            del self.feature_names_in_
        self.last_time_ = None

    def _names(self) -> np.ndarray | None:
        return getattr(self, "feature_names_in_", None)

    def _unfitted_copy(self) -> "NoveltyDetector":
        """A detector with this one's parameters and no learned state (where a new model is built)."""
        new = object.__new__(type(self))
        vars(new).update({k: v for k, v in vars(self).items()
                          if not (k.startswith("_") or k.endswith("_"))})
        return new

    def _adopt(self, new: "NoveltyDetector") -> None:
        """Take the state of ``new``, dropping this detector's own learned state.

        Other private attributes stay (scikit-learn's meta-estimators set some
        around a ``fit``); every fit rebuilds its own scratch.
        """
        for name in [n for n in vars(self) if _is_state_name(n) and n not in vars(new)]:
            delattr(self, name)
        # all but the clone's lock: this detector keeps waiting for its own
        vars(self).update({k: v for k, v in vars(new).items() if k != _LOCK})

    #: one scan's novelty outside this closed interval goes to :meth:`_finite` (the default: every finite
    #: number passes; a detector whose :meth:`_finite` checks a narrower range says so here)
    _novelty_interval = (-sys.float_info.max, sys.float_info.max)

    def _finite(self, novelty: np.ndarray) -> np.ndarray:
        if not np.isfinite(novelty).all():
            raise StateError(
                f"{type(self).__name__} computed a novelty that is not finite: its learned "
                "state is damaged. Refit it."
            )
        return novelty

    def _check_state(self) -> None:
        # A model file could hold anything here; refuse it now rather than fail later.
        n = check_int_state(self, "n_features_in_", low=1)
        names = self._names()
        if names is not None and not (
            isinstance(names, np.ndarray) and names.shape == (n,) and len(set(names.tolist())) == n
            and (names.dtype.kind == "i" or (names.dtype == object and all(isinstance(v, str) for v in names)))
        ):
            raise StateError(
                f"{type(self).__name__}.feature_names_in_ must hold {n} distinct names, all strings "
                f"or all integers; got {names!r}."
            )
        if hasattr(self, "decision_scores_"):
            self._check_scores(check_array_state(self, "decision_scores_", 1))
        t = getattr(self, "last_time_", None)
        if t is not None and (isinstance(t, bool) or not isinstance(t, numbers.Real) or (
                abs(t) > 2**63 - 1 if isinstance(t, numbers.Integral) else not math.isfinite(t))):
            raise StateError(f"{type(self).__name__}.last_time_ must be None or a finite number (an int "
                             f"within int64); got {t!r}.")

    def _check_scores(self, scores: np.ndarray) -> None:
        bounds = self._novelty_bounds()
        if bounds is None or not scores.size:
            return
        low, high = bounds
        slack = 1e-9 * max(1.0, abs(low), abs(high))
        if scores.min() < low - slack or scores.max() > high + slack:
            raise StateError(
                f"{type(self).__name__}.decision_scores_ must lie in [{low:.6g}, {high:.6g}], where this "
                f"model's novelty lies; they hold values from {scores.min():.6g} to {scores.max():.6g} "
                "(a threshold_ taken from them could not be reached)."
            )

    def _validate_params(self) -> None:
        super()._validate_params()
        if hasattr(self, "contamination"):
            validate_parameters(self, _CONTAMINATION_RULES)

    def _check_online(self) -> None:
        if not self.supports_online:
            raise TypeError(
                f"{type(self).__name__} learns in batch only; call 'fit' with all the data."
            )

    # -------------------------------------------------------------- batch (sklearn)
    @_one_at_a_time
    def fit(self, X, y=None, timestamps=None):
        """Learn ``X`` from scratch (``n_epochs`` passes, in order).

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Scans, in the order they were perceived.
        y : ignored
        timestamps : array-like of shape (n_samples,), optional
            Time of each scan; the synapses then integrate over the elapsed
            time instead of one step per scan. A scan's stimulus is held over
            the time since the previous scan (a zero-order hold: the robot
            perceived the same thing all along), so a longer gap habituates
            the winning neighbourhood more and, with forgetting, lets the
            other units recover more. The first scan of a model counts as one
            step.
        """
        names = frame_names(X)
        X = check_batch(X, self)
        self._validate_params()
        # a refit starts a new life: no previous timestamp
        dt = np.ones(X.shape[0]) if timestamps is None else check_timestamps(timestamps, X.shape[0], None)
        new = self._unfitted_copy()
        new._begin(X, names)
        for _ in range(getattr(self, "n_epochs", 1)):
            new._finite(new._learn(X, dt))
        new._finish_fit(X)
        new._advance_clock(X.shape[0], timestamps)
        new.decision_scores_ = new._finite(new._novelty(X))
        self._adopt(new)
        return self

    # Batch-only detectors do not offer partial_fit at all, so that scikit-learn
    # (which treats its presence as "learns incrementally") sees them as they are.
    @available_if(lambda self: self.supports_online)
    def partial_fit(self, X, y=None, timestamps=None):
        """Learn ``X`` in order, continuing from the current state (one pass)."""
        self.stream(X, timestamps=timestamps, learn=True)
        return self

    @_one_at_a_time
    def stream(self, X, timestamps=None, learn=True) -> np.ndarray:
        """Novelty of each scan of ``X`` as the robot sees it, learning as it goes.

        The novelty of a scan is computed before the scan is learned. With
        ``learn=False`` nothing is learned and this equals :meth:`novelty`.
        """
        if not learn:
            return self.novelty(X)
        fitted = self._is_fitted()
        if fitted:
            self._check_online()
        names = frame_names(X)
        if fitted:
            check_feature_names(self, names, self._names())
        X = check_batch(X, self, self.n_features_in_ if fitted else None)
        dt = self._elapsed(X.shape[0], timestamps)
        # Parameters may have changed through set_params since the last call; the
        # single-scan path skips this check to stay cheap.
        self._validate_params()
        # the first batch builds the model aside, as fit does
        target = self if fitted else self._unfitted_copy()
        if not fitted:
            target._begin(X, names)
        out = target._finite(target._learn(X, dt))
        target._advance_clock(X.shape[0], timestamps)
        if not fitted:
            self._adopt(target)
        return out

    @_one_at_a_time
    def novelty(self, X) -> np.ndarray:
        """Novelty of each scan (higher = more novel), without learning."""
        self._check_fitted()
        check_feature_names(self, frame_names(X), self._names())
        X = check_batch(X, self, self.n_features_in_)
        return self._finite(self._novelty(X))

    def score_samples(self, X) -> np.ndarray:
        """scikit-learn convention: ``-novelty(X)`` (higher = more normal)."""
        return -self.novelty(X)

    @property
    def threshold_(self) -> float:
        """The threshold in force: ``threshold``, or the contamination quantile of ``decision_scores_``."""
        self._check_fitted()
        contamination = getattr(self, "contamination", "auto")
        if isinstance(contamination, str):  # "auto"
            return float(self.threshold)
        if not hasattr(self, "decision_scores_"):
            raise ValueError(
                f"contamination={contamination!r} sets the threshold from the novelty of the training "
                f"scans, which only 'fit' records; this {type(self).__name__} learned online only "
                f"(stream, partial_fit or learn_one). Fit it, or set contamination='auto' to use "
                f"threshold={self.threshold!r}."
            )
        return float(np.quantile(self.decision_scores_, 1.0 - contamination))

    @property
    def labels_(self) -> np.ndarray:
        """PyOD's labels of the training scans: 1 outlier (above ``threshold_``), 0 normal."""
        self._check_fitted()
        if not hasattr(self, "decision_scores_"):
            raise AttributeError(
                f"This {type(self).__name__} learned online only; 'labels_' describe the training "
                "scans of 'fit'."
            )
        return (self.decision_scores_ > self.threshold_).astype(np.int64)

    @property
    def offset_(self) -> float:
        """scikit-learn's offset: ``decision_function = score_samples - offset_``."""
        return -self.threshold_

    def decision_function(self, X) -> np.ndarray:
        """``threshold_ - novelty(X)``: negative for novel scans, positive for normal."""
        return self.score_samples(X) - self.offset_

    def predict(self, X) -> np.ndarray:
        """+1 for normal scans, -1 for novel ones (novelty above ``threshold_``)."""
        return np.where(self.novelty(X) > self.threshold_, -1, 1)

    # ----------------------------------------------------------- streaming (robot)
    @_one_at_a_time
    def score_one(self, x) -> float:
        """Novelty of one scan, without learning.

        Before anything is learned: the novelty of a first perception (see
        the class notes), once ``x`` is checked.
        """
        if not self._is_fitted():
            if not unlearned_river_scan(x):  # River's unlearned scalers give NaN; the answer needs no values
                check_one(x, self, None)
            self._validate_params()
            return self._first_novelty()
        out = self._novelty_one(check_one(x, self, self.n_features_in_, self._names()))
        low, high = self._novelty_interval
        if not low <= out <= high:   # NaN too
            self._finite(np.array([out]))
        return out

    def learn_one(self, x, t=None):
        """Learn one scan (``t``: its timestamp, optional)."""
        self.score_learn_one(x, t)
        return self

    @_one_at_a_time
    def score_learn_one(self, x, t=None) -> float:
        """Novelty of one scan before learning it, then learn it (the robot's loop)."""
        fitted = self._is_fitted()
        if fitted:
            self._check_online()
            x = check_one(x, self, self.n_features_in_, self._names())
        else:
            names = scan_names(x, self) if isinstance(x, dict) else None
            x = check_one(x, self, None, names)
        timestamps = None if t is None else (t,)
        dt = self._elapsed(1, timestamps)
        target = self if fitted else self._unfitted_copy()
        if not fitted:
            self._validate_params()
            target._begin(x[None, :], names)
        out = float(target._learn(x[None, :], dt)[0])
        low, high = target._novelty_interval
        if not low <= out <= high:   # NaN too
            target._finite(np.array([out]))
        target._advance_clock(1, timestamps)
        if not fitted:
            self._adopt(target)
        return out

    # ------------------------------------------------------------------ files
    def save(self, path) -> None:
        """Write the detector to ``path`` (npz arrays + JSON metadata; no pickle)."""
        with _lock_of(self):
            persistence.save(self, path)


register_with_river(NoveltyDetector)  # River's pipelines and evaluation take every detector (river_composition)
