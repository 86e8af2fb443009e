"""How far an input is from what a network knows: the match scale and the mismatch novelties.

Our extension of Marsland, Nehmzow & Shapiro (2000), not part of the paper.
The paper's novelty is the efficacy ``y_s`` of the winning unit's synapse: it
says how often that unit has won, not how well it matches the input. The
*habituation x mismatch* novelty also reads the match distance
``d = ||x - w_s||``::

    n(x) = 1 - (1 - y_s) * exp(-d^2 / (2 sigma^2))

It is near its floor only when the input is both close to its winner and the
winner is habituated; it is 1 for an input far from every unit, whatever the
winner's efficacy; with ``sigma -> inf`` it is the paper's ``y_s``. It is the
probabilistic *or* of the efficacy and the mismatch
``m = 1 - exp(-d^2 / (2 sigma^2))``: ``y + m - y m``. The *product* novelty is
their *and*::

    n(x) = y_s * (1 - exp(-d^2 / (2 sigma^2)))

high only when the input is both far from its winner and won by an
unhabituated unit, so that a recurring input becomes familiar either as its
unit habituates or as the network learns to match it (0 for an exact match).

The match scale ``sigma`` is calibrated from the first ``m`` inputs
themselves, by one of two rules:

- ``"quantile"``: a quantile (``q``, 0.9 by default) of each calibration
  scan's distance to its nearest *distinct* other scan (leave-one-out nearest
  neighbours; exact repeats are ignored, so that a scan seen twice does not
  count as its own neighbour);
- ``"scott"``: Scott's normal-reference bandwidth (Scott 1992, chapter 6),
  per coordinate ``h_j = s_j m^(-1/(d+4))`` with ``s_j^2`` the sample
  variance (denominator ``m - 1``) of coordinate ``j`` over the ``m`` scans
  in ``d`` dimensions, combined into one isotropic scale by their root mean
  square::

      sigma = sqrt(mean_j s_j^2) * m^(-1/(d+4))

  With it, ``exp(-d^2 / (2 sigma^2))`` is a Gaussian kernel of the bandwidth
  a Parzen window of these scans would take (the ``parzen`` baseline's
  rule), centred on the winner instead of on every scan. It is 0.1-0.4 times
  the quantile scale on the tasks the project ships: a tighter match.

:class:`ScaleCalibration` collects the scans one at a time, so the scale after
``m`` scans is the same however they were batched.

References
----------
Scott, D. W. (1992). Multivariate Density Estimation: Theory, Practice, and
Visualization. Wiley, chapter 6 (the normal-reference rule for kernel
estimators in d dimensions, h_j = s_j n^(-1/(d+4))).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["mismatch_novelty", "product_novelty", "nearest_distinct", "scott_scale", "ScaleCalibration", "RULES"]

#: the calibration rules of the match scale
RULES = ("quantile", "scott")


def mismatch_novelty(efficacy: np.ndarray, distance: np.ndarray,
                     scale: float | np.ndarray | None) -> np.ndarray:
    """``1 - (1 - y) * exp(-d2 / (2 sigma^2))`` for efficacies ``y`` and squared distances ``d2``.

    ``scale``: one for all, or an array of one per input; None (no scale yet)
    gives the efficacies unchanged.

    >>> mismatch_novelty(np.array([0.2, 0.2, 1.0]), np.array([0.0, 2.0, 0.0]), 1.0).round(4).tolist()
    [0.2, 0.7057, 1.0]
    """
    if scale is None:
        return np.array(efficacy, dtype=np.float64)
    return 1.0 - (1.0 - efficacy) * np.exp(-distance / (2.0 * scale * scale))


def product_novelty(efficacy: np.ndarray, distance: np.ndarray,
                    scale: float | np.ndarray | None) -> np.ndarray:
    """``y * (1 - exp(-d2 / (2 sigma^2)))`` for efficacies ``y`` and squared distances ``d2``.

    ``scale``: one for all, or an array of one per input; None (no scale yet)
    gives the efficacies unchanged.

    >>> product_novelty(np.array([0.2, 0.2, 1.0]), np.array([0.0, 2.0, 2.0]), 1.0).round(4).tolist()
    [0.0, 0.1264, 0.6321]
    """
    if scale is None:
        return np.array(efficacy, dtype=np.float64)
    return efficacy * -np.expm1(-distance / (2.0 * scale * scale))


def nearest_distinct(X: np.ndarray) -> np.ndarray:
    """Each row's Euclidean distance to its nearest distinct other row (inf if none).

    >>> nearest_distinct(np.array([[0.0], [1.0], [1.0], [3.0]])).tolist()
    [1.0, 1.0, 1.0, 2.0]
    """
    m, n_features = X.shape
    out = np.empty(m)
    # a block of rows at a time against all rows (about 64k numbers in flight): each
    # distance is _distances' own arithmetic, a difference squared and summed over the
    # features, then its root
    block = max(1, (1 << 16) // max(1, m * n_features))
    for start in range(0, m, block):
        d = np.sqrt(((X[None, :, :] - X[start:start + block, None, :]) ** 2).sum(axis=2))
        d[~(d > 0.0)] = np.inf
        out[start:start + block] = d.min(axis=1)
    return out


def scott_scale(X: np.ndarray) -> float | None:
    """Scott's rule over the rows of ``X``: ``sqrt(mean_j s_j^2) * m^(-1/(d+4))`` (None if all equal).

    ``s_j^2`` is the sample variance (denominator ``m - 1``) of column ``j``;
    ``m`` rows, ``d`` columns. None for fewer than two rows or when no column
    varies (no two distinct rows).

    >>> scott_scale(np.array([[0.0, 0.0], [2.0, 0.0]]))   # s^2 = (2, 0): sqrt(1) * 2 ** (-1 / 6)
    0.8908987181403393
    """
    m, d = X.shape
    if m < 2:
        return None
    spread = float(np.sqrt(X.var(axis=0, ddof=1).mean()))
    if not spread > 0.0:
        return None
    return spread * m ** (-1.0 / (d + 4))


def linear_quantile(values: np.ndarray, q: float) -> float:
    """``np.quantile(values, q)`` (its default, linear interpolation) of a non-empty 1-D array
    of finite numbers, in numpy's arithmetic, without its general machinery.

    The ``q (m - 1)``-th value of the ``m`` values sorted, interpolated
    between its neighbours of ranks ``k = floor(q (m - 1))`` and ``k + 1``
    (Hyndman & Fan's definition 7), the way numpy interpolates: from the
    nearer neighbour's side, ``b - (b - a)(1 - g)`` when ``g >= 0.5``, else
    ``a + (b - a) g``. One calibration scan costs a quantile, which numpy
    takes tens of microseconds to set up; a test checks equality with
    ``np.quantile``, bit for bit.

    >>> linear_quantile(np.array([4.0, 1.0, 2.0, 3.0]), 0.5)
    2.5
    """
    m = values.shape[0]
    virtual = (m - 1) * q
    if virtual >= m - 1:
        return float(values.max())
    k = math.floor(virtual)
    ordered = np.partition(values, (k, k + 1))
    a, b, g = float(ordered[k]), float(ordered[k + 1]), virtual - k
    if g >= 0.5:
        return b - (b - a) * (1 - g)
    return a + (b - a) * g


def _distances(B: np.ndarray, x: np.ndarray) -> np.ndarray:
    # One formula for both orders of a pair: (b - x)^2 == (x - b)^2 exactly.
    return np.sqrt(((B - x) ** 2).sum(axis=1))


class ScaleCalibration:
    """The match scale of the first ``capacity`` scans, collected one at a time.

    Parameters
    ----------
    scans : ndarray of shape (m, n_features)
        The scans collected so far (``m <= capacity``).
    capacity : int
        How many scans calibrate the scale; later scans are not collected.
    quantile : float
        The quantile of the nearest-distinct distances that is the scale
        (rule ``"quantile"``).
    rule : {"quantile", "scott"}, default="quantile"
        How the scans make the scale (see the module).

    >>> cal = ScaleCalibration(np.empty((0, 1)), capacity=3, quantile=0.5)
    >>> cal.scale, [cal.add(np.array([v])) for v in (0.0, 0.0, 2.0, 5.0)], cal.full
    (None, [False, False, True, False], True)
    >>> cal.scale
    2.0
    """

    def __init__(self, scans: np.ndarray, capacity: int, quantile: float, rule: str = "quantile"):
        if rule not in RULES:
            raise ValueError(f"The match scale's rule must be one of {RULES}; got {rule!r}.")
        self.capacity = capacity
        self.quantile = quantile
        self.rule = rule
        # the scans and their nearest distances in arrays with room for more (filled in order,
        # a row never rewritten: a view of the first rows stays as it was)
        self._m = scans.shape[0]
        self._rows = np.array(scans, dtype=np.float64)
        self._near = nearest_distinct(self._rows) if rule == "quantile" else None
        self._scale = self._measure()

    @property
    def scans(self) -> np.ndarray:
        """The scans collected so far, in order."""
        return self._rows[:self._m]

    def __eq__(self, other) -> bool:
        return (isinstance(other, ScaleCalibration) and self.capacity == other.capacity
                and self.quantile == other.quantile and self.rule == other.rule
                and np.array_equal(self.scans, other.scans))

    @property
    def full(self) -> bool:
        return self._m >= self.capacity

    @property
    def scale(self) -> float | None:
        """The scale of the scans collected; None before two distinct scans."""
        return self._scale

    def _measure(self) -> float | None:
        # computed once per scan collected (a quantile costs tens of microseconds)
        if self.rule == "scott":
            return scott_scale(self.scans)
        nearest = self._near[:self._m]
        finite = nearest[np.isfinite(nearest)]
        return linear_quantile(finite, self.quantile) if finite.size else None

    def extend(self, X: np.ndarray) -> "ScaleCalibration":
        """Collect the rows of ``X`` in order (until full)."""
        for x in X:
            self.add(x)
        return self

    def add(self, x: np.ndarray) -> bool:
        """Collect ``x`` unless full; return whether the scale changed."""
        if self.full:
            return False
        before = self._scale
        m = self._m
        if m == self._rows.shape[0]:  # room for twice as many (at most the capacity)
            size = min(self.capacity, max(2 * m, 16))
            rows = np.empty((size, self._rows.shape[1]))
            rows[:m] = self._rows
            self._rows = rows
            if self._near is not None:
                near = np.empty(size)
                near[:m] = self._near
                self._near = near
        if self.rule == "quantile":
            d = _distances(self._rows[:m], x)
            d[~(d > 0.0)] = np.inf  # a repeat of x is not its neighbour
            nearest = self._near[:m]
            np.minimum(nearest, d, out=nearest)
            self._near[m] = d.min() if m else np.inf
        self._rows[m] = x
        self._m = m + 1
        self._scale = self._measure()
        return self._scale != before
