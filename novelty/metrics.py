"""Scorers for scikit-learn's model selection, on the novelty scale.

``GridSearchCV(det, grid, scoring=novelty_roc_auc, cv=...)`` ranks the
settings by the ROC AUC of the detector's novelty (higher = more novel)
against labels ``y`` with **1 = novel, 0 = normal**, and picks the highest.
Each scorer follows scikit-learn's scorer protocol, ``scorer(estimator, X,
y) -> float``, higher is better:

- :func:`novelty_roc_auc`: ``sklearn.metrics.roc_auc_score(y, novelty)``;
- :func:`novelty_average_precision`:
  ``sklearn.metrics.average_precision_score(y, novelty)``, the precision of
  the novel scans averaged over recall.

The novelty is ``estimator.novelty(X)`` for a detector of this package and
``-estimator.score_samples(X)`` for anything else with scikit-learn's sign
(a ``Pipeline`` ending in a detector, ``IsolationForest``, ...): the same
values, as ``score_samples`` is ``-novelty``.

The traps these scorers avoid:

- ``scoring="roc_auc"`` (and ``"average_precision"``) score with
  ``decision_function``, which is higher for *normal* scans. With labels
  1 = novel the search then gets ``1 - AUC`` and picks the worst setting.
- ``make_scorer(roc_auc_score)`` scores ``predict``'s -1/+1 (the same
  inversion, on two values); ``make_scorer(roc_auc_score,
  response_method="decision_function")`` is ``scoring="roc_auc"``. Adding
  ``greater_is_better=False`` negates ``1 - AUC``: the search then ranks the
  settings right but reports ``AUC - 1``, a negative score that reads as
  the opposite of what it is.
- Detectors have no ``score`` method, as scikit-learn's own outlier
  detectors (``IsolationForest``, ``OneClassSVM``): ``fit`` never sees a
  novel scan, so there is nothing to score without labels, and
  scikit-learn's estimator checks call ``score(X, y)`` with arbitrary
  targets. ``GridSearchCV`` without ``scoring`` therefore stops with
  scikit-learn's "should have a 'score' method": pass one of these scorers.

Labels are 0/1 (or ``False``/``True``): 1 = novel. scikit-learn's outlier
labels -1/+1 are refused rather than translated: in them -1 is the outlier
(``predict``'s convention) while in scikit-learn's binary metrics +1 is the
positive class, so the same array means opposite things to two readers.
Convert with ``y01 = (y == -1).astype(int)`` when -1 marks the novel scans.
Both classes must be present: an AUC of one class is undefined.

Validation with a detector is train-on-normal, test-on-labelled: give
``cv`` the split, e.g. ``cv=[(train_idx, test_idx)]`` with normal scans
only in ``train_idx`` (a K-fold split would let the detector learn the
novel scans it is then asked to flag).

>>> import numpy as np
>>> from sklearn.metrics import get_scorer
>>> import novelty
>>> rng = np.random.default_rng(0)
>>> X = np.vstack([rng.normal(0.3, 0.05, (120, 4)), rng.normal(0.7, 0.05, (10, 4))])
>>> y = np.r_[np.zeros(120), np.ones(10)].astype(int)    # 1 = novel
>>> det = novelty.make("hsom").fit(X[:100])                # learn normal scans only
>>> novelty_roc_auc(det, X[100:], y[100:])
1.0
>>> float(get_scorer("roc_auc")(det, X[100:], y[100:]))   # scikit-learn's sign: 1 - AUC
0.0

Shares its name with ``novelty/bench/exploration/metrics.py``, ``novelty/bench/holdout/metrics.py``:
each benchmark protocol's package holds its own metrics, plots and summary; novelty/metrics.py is
the users' ROC AUC of novelty scores.
"""

from __future__ import annotations

import numpy as np
from sklearn.metrics import average_precision_score, roc_auc_score

__all__ = ["novelty_roc_auc", "novelty_average_precision", "novelty_of", "check_novelty_labels"]


def novelty_of(estimator, X) -> np.ndarray:
    """The estimator's novelty of ``X`` (higher = more novel).

    ``estimator.novelty(X)`` where it exists, else ``-estimator.score_samples(X)``
    (scikit-learn's outlier detectors and pipelines: higher = more normal).
    """
    if hasattr(estimator, "novelty"):
        return np.asarray(estimator.novelty(X), dtype=np.float64)
    if hasattr(estimator, "score_samples"):
        return -np.asarray(estimator.score_samples(X), dtype=np.float64)
    raise TypeError(
        f"{type(estimator).__name__} has neither 'novelty' nor 'score_samples'; a novelty scorer "
        "needs a detector (higher novelty = more novel) or a scikit-learn outlier detector."
    )


def check_novelty_labels(y) -> np.ndarray:
    """``y`` as an int array of 0 (normal) and 1 (novel), both present; else a ``ValueError``."""
    if y is None:
        raise ValueError("A novelty scorer needs labels y (1 = novel, 0 = normal); got y=None. "
                         "Pass y to the search's fit: search.fit(X, y).")
    labels = np.asarray(y).ravel()
    values = set(np.unique(labels).tolist())
    if not values <= {0, 1}:
        hint = (" These look like scikit-learn's outlier labels (-1 outlier, +1 inlier); if -1 marks the "
                "novel scans, pass (y == -1).astype(int)." if values <= {-1, 1} else "")
        raise ValueError(f"Novelty labels must be 0 (normal) or 1 (novel); got {sorted(values)!r}.{hint}")
    if len(values) < 2:
        which = "novel (1)" if values == {1} else "normal (0)"
        raise ValueError(f"Novelty labels need both normal (0) and novel (1) scans; this split has only "
                         f"{which} scans ({labels.size} of them), so the score is undefined. Use a split "
                         "whose test part holds both.")
    return labels.astype(np.int64)


def novelty_roc_auc(estimator, X, y) -> float:
    """ROC AUC of the estimator's novelty against ``y`` (1 = novel, 0 = normal).

    ``roc_auc_score(y, novelty)``: the probability that a novel scan is more
    novel than a normal one (ties count one half); 1 is perfect, 0.5 chance.
    A scikit-learn scorer: ``GridSearchCV(..., scoring=novelty_roc_auc)``.
    """
    labels = check_novelty_labels(y)
    return float(roc_auc_score(labels, novelty_of(estimator, X)))


def novelty_average_precision(estimator, X, y) -> float:
    """Average precision of the estimator's novelty against ``y`` (1 = novel, 0 = normal).

    ``average_precision_score(y, novelty)``: the precision at each novel
    scan's rank, averaged over the novel scans; chance is their fraction.
    A scikit-learn scorer: ``GridSearchCV(..., scoring=novelty_average_precision)``.
    """
    labels = check_novelty_labels(y)
    return float(average_precision_score(labels, novelty_of(estimator, X)))
