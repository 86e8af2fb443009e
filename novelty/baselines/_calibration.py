"""The comparable novelty scale shared by every baseline detector.

Each baseline has a *raw* novelty score in its own units (a distance, a
negative log-likelihood, an outlier factor; higher = more novel). To put
every detector on one [0, 1] scale, so that thresholds, plots and the
benchmark treat them alike, a raw score ``r`` is compared with a *reference*:
the raw scores of familiar inputs, ``s_1 <= ... <= s_n``. With
``u_1 < ... < u_m`` the distinct reference values and
``F_k = #{i : s_i <= u_k} / (n + 1)``, the comparable novelty is

    c(r) = F_1 * exp((r - u_1) / lam)                 if r < u_1
    c(r) = linear interpolation of the points (u_k, F_k)   if u_1 <= r <= u_m
    c(r) = 1 - (1 - F_m) * exp(-(r - u_m) / lam)      if r > u_m

where ``lam`` is the standard deviation of the reference (1 when that is 0),
and ``c = 1`` while the reference is empty (nothing is familiar yet).

Reading: inside the reference's range, ``c(r)`` is the share of familiar
inputs that are less novel than ``r`` (the empirical distribution function,
with ``n + 1`` in the denominator as in conformal prediction: for an input
exchangeable with the familiar ones, P(c > t) is about 1 - t). So a
``threshold`` of 0.95 flags about 5 % of familiar inputs as novel, whatever
the detector. Beyond the reference the map keeps rising smoothly towards 1 (and
falling towards 0 below it) instead of saturating, so the ranking of very
novel inputs, and thus ROC curves, survive the calibration. ``c`` is
continuous and non-decreasing in ``r``; the raw score stays available as
``raw_novelty(X)``.

The reference is

- after a batch ``fit``: the raw scores of the training data under the fitted
  model (some detectors use a less biased version: leave-one-out densities for
  ``parzen``, the training outlier factors for ``lof``);
- while learning online (``stream``, ``partial_fit``, ``learn_one``): each
  scan's raw score, taken before the scan is learned, joins the reference, so
  a scan is judged against the model's own recent experience; the first scan
  of a stream is fully novel (1.0), as with a habituating synapse.

It holds at most 1000 scores (``_MAX_REFERENCE``): a larger training set is
summarised by 1000 evenly spaced quantiles, and online updates replace the
oldest entries first.

Habituation filters already report novelty in [0, 1] (resting value
``y0 - 1/alpha`` for Stanley's synapse) on their own scale, which is not a
calibrated one; :func:`comparable` applied to a filter's training-stream
novelty puts it on this scale too.

References
----------
Vovk, V., Gammerman, A. & Shafer, G. (2005). Algorithmic Learning in a Random
World. Springer (conformal p-values: the rank of a score among reference
scores, with n + 1 in the denominator).

Laxhammar, R. & Falkman, G. (2015). Inductive conformal anomaly detection for
sequential detection of anomalous sub-trajectories. Annals of Mathematics and
Artificial Intelligence, 74, 67-94 (conformal anomaly detection).
"""

from __future__ import annotations

from abc import abstractmethod

import numpy as np


from .._component import StateError, check_array_state, check_int_state
from .._validation import check_batch
from ..detector import NoveltyDetector

__all__ = ["CalibratedDetector", "comparable", "summarise_reference"]

_MAX_REFERENCE = 1000
# A stride coprime with _MAX_REFERENCE: quantiles stored in this order are
# thinned evenly when online updates overwrite the oldest slots first.
_STRIDE = 7919


class _Scale:
    """The knots of c(r) for one reference (cached; rebuilt when it changes)."""

    __slots__ = ("values", "levels", "lam", "empty")

    def __init__(self, reference: np.ndarray):
        self.empty = reference.size == 0
        if self.empty:
            return
        values, counts = np.unique(reference, return_counts=True)
        self.values = values
        self.levels = np.cumsum(counts) / (reference.size + 1.0)
        lam = float(np.std(reference))
        self.lam = lam if lam > 0 else 1.0

    def __call__(self, raw: np.ndarray) -> np.ndarray:
        raw = np.asarray(raw, dtype=np.float64)
        if self.empty:
            return np.ones_like(raw)
        u, f = self.values, self.levels
        out = self._interpolate(raw)
        low = raw < u[0]
        high = raw > u[-1]
        if low.any():
            out[low] = f[0] * np.exp((raw[low] - u[0]) / self.lam)
        if high.any():
            out[high] = 1.0 - (1.0 - f[-1]) * np.exp(-(raw[high] - u[-1]) / self.lam)
        return out

    def _interpolate(self, raw: np.ndarray) -> np.ndarray:
        # np.interp forms the slope (F_k+1 - F_k) / (u_k+1 - u_k), which overflows
        # when two knots differ by a subnormal amount; the fraction of the gap
        # covered, (r - u_k) / (u_k+1 - u_k), always lies in [0, 1].
        u, f = self.values, self.levels
        if u.size == 1:
            return np.full_like(raw, f[0])
        k = np.clip(np.searchsorted(u, raw, side="right") - 1, 0, u.size - 2)
        with np.errstate(invalid="ignore", over="ignore"):
            t = np.clip((raw - u[k]) / (u[k + 1] - u[k]), 0.0, 1.0)
        return f[k] + t * (f[k + 1] - f[k])


def comparable(raw, reference) -> np.ndarray:
    """Map raw novelty scores to the comparable [0, 1] scale of a reference.

    Parameters
    ----------
    raw : array-like of shape (n_samples,)
        Raw scores (higher = more novel).
    reference : array-like of shape (n_reference,)
        Raw scores of familiar inputs.

    Returns
    -------
    ndarray of shape (n_samples,)
        c(raw) as defined in the module docstring.

    Examples
    --------
    >>> c = comparable([0.0, 2.5, 100.0], reference=[1.0, 2.0, 3.0, 4.0])
    >>> [round(float(v), 3) for v in c]
    [0.082, 0.5, 1.0]
    """
    reference = np.asarray(reference, dtype=np.float64).ravel()
    return _Scale(reference)(np.atleast_1d(np.asarray(raw, dtype=np.float64)))


def summarise_reference(scores) -> np.ndarray:
    """The reference kept for ``scores``: all of them, or 1000 evenly spaced quantiles.

    The quantiles are stored in an interleaved order, so that overwriting the
    first slots (the oldest, in online learning) thins them evenly.
    """
    scores = np.asarray(scores, dtype=np.float64).ravel()
    if scores.size <= _MAX_REFERENCE:
        return scores.copy()
    levels = (np.arange(_MAX_REFERENCE) + 0.5) / _MAX_REFERENCE
    quantiles = np.quantile(scores, levels)
    return quantiles[(np.arange(_MAX_REFERENCE) * _STRIDE) % _MAX_REFERENCE]


class CalibratedDetector(NoveltyDetector):
    """Base of the baseline detectors: a raw score put on the comparable scale.

    A subclass implements

    - :meth:`_raw` (raw novelty of a batch, pure);
    - for batch learners (``supports_online = False``): :meth:`_fit_model`;
    - for online learners: :meth:`_start` and :meth:`_learn_one_raw` (raw
      novelty of one scan before learning it, then learn it);
    - optionally :meth:`_reference_raw` (the raw scores of the training data
      that calibrate the scale; default: :meth:`_raw`).

    :meth:`novelty` (and so ``predict``, ``score_samples`` and ``threshold``)
    is on the comparable scale; :meth:`raw_novelty` gives the raw score.

    Attributes
    ----------
    reference_ : ndarray of shape (n_reference,)
        Raw scores of familiar inputs (at most 1000), the calibration.
    reference_next_ : int
        Slot the next online score replaces once the reference is full.
    """

    supports_online = False
    #: whether a training scan's own raw score is biased by the scan itself (a density's own
    #: kernel, a memory's distance 0), so that :meth:`_reference_raw` scores it without it
    _scores_itself = False

    # ------------------------------------------------------------- to implement
    @abstractmethod
    def _raw(self, X: np.ndarray) -> np.ndarray:
        """Raw novelty of each row of ``X`` (higher = more novel); no state change."""

    def _fit_model(self, X: np.ndarray) -> None:
        """Learn the model from the whole of ``X`` (batch learners)."""
        raise NotImplementedError(f"{type(self).__name__} is a batch learner and must define _fit_model.")

    def _learn_one_raw(self, x: np.ndarray) -> float:
        """Raw novelty of ``x`` before learning it, then learn it (online learners)."""
        raise NotImplementedError(f"{type(self).__name__} learns online and must define _learn_one_raw.")

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        """Raw scores of the training data ``X`` that calibrate the scale."""
        return self._raw(X)

    # ------------------------------------------------------------------- hooks
    def _start(self, X: np.ndarray) -> None:
        self._set_reference(np.empty(0))

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        # dt is not used: no baseline has time dynamics.
        if not self.supports_online:
            self._fit_model(X)
            self._set_reference(self._reference_raw(X))
            return self._novelty(X)
        out = np.empty(X.shape[0])
        for i in range(X.shape[0]):
            raw = self._learn_one_raw(X[i])
            out[i] = self._scale(self._finite_raw(np.array([raw])))[0]
            self._push_reference(raw)
        return out

    def _finish_fit(self, X: np.ndarray) -> None:
        # A fit calibrates on the whole training data, also for online learners
        # (whose stream built a reference while learning); batch learners did in _learn.
        if self.supports_online:
            self._set_reference(self._reference_raw(X))

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        return self._scale(self._finite_raw(self._raw(X)))

    def _threshold_advice(self) -> str | None:
        # The scale's reference scores each training scan without itself; a contamination
        # quantile, as scikit-learn and PyOD define it, is of the training scans scored with it.
        contamination = getattr(self, "contamination", "auto")
        if not self._scores_itself or isinstance(contamination, str):
            return None
        return (f"threshold_ is the {1 - contamination:g} quantile of the novelty of the training scans scored "
                f"with themselves in the model, which they match as no new scan does: far more than "
                f"{contamination:g} of new scans of the same place can lie above it (the default threshold, "
                f"{self.threshold:g} on a scale calibrated without them, carries over).")

    def _finite_raw(self, raw: np.ndarray) -> np.ndarray:
        # The scale maps NaN to a finite value, so a damaged model would pass unnoticed.
        if np.isnan(raw).any():
            raise StateError(
                f"{type(self).__name__} computed a raw novelty that is not finite (NaN): its "
                "learned state is damaged. Refit it."
            )
        return raw

    def raw_novelty(self, X) -> np.ndarray:
        """The detector's own score (higher = more novel), before calibration."""
        self._check_fitted()
        return self._raw(check_batch(X, self, self.n_features_in_))

    # --------------------------------------------------------------- reference
    def _set_reference(self, scores) -> None:
        self.reference_ = summarise_reference(scores)
        self.reference_next_ = 0
        self._scale = _Scale(self.reference_)

    def _push_reference(self, raw: float) -> None:
        if self.reference_.size < _MAX_REFERENCE:
            self.reference_ = np.append(self.reference_, raw)
        else:
            self.reference_[self.reference_next_] = raw
            self.reference_next_ = (self.reference_next_ + 1) % _MAX_REFERENCE
        self._scale = _Scale(self.reference_)

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        self._scale = _Scale(self.reference_)

    def _novelty_bounds(self) -> tuple[float, float]:
        return 0.0, 1.0  # c(r) of the module notes

    def _check_state(self) -> None:
        super()._check_state()
        ref = check_array_state(self, "reference_", 1)
        nxt = check_int_state(self, "reference_next_")
        if ref.size > _MAX_REFERENCE or nxt >= _MAX_REFERENCE:
            raise StateError(
                f"{type(self).__name__}.reference_ holds at most {_MAX_REFERENCE} scores "
                f"and reference_next_ must be below that; got {ref.size} and {nxt}."
            )
