"""Scores of one benchmark cell, computed from novelty values and labels.

Every function takes the novelty of the test scans (higher = more novel) and,
where it needs them, the per-scan labels ``y`` (1 novel, 0 normal). ROC AUC
and average precision are scikit-learn's (``sklearn.metrics``); the others
are plain numpy so that a reader can check them against the definitions
below. ``tests/bench/holdout/test_metrics.py`` checks them against hand-computed
values.

Undefined values are ``nan``: ROC AUC, average precision and the TPRs need
both classes in the test part; the detection delay needs a novel scan and an
alarm at or after it.

:data:`METRICS` is the table of the columns a cell reports and the benchmark
summary shows: one :class:`Metric` a column, computed from the cell's
:class:`Scored` test. Adding a metric is adding an entry.

Shares its name with ``novelty/bench/exploration/metrics.py``, ``novelty/metrics.py``: each
benchmark protocol's package holds its own metrics, plots and summary; novelty/metrics.py is the
users' ROC AUC of novelty scores.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from sklearn.metrics import average_precision_score, roc_auc_score

__all__ = [
    "Scored",
    "Metric",
    "METRICS",
    "compute",
    "roc_auc",
    "roc_auc_of",
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

    The Mann-Whitney statistic with ties counted one half, ``(sum of the
    ranks of the novel scans - P(P+1)/2) / (P N)`` with average ranks for
    ties, ``P`` novel and ``N`` normal scans, which is the trapezoidal area
    under the ROC curve: scikit-learn's ``roc_auc_score``. 1 is perfect, 0.5
    is chance; ``nan`` with a single class.

    >>> roc_auc([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1])
    0.75
    """
    scores, y = _scores_labels(scores, y)
    if y.all() or not y.any():
        return float("nan")
    return float(roc_auc_score(y, scores))


def roc_auc_of(scores, y, positives) -> float:
    """:func:`roc_auc` of the novel scans ``positives`` holds against every normal scan (other novel ones left out).

    Used for the objects in seen and in unseen places (a task's
    ``seen_place`` column): each class against the same familiar scans.

    >>> roc_auc_of([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1], [0, 0, 0, 1]), roc_auc_of([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1], [0, 0, 1, 0])
    (1.0, 0.5)
    """
    scores, y = _scores_labels(scores, y)
    positives = np.asarray(positives).ravel().astype(bool)
    if positives.shape != y.shape:
        raise ValueError(f"positives has {positives.size} values but y has {y.size}.")
    kept = ~y | positives
    return roc_auc(scores[kept], y[kept])


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
    at least the k-th highest distinct score is called novel, tied scores
    together (scikit-learn's ``average_precision_score``, no interpolation).
    Chance level is the fraction of novel scans; ``nan`` with a single class
    (scikit-learn would say 0 without novel scans, 1 without normal ones).

    >>> round(average_precision([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1]), 4)
    0.8333
    """
    scores, y = _scores_labels(scores, y)
    if y.all() or not y.any():
        return float("nan")
    return float(average_precision_score(y, scores))


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


# ------------------------------------------------------------------ the table
@dataclass(frozen=True)
class Scored:
    """What a cell's metrics are computed from.

    ``novelty`` and ``y``: the test scans' novelty and labels (bool);
    ``threshold``: the alarm threshold set on the training scans;
    ``alarm_scores``: the novelty of a clean pass over the familiar route
    (false alarms are counted there); ``resting``: the detector's resting
    novelty (0 without one).
    """

    novelty: np.ndarray
    y: np.ndarray
    threshold: float
    alarm_scores: np.ndarray
    resting: float = 0.0


@dataclass(frozen=True)
class Metric:
    """One column of a cell's results: its name, how it is computed, how the summary shows it.

    ``heading`` is the column's title in the ranking of ``novelty bench``
    (None: in the results only) and ``digits`` the decimals shown there.
    The summary shows a detector's mean over its successful cells.
    ``route``: the metric reads the test scans as a route, in order (NaN
    for a task without one); ``bounds``: the interval its values lie in.
    """

    column: str
    compute: Callable[[Scored], float]
    heading: str | None = None
    digits: int = 3
    route: bool = False
    bounds: tuple[float, float] | None = None


def _false_alarm_rate(s: Scored) -> float:
    return count_alarms(s.alarm_scores, s.threshold) / max(len(s.alarm_scores), 1)


#: the metrics of a cell, in the order of the results' columns and the ranking's
METRICS: tuple[Metric, ...] = (
    Metric("roc_auc", lambda s: roc_auc(s.novelty, s.y), "ROC AUC", bounds=(0.0, 1.0)),
    Metric("average_precision", lambda s: average_precision(s.novelty, s.y), "AP", bounds=(0.0, 1.0)),
    Metric("tpr_at_1pct_fpr", lambda s: tpr_at_fpr(s.novelty, s.y, 0.01), "TPR@1%", bounds=(0.0, 1.0)),
    Metric("tpr_at_5pct_fpr", lambda s: tpr_at_fpr(s.novelty, s.y, 0.05), "TPR@5%", bounds=(0.0, 1.0)),
    Metric("detection_delay", lambda s: detection_delay(s.novelty, s.y, s.threshold), "delay", 1, route=True),
    Metric("false_alarms", lambda s: count_alarms(s.alarm_scores, s.threshold), "false alarms", 1, route=True),
    Metric("false_alarm_rate", _false_alarm_rate, route=True, bounds=(0.0, 1.0)),
    Metric("integrated_novelty", lambda s: integrated_novelty(s.novelty, s.resting), "integrated", 2,
           route=True),
    Metric("max_novelty", lambda s: float(np.max(s.novelty)), "max"),
)


def compute(scored: Scored, table: tuple[Metric, ...] | None = None) -> dict:
    """Every metric of ``table`` (default :data:`METRICS`) on ``scored``: ``{column: value}``.

    >>> s = Scored(np.array([0.1, 0.4, 0.35, 0.8]), np.array([0, 0, 1, 1], bool), 0.5, np.array([0.2, 0.6]))
    >>> {k: v for k, v in compute(s).items() if k in ("roc_auc", "false_alarms", "max_novelty")}
    {'roc_auc': 0.75, 'false_alarms': 1, 'max_novelty': 0.8}
    """
    return {m.column: m.compute(scored) for m in (METRICS if table is None else table)}
