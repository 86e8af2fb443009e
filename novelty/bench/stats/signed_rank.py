"""The pairwise tests of detectors over tasks: Wilcoxon's signed-rank test, Holm's correction.

The unit is the task, as in :mod:`.across_tasks` (which names these too).

- :func:`wilcoxon`: the exact Wilcoxon signed-rank test of a pair, zero
  differences split between the signs (Demsar 2006, section 3.1.3);
  :func:`pairwise_wilcoxon` every pair with Holm's correction for the family
  (Holm 1979; Benavoli, Corani & Mangili 2016).
- :func:`wilcoxon_min_p`: the smallest p-value the test can give with so few
  tasks.

References
----------
Demsar, J. (2006). Statistical comparisons of classifiers over multiple data
sets. *JMLR* 7, 1-30.
Benavoli, A., Corani, G. & Mangili, F. (2016). Should we really use post-hoc
tests based on mean-ranks? *JMLR* 17(5), 1-10.
Holm, S. (1979). A simple sequentially rejective multiple test procedure.
*Scandinavian Journal of Statistics* 6, 65-70.
Wilcoxon, F. (1945). Individual comparisons by ranking methods.
*Biometrics Bulletin* 1, 80-83.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import stats as sps

from .aggregate import TIE_TOLERANCE, TaskTable

__all__ = ["holm", "wilcoxon", "wilcoxon_min_p", "Pairwise", "pairwise_wilcoxon"]


def holm(pvalues: Sequence[float]) -> np.ndarray:
    """Holm's step-down adjusted p-values (Holm 1979), in the order given.

    With the ``m`` p-values sorted, ``p_(1) <= ... <= p_(m)``, the adjusted
    ``p~_(i) = max_{j <= i} min(1, (m - j + 1) p_(j))``; rejecting where
    ``p~ <= alpha`` controls the family-wise error rate at ``alpha``. NaN
    stays NaN and does not count in ``m``.
    """
    p = np.asarray(pvalues, dtype=float)
    out = np.full(p.shape, np.nan)
    valid = np.flatnonzero(~np.isnan(p))
    order = valid[np.argsort(p[valid], kind="stable")]
    m = order.size
    scaled = np.minimum(1.0, (m - np.arange(m)) * p[order])
    out[order] = np.maximum.accumulate(scaled)
    return out


def wilcoxon_min_p(n: int) -> float:
    """The smallest two-sided p-value of the exact Wilcoxon signed-rank test on ``n`` tasks: ``2 / 2^n``.

    >>> wilcoxon_min_p(2), wilcoxon_min_p(8)
    (0.5, 0.0078125)
    """
    return min(1.0, 2.0 ** (1 - n)) if n > 0 else float("nan")


def _signed_rank_p(d: np.ndarray) -> float:
    """Exact two-sided p of the signed-rank statistic, zeros split, by the distribution of random signs.

    Ranks of ``|d|`` (averaged over ties) are halves at worst, so twice
    them are integers; the null distribution of the positive rank sum of the
    non-zero differences is counted by dynamic programming over them.
    """
    ranks = sps.rankdata(np.abs(d))
    nonzero = d != 0
    twice = np.rint(2 * ranks[nonzero]).astype(int)
    counts = np.zeros(int(twice.sum()) + 1)
    counts[0] = 1.0
    for r in twice:
        counts[r:] = counts[r:] + counts[:-r]
    probs = counts / counts.sum()
    observed = int(twice[d[nonzero] > 0].sum())
    centre = twice.sum() / 2
    totals = np.arange(counts.size)
    return float(min(1.0, probs[np.abs(totals - centre) >= abs(observed - centre) - 1e-9].sum()))


def wilcoxon(a: np.ndarray, b: np.ndarray) -> tuple[int, float, float]:
    """``(n, statistic, p)``: the exact two-sided Wilcoxon signed-rank test of ``a - b`` over shared tasks.

    Zero differences are kept and their ranks split evenly between the two
    sums, as Demsar (2006, section 3.1.3) recommends; ``statistic`` is the
    smaller rank sum. The p-value is exact: under the null hypothesis each
    non-zero difference is positive or negative with probability 1/2 (the
    zeros' split ranks are fixed). With no non-zero difference the test has
    nothing to say: p = 1. With no shared task: NaN.
    """
    shared = ~np.isnan(a) & ~np.isnan(b)
    d = a[shared] - b[shared]
    d[np.abs(d) <= TIE_TOLERANCE] = 0.0
    if d.size == 0:
        return 0, float("nan"), float("nan")
    if not np.any(d):
        return int(d.size), 0.0, 1.0
    ranks = sps.rankdata(np.abs(d))
    zeros = ranks[d == 0].sum() / 2
    plus, minus = ranks[d > 0].sum() + zeros, ranks[d < 0].sum() + zeros
    return int(d.size), float(min(plus, minus)), _signed_rank_p(d)


@dataclass
class Pairwise:
    """Wilcoxon signed-rank tests of every pair of detectors, Holm-corrected as one family.

    ``pvalue[i, j]`` and ``adjusted[i, j]`` (symmetric; NaN on the
    diagonal) for ``detectors[i]`` against ``detectors[j]``; ``n[i, j]`` the
    tasks both completed.
    """

    detectors: list[str]
    n: np.ndarray
    pvalue: np.ndarray
    adjusted: np.ndarray

    def significant(self, alpha: float = 0.05) -> np.ndarray:
        """``True`` where the pair differs at family-wise level ``alpha``."""
        return ~np.isnan(self.adjusted) & (np.nan_to_num(self.adjusted) <= alpha)


def pairwise_wilcoxon(table: TaskTable) -> Pairwise:
    """:func:`wilcoxon` for each of the ``k (k - 1) / 2`` pairs, then :func:`holm` over all of them."""
    k = len(table.detectors)
    n = np.zeros((k, k), dtype=int)
    p = np.full((k, k), np.nan)
    pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    for i, j in pairs:
        n[i, j], _, p[i, j] = wilcoxon(table.values[i], table.values[j])
    adjusted = np.full((k, k), np.nan)
    if pairs:
        rows, cols = np.array(pairs).T
        adjusted[rows, cols] = holm(p[rows, cols])
    return Pairwise(list(table.detectors), n + n.T, _symmetric(p), _symmetric(adjusted))


def _symmetric(upper: np.ndarray) -> np.ndarray:
    return np.where(np.isnan(upper), upper.T, upper)
