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
