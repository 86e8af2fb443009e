"""Comparisons of detectors over the cells of a run: paired differences, ranks, tests.

A *cell* here is a (task, seed) pair; two detectors are compared on the cells
that both completed with a ROC AUC, so that every difference is paired: same
scans, same seed.

- :func:`paired_comparison`: each detector against a reference detector, the
  mean and standard error of the per-cell difference of ROC AUC, and the
  number of cells it wins, ties and loses.
- :func:`task_ranks`: the rank of each detector on each task (by its mean ROC
  AUC over seeds, 1 = best, ties share the average rank), and the average
  rank over tasks.
- :func:`friedman`: Friedman's test that all detectors perform alike, over
  the cells every detector completed (Friedman 1937; Demsar 2006, section 3.2.2),
  with the Iman-Davenport F form Demsar recommends.
- :func:`pairwise_wilcoxon`: the Wilcoxon signed-rank test for every pair of
  detectors over their shared cells, with Holm's correction for the family of
  pairs (Holm 1979; Benavoli, Corani & Mangili 2016).
- :func:`cliques`: the groups a critical-difference diagram joins with a bar.
- :func:`nemenyi_cd`: Nemenyi's critical difference of average ranks
  (Demsar 2006, section 3.2.2), reported beside the Wilcoxon-Holm groups.

The seeds of one task are not independent samples of a population of tasks
(they share the task's generator), so a p-value over (task, seed) cells
speaks of these tasks, not of sonar tasks in general.

The module is a little over 300 lines and kept whole: every test reads the
same cell table and ranks, and a reader checks them all against Demsar (2006)
in one place.

References
----------
Demsar, J. (2006). Statistical comparisons of classifiers over multiple data
sets. *JMLR* 7, 1-30.
Benavoli, A., Corani, G. & Mangili, F. (2016). Should we really use post-hoc
tests based on mean-ranks? *JMLR* 17(5), 1-10.
Friedman, M. (1937). The use of ranks to avoid the assumption of normality
implicit in the analysis of variance. *JASA* 32, 675-701.
Holm, S. (1979). A simple sequentially rejective multiple test procedure.
*Scandinavian Journal of Statistics* 6, 65-70.
Wilcoxon, F. (1945). Individual comparisons by ranking methods.
*Biometrics Bulletin* 1, 80-83.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np
from scipy import stats as sps

__all__ = [
    "TIE_TOLERANCE",
    "CellTable",
    "cell_table",
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
]

#: two ROC AUCs closer than this are a tie (they are ratios of pair counts, so
#: equal AUCs are equal up to rounding)
TIE_TOLERANCE = 1e-12


def _value(row: dict, metric: str) -> float:
    try:
        value = float(row.get(metric))
    except (TypeError, ValueError):
        return float("nan")
    return value


@dataclass
class CellTable:
    """A metric per detector and cell: ``values[i, j]`` for ``detectors[i]`` on ``cells[j]``.

    ``cells`` are ``(task, seed)`` pairs, tasks in their order of appearance;
    a cell a detector did not complete (failed, missing, or an undefined
    metric) is NaN.
    """

    detectors: list[str]
    cells: list[tuple[str, int]]
    values: np.ndarray

    def row(self, detector: str) -> np.ndarray:
        return self.values[self.detectors.index(detector)]

    def complete(self) -> "CellTable":
        """Only the cells every detector completed."""
        keep = ~np.isnan(self.values).any(axis=0)
        return CellTable(self.detectors, [c for c, k in zip(self.cells, keep) if k], self.values[:, keep])


def cell_table(rows: Iterable[dict], metric: str = "roc_auc", detectors: Sequence[str] | None = None) -> CellTable:
    """The ``metric`` of every successful row, as a :class:`CellTable`."""
    rows = list(rows)
    names = list(detectors) if detectors is not None else list(dict.fromkeys(r["detector"] for r in rows))
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    cells = sorted({(r["task"], int(r["seed"])) for r in rows}, key=lambda c: (tasks.index(c[0]), c[1]))
    values = np.full((len(names), len(cells)), np.nan)
    where = {c: j for j, c in enumerate(cells)}
    index = {d: i for i, d in enumerate(names)}
    for r in rows:
        if r.get("status") == "ok" and r["detector"] in index:
            values[index[r["detector"]], where[(r["task"], int(r["seed"]))]] = _value(r, metric)
    return CellTable(names, cells, values)


def paired_comparison(table: CellTable, reference: str) -> list[dict]:
    """Each detector minus ``reference``, over the cells both completed.

    For detector ``a`` and reference ``r`` with ROC AUCs ``a_c`` and ``r_c``
    on their shared cells ``c = 1..n``, ``d_c = a_c - r_c``:
    ``mean = sum(d_c) / n``, ``se = sd(d_c) / sqrt(n)`` with the sample
    standard deviation (``ddof=1``; NaN for ``n < 2``), and ``wins``,
    ``ties``, ``losses`` count ``d_c > 0``, ``|d_c| <= TIE_TOLERANCE``,
    ``d_c < 0``. The reference's own record has ``n`` its completed cells
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


def task_ranks(table: CellTable) -> tuple[list[str], np.ndarray]:
    """Tasks, and ``ranks[i, t]`` of ``table.detectors[i]`` on task ``t``.

    A detector's score on a task is its mean ROC AUC over the seeds it
    completed; detectors are ranked on each task among those with a score
    (1 = best, ties averaged); a detector without a score there is NaN.
    """
    tasks = list(dict.fromkeys(task for task, _ in table.cells))
    ranks = np.full((len(table.detectors), len(tasks)), np.nan)
    for t, task in enumerate(tasks):
        columns = [j for j, (name, _) in enumerate(table.cells) if name == task]
        scores = table.values[:, columns]
        has = ~np.isnan(scores).all(axis=1)
        if has.any():
            means = np.nanmean(scores[has], axis=1)
            ranks[has, t] = sps.rankdata(-means, method="average")
    return tasks, ranks


# -------------------------------------------------------------------- tests
@dataclass
class Friedman:
    """Friedman's test over ``n_cells`` complete cells and ``k`` detectors.

    ``statistic`` is scipy's chi-square (corrected for ties), ``f``/``f_pvalue``
    the Iman-Davenport form ``F = (N - 1) chi2 / (N (k - 1) - chi2)`` with
    ``(k - 1, (k - 1)(N - 1))`` degrees of freedom, ``mean_ranks`` the
    average rank of each detector over the cells (1 = best).
    """

    n_cells: int
    k: int
    statistic: float
    pvalue: float
    f: float
    f_pvalue: float
    mean_ranks: np.ndarray


def friedman(table: CellTable) -> Friedman | None:
    """Friedman's test on the cells every detector completed; ``None`` if it cannot apply.

    It needs at least three detectors and two complete cells. When every
    detector ties on every cell there is nothing to rank: statistic 0, p 1.
    """
    complete = table.complete()
    k, n = complete.values.shape
    if k < 3 or n < 2:
        return None
    mean_ranks = ranks_within(complete.values).mean(axis=1)
    if np.all(np.ptp(complete.values, axis=0) <= TIE_TOLERANCE):
        return Friedman(n, k, 0.0, 1.0, 0.0, 1.0, mean_ranks)
    chi2, p = sps.friedmanchisquare(*complete.values)
    denominator = n * (k - 1) - chi2
    f = (n - 1) * chi2 / denominator if denominator > 0 else math.inf
    f_p = float(sps.f.sf(f, k - 1, (k - 1) * (n - 1))) if math.isfinite(f) else 0.0
    return Friedman(n, k, float(chi2), float(p), float(f), f_p, mean_ranks)


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


def wilcoxon(a: np.ndarray, b: np.ndarray) -> tuple[int, float, float]:
    """``(n, statistic, p)``: the two-sided Wilcoxon signed-rank test of ``a - b`` over shared cells.

    Zero differences are kept and their ranks split evenly between the two
    sums, as Demsar (2006, section 3.1.3) recommends (scipy's
    ``zero_method="zsplit"``); ``statistic`` is the smaller rank sum. With
    no non-zero difference the test has nothing to say: p = 1. With no
    shared cell: NaN.
    """
    shared = ~np.isnan(a) & ~np.isnan(b)
    d = a[shared] - b[shared]
    d[np.abs(d) <= TIE_TOLERANCE] = 0.0
    if d.size == 0:
        return 0, float("nan"), float("nan")
    if not np.any(d):
        return int(d.size), 0.0, 1.0
    result = sps.wilcoxon(d, zero_method="zsplit")
    return int(d.size), float(result.statistic), float(result.pvalue)


@dataclass
class Pairwise:
    """Wilcoxon signed-rank tests of every pair of detectors, Holm-corrected as one family.

    ``pvalue[i, j]`` and ``adjusted[i, j]`` (symmetric; NaN on the
    diagonal) for ``detectors[i]`` against ``detectors[j]``; ``n[i, j]`` the
    cells both completed.
    """

    detectors: list[str]
    n: np.ndarray
    pvalue: np.ndarray
    adjusted: np.ndarray

    def significant(self, alpha: float = 0.05) -> np.ndarray:
        """``True`` where the pair differs at family-wise level ``alpha``."""
        return ~np.isnan(self.adjusted) & (np.nan_to_num(self.adjusted) <= alpha)


def pairwise_wilcoxon(table: CellTable) -> Pairwise:
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
