"""Comparisons of two detectors on one task: a paired bootstrap over test scans, a corrected t-test over splits.

On one data set there is no population of tasks to test across; what can be
said is how sure one is of a difference on this task.

- :func:`paired_bootstrap`: both detectors scored the same test scans; the
  scans are resampled with replacement, positives and negatives separately
  (stratified, so every resample has the task's class balance), and the
  difference of ROC AUC (or average precision) recomputed on each resample
  (Efron & Tibshirani 1993, percentile interval). The resampling is seeded.
  It speaks of these test scans, one split: the uncertainty of the test
  sample, not of the training.
- :func:`corrected_resampled_t`: for a task whose seeds draw different
  train/test splits, the per-seed differences ``d_j`` over ``J`` splits, with
  the variance corrected for the overlap of the training sets
  (Nadeau & Bengio 2003): ``t = mean(d) / sqrt((1/J + n_test/n_train) s^2)``
  on ``J - 1`` degrees of freedom, ``s^2`` the sample variance of ``d``.

References
----------
Efron, B. & Tibshirani, R. (1993). *An Introduction to the Bootstrap*.
Chapman & Hall, chapter 13 (percentile intervals).
Nadeau, C. & Bengio, Y. (2003). Inference for the generalization error.
*Machine Learning* 52, 239-281 (the corrected resampled t-test, eq. 17).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats as sps

__all__ = ["Bootstrap", "paired_bootstrap", "CorrectedT", "corrected_resampled_t", "rank_auc", "RESAMPLES"]

#: bootstrap resamples drawn by default
RESAMPLES = 2000


@dataclass(frozen=True)
class Bootstrap:
    """The difference ``metric(a) - metric(b)`` on the test scans and its bootstrap interval."""

    metric: str
    difference: float
    low: float
    high: float
    se: float
    resamples: int
    confidence: float

    @property
    def excludes_zero(self) -> bool:
        """Whether the interval lies on one side of zero."""
        return self.low > 0 or self.high < 0


def rank_auc(scores: np.ndarray, y: np.ndarray) -> np.ndarray:
    """ROC AUC of each row of ``scores`` (shape ``(m, n)``) against labels ``y`` (Mann-Whitney, ties 1/2).

    >>> float(rank_auc(np.array([[0.1, 0.4, 0.35, 0.8]]), np.array([0, 0, 1, 1]))[0])
    0.75
    """
    scores = np.atleast_2d(np.asarray(scores, dtype=np.float64))
    y = np.asarray(y).astype(bool)
    ranks = sps.rankdata(scores, axis=1)
    n_pos, n_neg = int(y.sum()), int((~y).sum())
    return (ranks[:, y].sum(axis=1) - n_pos * (n_pos + 1) / 2) / (n_pos * n_neg)


def _average_precision(scores: np.ndarray, y: np.ndarray) -> float:
    """``sum_k (R_k - R_{k-1}) P_k`` over the distinct scores, high to low (scikit-learn's definition)."""
    order = np.argsort(-scores, kind="mergesort")
    s, hit = scores[order], y[order]
    last = np.r_[np.flatnonzero(np.diff(s)), s.size - 1]  # the last scan of each tied group
    tp = np.cumsum(hit)[last]
    recall = tp / tp[-1]
    return float(np.sum(np.diff(np.r_[0.0, recall]) * tp / (last + 1)))


def _metric(name: str, scores: np.ndarray, y: np.ndarray) -> np.ndarray:
    if name == "roc_auc":
        return rank_auc(scores, y)
    if name == "average_precision":
        return np.array([_average_precision(row, y) for row in np.atleast_2d(scores)])
    raise ValueError(f"Unknown metric {name!r}; expected 'roc_auc' or 'average_precision'.")


def paired_bootstrap(a, b, y, metric: str = "roc_auc", resamples: int = RESAMPLES, seed: int = 0,
                     confidence: float = 0.95) -> Bootstrap:
    """The paired, stratified bootstrap of ``metric(a) - metric(b)`` over the test scans.

    Parameters
    ----------
    a, b : array-like of shape (n_scans,)
        The two detectors' novelty of the same test scans (higher = more novel).
    y : array-like of shape (n_scans,)
        1 for a novel scan, 0 for a normal one; both classes needed.
    metric : {"roc_auc", "average_precision"}, default="roc_auc"
    resamples : int, default=2000
    seed : int, default=0
        Seed of the resampling.
    confidence : float, default=0.95
        Level of the percentile interval.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> y = np.r_[np.zeros(200), np.ones(50)]
    >>> good, poor = y + rng.normal(0, 0.5, 250), y + rng.normal(0, 2.0, 250)
    >>> paired_bootstrap(good, poor, y).excludes_zero
    True
    """
    a, b, y = (np.asarray(v, dtype=np.float64).ravel() for v in (a, b, y))
    if not a.shape == b.shape == y.shape:
        raise ValueError(f"a, b and y must have one value a scan; got {a.size}, {b.size} and {y.size}.")
    y = y.astype(bool)
    if y.all() or not y.any():
        raise ValueError("The paired bootstrap needs both novel and normal test scans.")
    if not 0 < confidence < 1 or resamples < 1:
        raise ValueError(f"confidence must be in (0, 1) and resamples >= 1; got {confidence}, {resamples}.")
    rng = np.random.default_rng(seed)
    pos, neg = np.flatnonzero(y), np.flatnonzero(~y)
    index = np.concatenate([rng.choice(pos, (resamples, pos.size)), rng.choice(neg, (resamples, neg.size))],
                           axis=1)
    labels = np.r_[np.ones(pos.size, bool), np.zeros(neg.size, bool)]
    diffs = _metric(metric, a[index], labels) - _metric(metric, b[index], labels)
    observed = float(_metric(metric, a[None], y)[0] - _metric(metric, b[None], y)[0])
    tail = (1 - confidence) / 2
    low, high = np.quantile(diffs, [tail, 1 - tail])
    return Bootstrap(metric, observed, float(low), float(high), float(diffs.std(ddof=1)), resamples,
                     confidence)


@dataclass(frozen=True)
class CorrectedT:
    """The corrected resampled t-test of the per-split differences."""

    n_splits: int
    mean: float
    t: float
    pvalue: float


def corrected_resampled_t(differences, n_train: int, n_test: int) -> CorrectedT:
    """Nadeau & Bengio's (2003) corrected resampled t-test of ``differences`` over random splits.

    ``t = mean(d) / sqrt((1/J + n_test/n_train) s^2)``, two-sided on ``J - 1``
    degrees of freedom. Needs at least two splits; a zero variance gives
    ``t = ±inf`` (p = 0) for a non-zero mean and p = 1 for a zero mean.

    >>> r = corrected_resampled_t([0.02, 0.03, 0.01, 0.04, 0.02], n_train=800, n_test=200)
    >>> round(r.t, 3), round(r.pvalue, 4)
    (3.138, 0.0349)
    """
    d = np.asarray(differences, dtype=np.float64)
    d = d[~np.isnan(d)]
    if d.size < 2:
        raise ValueError(f"The corrected resampled t-test needs at least two splits; got {d.size}.")
    if n_train < 1 or n_test < 1:
        raise ValueError(f"n_train and n_test must be positive; got {n_train} and {n_test}.")
    var = float(d.var(ddof=1)) * (1 / d.size + n_test / n_train)
    mean = float(d.mean())
    if var == 0:
        return CorrectedT(int(d.size), mean, math.copysign(math.inf, mean) if mean else 0.0,
                          0.0 if mean else 1.0)
    t = mean / math.sqrt(var)
    return CorrectedT(int(d.size), mean, t, float(2 * sps.t.sf(abs(t), d.size - 1)))
