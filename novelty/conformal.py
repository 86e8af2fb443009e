"""Split-conformal thresholds and p-values: alarms at a stated false-alarm rate.

A detector scores ``n`` scans of a stretch the robot knows to be familiar
(its *calibration* scans) the way it scores in use: frozen, after learning
and never in-sample; or learning, each scan scored before it is learned.
With ``s_(1) <= ... <= s_(n)`` their novelty sorted and ``a`` the target
false-alarm rate,

    k = ceil((n + 1) (1 - a))
    threshold = s_(k)                              (infinite when k > n)
    p(x) = (1 + #{i : s_i >= s(x)}) / (n + 1)      (the conformal p-value)

and a scan raises an alarm when its novelty is strictly above the threshold,
which is exactly when ``p(x) <= a``. If the calibration scans and a later
familiar scan are exchangeable (drawn alike, in any order), the chance that
the later scan raises an alarm is at most ``a`` (and, for scores without
ties, more than ``a - 1 / (n + 1)``): the finite-sample guarantee of split
(inductive) conformal prediction. It holds for any detector and any score,
averaged over calibration sets; a robot's drive is not exchangeable where the
place or the light changes, so the rate met later can be higher than ``a``.

A threshold can promise a rate ``a`` only from ``n >= 1/a - 1`` scans (99 for
1 %, 19 for 5 %); with fewer, ``k > n`` and the threshold is infinite: no scan
raises an alarm, and :func:`conformal_threshold` warns
(:class:`CalibrationWarning`).

Rates are read as the decimal the user wrote (``0.01`` is 1/100 exactly), so
that ``k`` is not off by one where ``(n + 1)(1 - a)`` is a whole number.

References
----------
Vovk, V., Gammerman, A. & Shafer, G. (2005). Algorithmic Learning in a Random
World. Springer (conformal prediction; p-values as ranks with n + 1).

Laxhammar, R. & Falkman, G. (2015). Inductive conformal anomaly detection for
sequential detection of anomalous sub-trajectories. Annals of Mathematics and
Artificial Intelligence, 74, 67-94 (the false-alarm rate of a conformal anomaly
detector is at most its significance level).

Bates, S., Candès, E., Lei, L., Romano, Y. & Sesia, M. (2023). Testing for
outliers with conformal p-values. Annals of Statistics, 51(1), 149-178 (the
p-value above, its validity from a calibration set of inliers, eq. (3)).

Examples
--------
>>> scores = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
>>> conformal_threshold(scores, 0.2)    # k = ceil(11 * 0.8) = 9
0.9
>>> conformal_p_values([0.95, 0.05], scores).round(3).tolist()
[0.182, 1.0]
"""

from __future__ import annotations

import math
import numbers
import warnings
from fractions import Fraction

import numpy as np

from ._validation import Interval

__all__ = ["conformal_threshold", "conformal_p_values", "threshold_rank", "fewest_scans", "check_rate",
           "CalibrationWarning", "FALSE_ALARM_RATE"]

#: the rule for a target false-alarm rate
FALSE_ALARM_RATE = Interval(numbers.Real, 0, 1, closed="neither")


class CalibrationWarning(UserWarning):
    """Too few calibration scans to promise the rate asked for: no scan raises an alarm."""


def check_rate(false_alarm_rate, owner: str = "calibrate") -> float:
    """``false_alarm_rate`` as a float, or a ValueError in the project's one form."""
    if not FALSE_ALARM_RATE.accepts(false_alarm_rate):
        raise ValueError(f"The 'false_alarm_rate' argument of {owner} must be {FALSE_ALARM_RATE.describe()}. "
                         f"Got {false_alarm_rate!r} instead.")
    return float(false_alarm_rate)


def _exact(rate: float) -> Fraction:
    # the decimal the user wrote: 0.01 is 1/100, not the binary float just above it
    return Fraction(repr(float(rate)))


def threshold_rank(n: int, false_alarm_rate: float) -> int:
    """``k = ceil((n + 1)(1 - a))``: the threshold is the ``k``-th smallest of ``n`` scores (1-based).

    >>> threshold_rank(99, 0.01), threshold_rank(100, 0.05), threshold_rank(18, 0.05)
    (99, 96, 19)
    """
    return math.ceil((n + 1) * (1 - _exact(false_alarm_rate)))


def fewest_scans(false_alarm_rate: float) -> int:
    """The fewest calibration scans whose threshold is finite for this rate: ``ceil(1/a) - 1``.

    >>> fewest_scans(0.01), fewest_scans(0.05), fewest_scans(0.03)
    (99, 19, 33)
    """
    return math.ceil(1 / _exact(false_alarm_rate)) - 1


def conformal_threshold(scores, false_alarm_rate: float, *, warn: bool = True) -> float:
    """The split-conformal threshold of calibration ``scores`` for a false-alarm rate.

    Parameters
    ----------
    scores : array-like of shape (n,)
        Novelty of the calibration scans (higher = more novel), finite.
    false_alarm_rate : float in (0, 1)
        The target rate ``a``.
    warn : bool, default=True
        Warn when the scores are too few for the rate (a detector warns once, when it is calibrated).

    Returns
    -------
    float
        ``s_(k)`` with ``k = ceil((n + 1)(1 - a))``; ``inf`` when ``k > n``
        (too few scans for ``a``: warned with :class:`CalibrationWarning`).
    """
    rate = check_rate(false_alarm_rate, "conformal_threshold")
    s = _scores(scores)
    k = threshold_rank(s.size, rate)
    if k > s.size:
        if not warn:
            return math.inf
        warnings.warn(
            f"{s.size} calibration scans cannot promise a false-alarm rate of {rate:g}: the smallest they "
            f"can is 1/{s.size + 1} = {1 / (s.size + 1):.3g}. The threshold is infinite (no scan raises an "
            f"alarm); calibrate on at least {fewest_scans(rate)} scans.",
            CalibrationWarning, stacklevel=2)
        return math.inf
    return float(np.partition(s, k - 1)[k - 1])


def conformal_p_values(novelty, scores) -> np.ndarray:
    """The conformal p-value of each novelty against calibration ``scores``.

    ``p = (1 + #{i : s_i >= novelty}) / (n + 1)``: small for a scan more novel
    than most familiar ones; for a familiar scan exchangeable with the
    calibration scans, ``P(p <= a) <= a`` for every ``a``.

    Parameters
    ----------
    novelty : array-like of shape (m,)
        Scores to test.
    scores : array-like of shape (n,)
        Novelty of the calibration scans.

    Returns
    -------
    ndarray of shape (m,), values in [1/(n + 1), 1]
    """
    s = np.sort(_scores(scores))
    x = np.asarray(novelty, dtype=np.float64).ravel()
    if np.isnan(x).any():
        raise ValueError("conformal_p_values takes novelty scores as numbers; got NaN.")
    at_least = s.size - np.searchsorted(s, x, side="left")
    return (1.0 + at_least) / (s.size + 1.0)


def _scores(scores) -> np.ndarray:
    s = np.asarray(scores, dtype=np.float64).ravel()
    if s.size == 0:
        raise ValueError("Calibration needs the novelty of at least one familiar scan; got none.")
    if not np.isfinite(s).all():
        raise ValueError("Calibration scores must be finite numbers.")
    return s
