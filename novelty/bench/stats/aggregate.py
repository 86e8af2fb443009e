"""Reading result rows as numbers: one value a cell, then one value a task.

The seeds of a task are aggregated first (:func:`task_table`: their mean,
its confidence interval, and whether they repeated one measurement); the
comparisons between detectors take the task as their unit
(:mod:`novelty.bench.stats.across_tasks`).

Rows come from ``results.jsonl``/``results.csv`` (a missing or empty value is
NaN) and from backends that finish cells in any order: :func:`in_order` sorts
them so that every sum is taken in one order and a table is identical
whichever backend ran it.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np
from scipy import stats as sps

__all__ = ["as_float", "in_order", "mean", "sd", "TaskTable", "task_table", "seed_interval", "distinct",
           "bounds_of", "TIE_TOLERANCE", "CONFIDENCE"]


def as_float(value) -> float:
    """A row's value as a float; NaN for ``None``, ``""`` or text that is not a number.

    >>> as_float("0.5"), as_float(None), as_float("")
    (0.5, nan, nan)
    """
    try:
        return float("nan") if value is None or value == "" else float(value)
    except (TypeError, ValueError):
        return float("nan")


def in_order(rows: Iterable[dict]) -> list[dict]:
    """Rows sorted by detector, task, seed and cell (a fixed order for sums)."""
    return sorted(rows, key=lambda r: (str(r["detector"]), str(r["task"]), r["seed"], r["cell_id"]))


def mean(values: Iterable[float]) -> float:
    """The mean of the values that are not NaN (NaN if none)."""
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.mean()) if arr.size else float("nan")


def sd(values: Sequence[float]) -> float:
    """The sample standard deviation (``ddof=1``) of the values that are not NaN (NaN for fewer than 2)."""
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.std(ddof=1)) if arr.size > 1 else float("nan")


# ------------------------------------------------------------ seeds -> tasks
#: two values closer than this are equal (ROC AUCs are ratios of pair counts: equal up to rounding)
TIE_TOLERANCE = 1e-12
#: the confidence level of the intervals over seeds
CONFIDENCE = 0.95


@dataclass
class TaskTable:
    """A metric per detector and task, the seeds of each task aggregated first.

    The unit of every comparison built on it is the task: the seeds of one
    task share its data (or its split), so they are repeated measurements of
    that task, not independent data sets (Demsar 2006, section 2).

    Attributes
    ----------
    detectors, tasks : list of str
    values : ndarray of shape (n_detectors, n_tasks)
        The mean over the seeds a detector completed on the task (NaN: none).
    n_seeds : ndarray of int, same shape
        Seeds completed.
    n_distinct : ndarray of int, same shape
        Distinct values among them: 1 with several seeds means the seeds
        repeated one measurement (a fixed split and a deterministic detector).
    ci : ndarray of shape (n_detectors, n_tasks, 2)
        The 95 % Student-t interval of the mean over seeds
        (``mean ± t_{0.975, n-1} sd / sqrt(n)``), truncated to the metric's
        bounds (:func:`bounds_of`); NaN when the seeds gave fewer than two
        distinct values.
    """

    detectors: list[str]
    tasks: list[str]
    values: np.ndarray
    n_seeds: np.ndarray
    n_distinct: np.ndarray
    ci: np.ndarray
    #: what one column is
    unit: str = "task"

    def row(self, detector: str) -> np.ndarray:
        return self.values[self.detectors.index(detector)]

    def complete(self) -> "TaskTable":
        """Only the tasks every detector completed."""
        keep = ~np.isnan(self.values).any(axis=0)
        return TaskTable(self.detectors, [t for t, k in zip(self.tasks, keep) if k], self.values[:, keep],
                         self.n_seeds[:, keep], self.n_distinct[:, keep], self.ci[:, keep])

    def repeated_tasks(self) -> list[str]:
        """Tasks on which every detector's seeds gave one value (seeds repeat one measurement)."""
        out = []
        for t, task in enumerate(self.tasks):
            has = self.n_seeds[:, t] > 0
            if has.any() and np.all(self.n_seeds[has, t] > 1) and np.all(self.n_distinct[has, t] == 1):
                out.append(task)
        return out


def bounds_of(metric: str) -> tuple[float, float] | None:
    """The interval a metric's values lie in, by its name: a ROC AUC, a precision, a rate lie in [0, 1].

    >>> bounds_of("roc_auc"), bounds_of("detection_delay")
    ((0.0, 1.0), None)
    """
    bounded = (metric in ("roc_auc", "average_precision") or metric.endswith(("_auc", "_rate", "_fraction"))
               or metric.startswith("tpr_at_"))
    return (0.0, 1.0) if bounded else None


def seed_interval(values: Sequence[float], confidence: float = CONFIDENCE,
                  bounds: tuple[float, float] | None = None) -> tuple[float, float]:
    """The Student-t interval of the mean of ``values`` (NaN, NaN with fewer than two distinct values).

    ``mean ± t_{(1+c)/2, n-1} sd / sqrt(n)``; with ``bounds``, truncated to
    them (a mean of ROC AUCs lies in [0, 1]; on two seeds the t quantile is
    12.7 and the plain interval runs far outside).

    >>> [round(x, 4) for x in seed_interval([0.7, 0.8, 0.9])]
    [0.5516, 1.0484]
    >>> [round(x, 4) for x in seed_interval([0.7, 0.8, 0.9], bounds=(0.0, 1.0))]
    [0.5516, 1.0]
    """
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    if arr.size < 2 or np.ptp(arr) <= TIE_TOLERANCE:
        return float("nan"), float("nan")
    half = sps.t.ppf(0.5 + confidence / 2, arr.size - 1) * arr.std(ddof=1) / math.sqrt(arr.size)
    low, high = float(arr.mean() - half), float(arr.mean() + half)
    if bounds is not None:
        low, high = max(low, bounds[0]), min(high, bounds[1])
    return low, high


def distinct(values: Sequence[float]) -> int:
    """How many distinct values (equal within :data:`TIE_TOLERANCE`), NaN left out.

    >>> distinct([0.8, 0.8, 0.8 + 1e-15, float("nan")]), distinct([0.7, 0.8])
    (1, 2)
    """
    arr = np.sort(np.array([v for v in values if not math.isnan(v)], dtype=float))
    return int(arr.size and 1 + np.count_nonzero(np.diff(arr) > TIE_TOLERANCE))


def task_table(rows: Iterable[dict], metric: str = "roc_auc", detectors: Sequence[str] | None = None) -> TaskTable:
    """The ``metric`` of every successful row, seeds aggregated per (detector, task).

    Detectors in the order given (default: of appearance), tasks in their
    order of appearance; a failed cell, or one whose metric is undefined,
    counts for no seed.
    """
    rows = list(rows)
    names = list(detectors) if detectors is not None else list(dict.fromkeys(r["detector"] for r in rows))
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    seeds: dict[tuple[str, str], list[float]] = defaultdict(list)
    for r in in_order(rows):
        if r.get("status") == "ok" and not math.isnan(as_float(r.get(metric))):
            seeds[r["detector"], r["task"]].append(as_float(r.get(metric)))
    shape = (len(names), len(tasks))
    values, n, k = np.full(shape, np.nan), np.zeros(shape, dtype=int), np.zeros(shape, dtype=int)
    ci = np.full(shape + (2,), np.nan)
    for i, d in enumerate(names):
        for t, task in enumerate(tasks):
            v = seeds.get((d, task), [])
            if v:
                values[i, t], n[i, t], k[i, t] = float(np.mean(v)), len(v), distinct(v)
                ci[i, t] = seed_interval(v, bounds=bounds_of(metric))
    return TaskTable(names, tasks, values, n, k, ci)
