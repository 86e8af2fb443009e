"""Comparisons of detectors over tasks: paired differences, ranks, tests.

The unit is the task. The seeds of a task are aggregated first (their mean,
:func:`novelty.bench.stats.aggregate.task_table`): they share the task's
data or split, so they are repeated measurements of one task, not
independent data sets (Demsar 2006 takes the data set as the unit). Two
detectors are compared on the tasks both completed.

- :func:`paired_comparison`: each detector against a reference detector, the
  mean and standard error of the per-task difference, and the tasks won,
  tied and lost.
- :func:`task_ranks`: the rank of each detector on each task (1 = best, ties
  share the average rank).
- :func:`friedman`: Friedman's test that all detectors perform alike, over the
  tasks every detector completed (Friedman 1937; Demsar 2006, section 3.2.2),
  with the Iman-Davenport F form Demsar recommends. Its p-value is exact:
  the rankings of each task permuted at random (a fixed seed), since the
  chi-square and F approximations fail on few tasks (with two tasks and
  every ranking alike, F is infinite).
- the pairwise tests, in :mod:`.signed_rank` (and named here too):
  ``wilcoxon``, the exact Wilcoxon signed-rank test of a pair, and
  ``pairwise_wilcoxon``, every pair with Holm's correction for the family;
  ``wilcoxon_min_p``, the smallest p-value it can give.
- :func:`friedman_min_p`: the smallest p-value Friedman's test can give with
  so few tasks; when a test's smallest p-value is above the level, the test
  can say nothing and the summary says so instead of printing a p-value.
- :func:`cliques`: the groups a critical-difference diagram joins with a bar;
  :func:`nemenyi_cd`: Nemenyi's critical difference of average ranks.

References
----------
Demsar, J. (2006). Statistical comparisons of classifiers over multiple data
sets. *JMLR* 7, 1-30.
Friedman, M. (1937). The use of ranks to avoid the assumption of normality
implicit in the analysis of variance. *JASA* 32, 675-701.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

import numpy as np
from scipy import stats as sps

from .aggregate import TIE_TOLERANCE, TaskTable
from .signed_rank import Pairwise, holm, pairwise_wilcoxon, wilcoxon, wilcoxon_min_p

__all__ = [
    "paired_comparison",
    "ranks_within",
    "task_ranks",
    "Friedman",
    "friedman",
    "holm",
    "wilcoxon",
    "Pairwise",
    "pairwise_wilcoxon",
    "nemenyi_cd",
    "cliques",
    "wilcoxon_min_p",
    "friedman_min_p",
    "RANDOM_RANKINGS",
]

#: random rankings per task drawn for Friedman's exact p-value (seed 0)
RANDOM_RANKINGS = 20_000


def paired_comparison(table: TaskTable, reference: str) -> list[dict]:
    """Each detector minus ``reference``, over the tasks both completed.

    For detector ``a`` and reference ``r`` with values ``a_c`` and ``r_c``
    (means over seeds) on their shared tasks ``c = 1..n``, ``d_c = a_c - r_c``:
    ``mean = sum(d_c) / n``, ``se = sd(d_c) / sqrt(n)`` with the sample
    standard deviation (``ddof=1``; NaN for ``n < 2``), and ``wins``,
    ``ties``, ``losses`` count ``d_c > 0``, ``|d_c| <= TIE_TOLERANCE``,
    ``d_c < 0``. The reference's own record has ``n`` its completed tasks
    and a zero difference. Records are in the order of ``table.detectors``.
    """
    if reference not in table.detectors:
        raise ValueError(f"The reference detector {reference!r} is not in this run; "
                         f"expected one of {', '.join(table.detectors)}.")
    ref = table.row(reference)
    records = []
    for detector, values in zip(table.detectors, table.values):
        shared = ~np.isnan(values) & ~np.isnan(ref)
        d = values[shared] - ref[shared]
        n = int(d.size)
        tie = np.abs(d) <= TIE_TOLERANCE
        records.append({
            "detector": detector,
            "n": n,
            "mean_diff": float(d.mean()) if n else float("nan"),
            "se": float(d.std(ddof=1) / math.sqrt(n)) if n > 1 else float("nan"),
            "wins": int(np.sum(~tie & (d > 0))),
            "ties": int(np.sum(tie)),
            "losses": int(np.sum(~tie & (d < 0))),
        })
    return records


# -------------------------------------------------------------------- ranks
def ranks_within(values: np.ndarray) -> np.ndarray:
    """Rank the rows of ``values`` within each column: 1 = highest, ties share the average rank."""
    return np.apply_along_axis(lambda column: sps.rankdata(-column, method="average"), 0, values)


def task_ranks(table: TaskTable) -> np.ndarray:
    """``ranks[i, t]`` of ``table.detectors[i]`` on task ``t`` among the detectors with a value there.

    1 = best, ties averaged; a detector without a value on the task is NaN.
    """
    ranks = np.full(table.values.shape, np.nan)
    for t in range(table.values.shape[1]):
        has = ~np.isnan(table.values[:, t])
        if has.any():
            ranks[has, t] = sps.rankdata(-table.values[has, t], method="average")
    return ranks


# -------------------------------------------------------------------- tests
@dataclass
class Friedman:
    """Friedman's test over ``n_tasks`` complete tasks and ``k`` detectors.

    ``statistic`` is the chi-square (scipy's, corrected for ties),
    ``f`` the Iman-Davenport form ``F = (N - 1) chi2 / (N (k - 1) - chi2)``
    (infinite when every task ranks the detectors alike), ``pvalue`` the
    exact p-value by random rankings (:func:`friedman`), ``min_pvalue`` the
    smallest p-value possible with these ``N`` and ``k`` (:func:`friedman_min_p`),
    ``mean_ranks`` the average rank of each detector over the tasks (1 = best).
    """

    n_tasks: int
    k: int
    statistic: float
    f: float
    pvalue: float
    min_pvalue: float
    mean_ranks: np.ndarray


def friedman_min_p(k: int, n: int) -> float:
    """The smallest p-value of Friedman's exact test with ``k`` detectors and ``n`` tasks: ``(k!)^(1 - n)``.

    Under the null hypothesis each task ranks the detectors in one of ``k!``
    orders at random; the statistic is largest only when all ``n`` tasks
    rank them alike, which has probability ``k! / (k!)^n``.

    >>> friedman_min_p(3, 2), friedman_min_p(4, 2)
    (0.16666666666666666, 0.041666666666666664)
    """
    # exact, then rounded once: exp(lgamma) rounded differently from one libm to another
    return float(Fraction(1, math.factorial(k) ** (n - 1)))


def friedman(table: TaskTable, draws: int = RANDOM_RANKINGS, seed: int = 0) -> Friedman | None:
    """Friedman's test on the tasks every detector completed; ``None`` if it cannot apply.

    It needs at least three detectors and two complete tasks. The p-value is
    a randomization test: each task's ranking is permuted at random ``draws``
    times (``numpy`` generator seeded with ``seed``), and
    ``p = (1 + #{chi2* >= chi2}) / (1 + draws)``, valid however few the tasks
    (ties keep their tied ranks). When every detector ties on every task
    there is nothing to rank: statistic 0, p 1.
    """
    complete = table.complete()
    k, n = complete.values.shape
    if k < 3 or n < 2:
        return None
    ranks = ranks_within(complete.values)
    mean_ranks = ranks.mean(axis=1)
    floor = friedman_min_p(k, n)
    if np.all(np.ptp(complete.values, axis=0) <= TIE_TOLERANCE):
        return Friedman(n, k, 0.0, 0.0, 1.0, floor, mean_ranks)
    chi2 = float(sps.friedmanchisquare(*complete.values).statistic)
    rng = np.random.default_rng(seed)
    keys = rng.random((draws, k, n))
    shuffled = np.take_along_axis(np.broadcast_to(ranks, (draws, k, n)), np.argsort(keys, axis=1), axis=1)
    sums = shuffled.sum(axis=2)
    # the statistic is an increasing function of the sum of squared rank sums (ties are per task, unchanged)
    observed = float(np.sum(ranks.sum(axis=1) ** 2))
    p = (1 + int(np.count_nonzero(np.sum(sums ** 2, axis=1) >= observed - 1e-9))) / (1 + draws)
    denominator = n * (k - 1) - chi2
    f = (n - 1) * chi2 / denominator if denominator > 1e-12 else math.inf
    return Friedman(n, k, chi2, float(f), float(max(p, floor)), floor, mean_ranks)


def nemenyi_cd(k: int, n: int, alpha: float = 0.05) -> float:
    """Nemenyi's critical difference of average ranks (Demsar 2006, eq. in section 3.2.2).

    ``CD = q_alpha sqrt(k (k + 1) / (6 N))``, with ``q_alpha`` the
    studentized range quantile for ``k`` groups and infinite degrees of
    freedom divided by ``sqrt(2)`` (Demsar's table 5: 2.569 for k = 4).
    """
    q = sps.studentized_range.ppf(1 - alpha, k, np.inf) / math.sqrt(2)
    return float(q * math.sqrt(k * (k + 1) / (6 * n)))


def cliques(mean_ranks: Sequence[float], significant: np.ndarray) -> list[list[int]]:
    """The groups a critical-difference diagram joins with a bar.

    Detectors are taken in order of average rank; a group is a maximal run
    of detectors adjacent in that order among which no pair differs
    significantly (``significant[i, j]`` is ``False`` for every pair in it),
    as in Demsar's (2006) diagrams, with significance from any pairwise test.
    Runs inside a longer run and single detectors are left out. Each group
    lists indices into ``mean_ranks``, best first.
    """
    order = list(np.argsort(np.asarray(mean_ranks, dtype=float), kind="stable"))
    runs = []
    for start in range(len(order)):
        end = start
        while end + 1 < len(order) and not any(significant[order[end + 1], order[m]]
                                               for m in range(start, end + 1)):
            end += 1
        if end > start and not (runs and runs[-1][1] >= end):
            runs.append((start, end))
    return [[int(i) for i in order[s:e + 1]] for s, e in runs]
