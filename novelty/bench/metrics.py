"""Scores of one benchmark cell, computed from novelty values and labels.

Every function takes the novelty of the test scans (higher = more novel) and,
where it needs them, the per-scan labels ``y`` (1 novel, 0 normal). They are
plain numpy so that a reader can check them against the definitions below;
``tests/bench/test_metrics.py`` checks them against hand-computed values.

Undefined values are ``nan``: ROC AUC, average precision and the TPRs need
both classes in the test part; the detection delay needs a novel scan and an
alarm at or after it.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import rankdata

__all__ = [
    "roc_auc",
    "average_precision",
    "roc_points",
    "tpr_at_fpr",
    "training_threshold",
    "detection_delay",
    "count_alarms",
    "integrated_novelty",
]


def _scores_labels(scores, y) -> tuple[np.ndarray, np.ndarray]:
    scores = np.asarray(scores, dtype=np.float64).ravel()
    y = np.asarray(y).ravel().astype(bool)
    if scores.shape != y.shape:
        raise ValueError(f"scores has {scores.size} values but y has {y.size}.")
    return scores, y


def roc_auc(scores, y) -> float:
    """Area under the ROC curve: P(novel scan scores higher than a normal one).

    Computed as the Mann-Whitney statistic with ties counted one half:
    ``(sum of the ranks of the novel scans - P(P+1)/2) / (P N)`` with average
    ranks for ties, ``P`` novel and ``N`` normal scans. 1 is perfect, 0.5 is
    chance.

    >>> roc_auc([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1])
    0.75
    """
    scores, y = _scores_labels(scores, y)
    n_pos, n_neg = int(y.sum()), int((~y).sum())
    if n_pos == 0 or n_neg == 0:
        return float("nan")
    ranks = rankdata(scores)  # average ranks for ties
    return float((ranks[y].sum() - n_pos * (n_pos + 1) / 2) / (n_pos * n_neg))


def roc_points(scores, y) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """False- and true-positive rates at every distinct threshold.

    A scan is called novel when its novelty is ``>= t``; ``t`` runs over the
    distinct scores from high to low, preceded by ``+inf`` (nothing called
    novel), so the curve starts at (0, 0) and ends at (1, 1).

    Returns ``fpr, tpr, thresholds``.
    """
    scores, y = _scores_labels(scores, y)
    order = np.argsort(-scores, kind="mergesort")
    s, yy = scores[order], y[order]
    last_of_tie = np.r_[np.flatnonzero(np.diff(s)), s.size - 1]  # last index of each distinct score
    tp = np.cumsum(yy)[last_of_tie]
    fp = (last_of_tie + 1) - tp
    n_pos, n_neg = max(int(y.sum()), 1), max(int((~y).sum()), 1)
    fpr = np.r_[0.0, fp / n_neg]
    tpr = np.r_[0.0, tp / n_pos]
    return fpr, tpr, np.r_[np.inf, s[last_of_tie]]


def average_precision(scores, y) -> float:
    """Average precision: ``sum_k (R_k - R_{k-1}) P_k`` over the thresholds.

    ``P_k`` and ``R_k`` are the precision and recall when every scan scoring
    at least the k-th highest distinct score is called novel (scikit-learn's
    definition, no interpolation). Chance level is the fraction of novel scans.

    >>> round(average_precision([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1]), 4)
    0.8333
    """
    scores, y = _scores_labels(scores, y)
    n_pos = int(y.sum())
    if n_pos == 0 or n_pos == y.size:
        return float("nan")
    fpr, tpr, _ = roc_points(scores, y)
    tp = tpr[1:] * n_pos
    fp = fpr[1:] * (y.size - n_pos)
    precision = tp / (tp + fp)
    recall_gain = np.diff(tpr)
    return float(np.sum(recall_gain * precision))


def tpr_at_fpr(scores, y, max_fpr: float) -> float:
    """The best true-positive rate at a false-positive rate of at most ``max_fpr``.

    Taken over the operating points of :func:`roc_points` (no interpolation
    between them): the highest TPR among thresholds whose FPR is ``<= max_fpr``.

    >>> tpr_at_fpr([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1], 0.0)
    0.5
    """
    scores, y = _scores_labels(scores, y)
    if y.all() or not y.any():
        return float("nan")
    fpr, tpr, _ = roc_points(scores, y)
    return float(tpr[fpr <= max_fpr + 1e-12].max())


def training_threshold(train_novelty, rule="max") -> float:
    """The alarm threshold, set from the training scans only.

    ``train_novelty`` is the novelty of the training scans scored *after*
    training, without learning. ``rule="max"`` (the default of the harness)
    takes their maximum: an alarm is a scan more novel than anything on the
    familiar route. A float ``q`` in (0, 1] takes the ``q`` quantile instead.
    A scan raises an alarm when its novelty is strictly above the threshold.

    >>> training_threshold([0.05, 0.2, 0.1])
    0.2
    """
    values = np.asarray(train_novelty, dtype=np.float64).ravel()
    if values.size == 0:
        raise ValueError("No training novelty to set a threshold from.")
    if rule == "max":
        return float(values.max())
    q = float(rule)
    if not 0 < q <= 1:
        raise ValueError(f"A threshold quantile must be in (0, 1]; got {rule!r}.")
    return float(np.quantile(values, q))


def detection_delay(scores, y, threshold: float) -> float:
    """Scans from the first novel scan to the first alarm at or after it.

    An alarm is a scan with novelty ``> threshold``. 0 means the first novel
    scan itself raised an alarm. Alarms before the first novel scan are false
    alarms, not detections. ``nan`` when there is no novel scan or no alarm
    from it on (the novelty was missed).

    >>> detection_delay([0.9, 0.1, 0.2, 0.7, 0.8], [0, 0, 1, 1, 1], 0.5)
    1.0
    """
    scores, y = _scores_labels(scores, y)
    if not y.any():
        return float("nan")
    first_novel = int(np.argmax(y))
    alarms = np.flatnonzero(scores[first_novel:] > threshold)
    return float(alarms[0]) if alarms.size else float("nan")


def count_alarms(scores, threshold: float) -> int:
    """How many scans have novelty strictly above ``threshold``.

    >>> count_alarms([0.1, 0.5, 0.6], 0.5)
    1
    """
    return int(np.count_nonzero(np.asarray(scores, dtype=np.float64) > threshold))


def integrated_novelty(scores, resting: float = 0.0) -> float:
    """The paper's integrated output: ``sum_i (novelty_i - resting)``.

    Marsland, Nehmzow & Shapiro (2000), Table 1, subtract the output neuron's
    resting activity (0.0476 a step for the HSOM) from every step. For
    detectors without a resting level, ``resting`` is 0 and this is the plain
    sum. Not clipped at 0: a detector below its own resting level shows it.

    >>> round(integrated_novelty([1.0, 0.0476, 0.5476], resting=0.0476), 4)
    1.4524
    """
    scores = np.asarray(scores, dtype=np.float64)
    return float(np.sum(scores - resting))
