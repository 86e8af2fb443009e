"""The ranking of a run: detectors by mean and spread over seeds.

A detector's score for one seed is its ROC AUC averaged over the suite's tasks;
the ranking is by the mean of that score over seeds, and its spread is the
standard deviation over seeds (``ddof=1``; blank with a single seed). Other
columns asked for are means over every successful cell of the detector. A
per-task table gives the mean and spread of the ROC AUC on each task.
"""

from __future__ import annotations

import math
from collections import defaultdict
from typing import Iterable, Sequence

import numpy as np

from ..stats.aggregate import as_float, in_order, mean, sd
from .format import format_table, mean_spread

#: the metric detectors are ranked by
RANK_BY = "roc_auc"

__all__ = ["rank_detectors", "per_task", "reference_of", "per_task_text", "detector_order", "RANK_BY"]


def rank_detectors(rows: Iterable[dict], columns: Sequence[str] = ()) -> list[dict]:
    """One record a detector, best first (by mean ROC AUC over seeds).

    The ROC AUC is averaged over the tasks of each seed, then over seeds
    (with its spread over seeds, ``roc_auc_sd``); each of ``columns`` is the
    mean over the detector's successful cells.
    """
    by_detector: dict[str, list[dict]] = defaultdict(list)
    for row in in_order(rows):
        by_detector[row["detector"]].append(row)
    records = []
    for detector, cells in by_detector.items():
        ok = [r for r in cells if r.get("status") == "ok"]
        per_seed: dict[int, list[float]] = defaultdict(list)
        for r in ok:
            per_seed[r["seed"]].append(as_float(r.get(RANK_BY)))
        seed_scores = [mean(v) for _, v in sorted(per_seed.items())]
        record = {"detector": detector}
        for column in columns:
            record[column] = mean(as_float(r.get(column)) for r in ok)
        record[RANK_BY], record[f"{RANK_BY}_sd"] = mean(seed_scores), sd(seed_scores)
        record["cells"], record["failed"] = len(cells), len(cells) - len(ok)
        records.append(record)
    records.sort(key=lambda r: (math.isnan(r[RANK_BY]), -np.nan_to_num(r[RANK_BY]), r["detector"]))
    for i, record in enumerate(records, 1):
        record["rank"] = i
    return records


def per_task(rows: Iterable[dict]) -> dict[str, dict[str, tuple[float, float]]]:
    """``{detector: {task: (mean AUC, sd over seeds)}}`` over successful cells."""
    values: dict[str, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for row in in_order(rows):
        if row.get("status") == "ok":
            values[row["detector"]][row["task"]].append(as_float(row.get(RANK_BY)))
    return {d: {t: (mean(v), sd(v)) for t, v in tasks.items()} for d, tasks in values.items()}


def detector_order(rows: Iterable[dict]) -> list[str]:
    """The detectors' labels, best first."""
    return [r["detector"] for r in rank_detectors(rows)]


def reference_of(rows: Sequence[dict], reference: str | None = None) -> str | None:
    """``reference`` if given, else the first detector by label (``None`` for no rows).

    The default never depends on the results: a reference that changed with
    the ranking would pair the detectors with another one from run to run. A
    run passes its suite's reference (its ``reference``, else its first
    detector: :attr:`novelty.bench.suite.Suite.reference_label`).
    """
    if reference is not None:
        return reference
    labels = sorted({str(r["detector"]) for r in rows})
    return labels[0] if labels else None


def per_task_text(rows: Sequence[dict]) -> str:
    """ROC AUC per detector and task (mean ± sd over seeds), detectors in rank order."""
    order = detector_order(rows)
    table = per_task(rows)
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    body = []
    for d in order:
        cells = table.get(d, {})
        body.append([d] + [mean_spread(*cells[t]) if t in cells else "-" for t in tasks])
    return format_table(["detector", *tasks], body)
