"""The ranking of a run: detectors by mean and spread over seeds.

A detector's score for one seed is its ROC AUC averaged over the suite's tasks;
the ranking is by the mean of that score over seeds, and its spread is the
standard deviation over seeds (``ddof=1``; blank with a single seed). The
other columns are means over every successful cell of the detector. A
per-task table gives the mean and spread of the ROC AUC on each task.
"""

from __future__ import annotations

import math
from collections import defaultdict
from typing import Iterable, Sequence

import numpy as np

from . import metrics

#: the metric detectors are ranked by
RANK_BY = "roc_auc"

__all__ = ["rank_detectors", "per_task", "reference_of", "format_table", "ranking_text", "per_task_text",
           "RANK_BY"]


def _num(value) -> float:
    try:
        return float("nan") if value is None or value == "" else float(value)
    except (TypeError, ValueError):
        return float("nan")


def _in_order(rows: Iterable[dict]) -> list[dict]:
    # Backends finish cells in any order; summing in one order makes the table identical.
    return sorted(rows, key=lambda r: (str(r["detector"]), str(r["task"]), r["seed"], r["cell_id"]))


def _mean(values: Iterable[float]) -> float:
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.mean()) if arr.size else float("nan")


def _sd(values: Sequence[float]) -> float:
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.std(ddof=1)) if arr.size > 1 else float("nan")


#: what the summary shows of the machine and the model besides the metrics
_MACHINE = ["train_time_s", "score_scans_per_s", "peak_memory_mb", "n_units"]


def rank_detectors(rows: Iterable[dict]) -> list[dict]:
    """One record a detector, best first (by mean ROC AUC over seeds).

    The ROC AUC is averaged over the tasks of each seed, then over seeds
    (with its spread over seeds, ``roc_auc_sd``); every other metric of
    :data:`novelty.bench.metrics.METRICS` is the mean over the detector's
    successful cells.
    """
    by_detector: dict[str, list[dict]] = defaultdict(list)
    for row in _in_order(rows):
        by_detector[row["detector"]].append(row)
    records = []
    for detector, cells in by_detector.items():
        ok = [r for r in cells if r.get("status") == "ok"]
        per_seed: dict[int, list[float]] = defaultdict(list)
        for r in ok:
            per_seed[r["seed"]].append(_num(r.get(RANK_BY)))
        seed_scores = [_mean(v) for _, v in sorted(per_seed.items())]
        record = {"detector": detector}
        for column in [m.column for m in metrics.METRICS] + _MACHINE:
            record[column] = _mean(_num(r.get(column)) for r in ok)
        record[RANK_BY], record[f"{RANK_BY}_sd"] = _mean(seed_scores), _sd(seed_scores)
        record["detected"] = sum(not math.isnan(_num(r.get("detection_delay"))) for r in ok)
        record["cells"], record["failed"] = len(cells), len(cells) - len(ok)
        records.append(record)
    records.sort(key=lambda r: (math.isnan(r[RANK_BY]), -np.nan_to_num(r[RANK_BY]), r["detector"]))
    for i, record in enumerate(records, 1):
        record["rank"] = i
    return records


def per_task(rows: Iterable[dict]) -> dict[str, dict[str, tuple[float, float]]]:
    """``{detector: {task: (mean AUC, sd over seeds)}}`` over successful cells."""
    values: dict[str, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for row in _in_order(rows):
        if row.get("status") == "ok":
            values[row["detector"]][row["task"]].append(_num(row.get("roc_auc")))
    return {d: {t: (_mean(v), _sd(v)) for t, v in tasks.items()} for d, tasks in values.items()}


def _fmt(value: float, digits: int = 3) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    if isinstance(value, int):
        return str(value)
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    if abs(value) >= 100:
        return f"{value:.1f}"
    return f"{value:.{digits}f}"


def _pm(mean: float, sd: float) -> str:
    return _fmt(mean) + ("" if math.isnan(sd) else f" ± {_fmt(sd)}")


def format_table(header: Sequence[str], body: Sequence[Sequence[str]]) -> str:
    """A markdown table with aligned columns (readable as plain text too)."""
    widths = [max(len(h), *(len(r[i]) for r in body)) if body else len(h) for i, h in enumerate(header)]
    line = lambda cells: "| " + " | ".join(c.ljust(w) for c, w in zip(cells, widths)) + " |"  # noqa: E731
    rule = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    return "\n".join([line(header), rule, *(line(r) for r in body)])


def ranking_text(rows: Sequence[dict]) -> str:
    """The ranked table printed at the end of ``novelty bench``."""
    records = rank_detectors(rows)
    shown = [m for m in metrics.METRICS if m.heading is not None]
    header = ["#", "detector",
              *(m.heading + (" (± sd over seeds)" if m.column == RANK_BY else "") for m in shown),
              "train s", "MiB", "units", "failed"]
    body = [[
        str(r["rank"]), r["detector"],
        *(_pm(r[m.column], r[f"{RANK_BY}_sd"]) if m.column == RANK_BY else _fmt(r[m.column], m.digits)
          for m in shown),
        _fmt(r["train_time_s"], 3), _fmt(r["peak_memory_mb"], 2),
        "-" if math.isnan(r["n_units"]) else f"{r['n_units']:.0f}",
        f"{r['failed']}/{r['cells']}" if r["failed"] else "0",
    ] for r in records]
    return format_table(header, body)


def reference_of(rows: Sequence[dict], reference: str | None = None) -> str | None:
    """``reference`` if given, else the detector ranked first (``None`` for no rows)."""
    if reference is not None:
        return reference
    records = rank_detectors(rows)
    return records[0]["detector"] if records else None


def per_task_text(rows: Sequence[dict]) -> str:
    """ROC AUC per detector and task (mean ± sd over seeds), detectors in rank order."""
    order = [r["detector"] for r in rank_detectors(rows)]
    table = per_task(rows)
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    body = []
    for d in order:
        cells = table.get(d, {})
        body.append([d] + [_pm(*cells[t]) if t in cells else "-" for t in tasks])
    return format_table(["detector", *tasks], body)
