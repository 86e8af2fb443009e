"""The ranking of a run: detectors by mean and spread over seeds.

A detector's score for one seed is its ROC AUC averaged over the suite's tasks;
the ranking is by the mean of that score over seeds, and its spread is the
standard deviation over seeds (``ddof=1``; blank with a single seed). The
other columns are means over every successful cell of the detector. A
per-task table gives the mean and spread of the ROC AUC on each task.

The paired comparison (:func:`paired_text`) sets each detector against a
reference detector on the (task, seed) cells both completed: the mean and
standard error of the per-cell difference of ROC AUC, and the cells won, tied
and lost (see :func:`novelty.bench.stats.paired_comparison`). The reference
is the suite's ``reference``, or else the detector ranked first.
"""

from __future__ import annotations

import math
from collections import defaultdict
from typing import Iterable, Sequence

import numpy as np

from . import stats

__all__ = ["rank_detectors", "per_task", "format_table", "summary_markdown", "ranking_text",
           "paired_text", "reference_of"]


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


def rank_detectors(rows: Iterable[dict]) -> list[dict]:
    """One record a detector, best first (by mean ROC AUC over seeds)."""
    by_detector: dict[str, list[dict]] = defaultdict(list)
    for row in _in_order(rows):
        by_detector[row["detector"]].append(row)
    records = []
    for detector, cells in by_detector.items():
        ok = [r for r in cells if r.get("status") == "ok"]
        per_seed: dict[int, list[float]] = defaultdict(list)
        for r in ok:
            per_seed[r["seed"]].append(_num(r.get("roc_auc")))
        seed_scores = [_mean(v) for _, v in sorted(per_seed.items())]
        delays = [_num(r.get("detection_delay")) for r in ok]
        records.append({
            "detector": detector,
            "roc_auc": _mean(seed_scores),
            "roc_auc_sd": _sd(seed_scores),
            "average_precision": _mean(_num(r.get("average_precision")) for r in ok),
            "tpr_at_1pct_fpr": _mean(_num(r.get("tpr_at_1pct_fpr")) for r in ok),
            "tpr_at_5pct_fpr": _mean(_num(r.get("tpr_at_5pct_fpr")) for r in ok),
            "detection_delay": _mean(delays),
            "detected": sum(not math.isnan(d) for d in delays),
            "false_alarms": _mean(_num(r.get("false_alarms")) for r in ok),
            "integrated_novelty": _mean(_num(r.get("integrated_novelty")) for r in ok),
            "max_novelty": _mean(_num(r.get("max_novelty")) for r in ok),
            "train_time_s": _mean(_num(r.get("train_time_s")) for r in ok),
            "score_scans_per_s": _mean(_num(r.get("score_scans_per_s")) for r in ok),
            "peak_memory_mb": _mean(_num(r.get("peak_memory_mb")) for r in ok),
            "n_units": _mean(_num(r.get("n_units")) for r in ok),
            "cells": len(cells),
            "failed": len(cells) - len(ok),
        })
    records.sort(key=lambda r: (math.isnan(r["roc_auc"]), -np.nan_to_num(r["roc_auc"]), r["detector"]))
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
    header = ["#", "detector", "ROC AUC (± sd over seeds)", "AP", "TPR@1%", "TPR@5%",
              "delay", "false alarms", "integrated", "max", "train s", "MiB", "units", "failed"]
    body = [[
        str(r["rank"]), r["detector"], _pm(r["roc_auc"], r["roc_auc_sd"]),
        _fmt(r["average_precision"]), _fmt(r["tpr_at_1pct_fpr"]), _fmt(r["tpr_at_5pct_fpr"]),
        _fmt(r["detection_delay"], 1), _fmt(r["false_alarms"], 1), _fmt(r["integrated_novelty"], 2),
        _fmt(r["max_novelty"]), _fmt(r["train_time_s"], 3), _fmt(r["peak_memory_mb"], 2),
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


def _signed(mean: float, se: float) -> str:
    if math.isnan(mean):
        return "-"
    return f"{mean:+.3f}" + ("" if math.isnan(se) else f" ± {se:.3f}")


def paired_text(rows: Sequence[dict], reference: str | None = None) -> str:
    """Each detector's ROC AUC minus the reference's, cell by cell, detectors in rank order."""
    reference = reference_of(rows, reference)
    if reference is None:
        return ""
    order = [r["detector"] for r in rank_detectors(rows)]
    records = stats.paired_comparison(stats.cell_table(rows, detectors=order), reference)
    header = ["detector", "cells", f"ΔROC AUC vs {reference} (mean ± se)", "wins", "ties", "losses"]
    body = [[
        r["detector"], str(r["n"]),
        "(reference)" if r["detector"] == reference else _signed(r["mean_diff"], r["se"]),
        *(("-", "-", "-") if r["detector"] == reference else (str(r["wins"]), str(r["ties"]), str(r["losses"]))),
    ] for r in records]
    return format_table(header, body)


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


def summary_markdown(rows: Sequence[dict], title: str = "Benchmark", notes: Sequence[str] = (),
                     reference: str | None = None) -> str:
    """The ``summary.md`` of a run (``reference``: the detector of the paired comparison)."""
    rows = list(rows)
    chosen = reference_of(rows, reference)
    seeds = sorted({r["seed"] for r in rows})
    failed = [r for r in rows if r.get("status") != "ok"]
    parts = [
        f"# {title}",
        "",
        f"{len(rows)} cells: {len({r['detector'] for r in rows})} detectors x "
        f"{len({r['task'] for r in rows})} tasks x {len(seeds)} seeds ({', '.join(map(str, seeds))}); "
        f"{len(failed)} failed.",
        "",
        "## Ranking",
        "",
        "Ranked by ROC AUC averaged over tasks, mean ± standard deviation over seeds. Other columns "
        "are means over cells: average precision, true-positive rate at 1% and 5% false-positive "
        "rate, detection delay in scans (first novel scan to first alarm, at a threshold set from the "
        "training novelty only: its maximum unless a note below says otherwise), false alarms on a "
        "clean pass (or the normal test scans), integrated "
        "novelty over the test part with the resting activity subtracted and its maximum, "
        "training time, peak memory (MiB, traced), model size in units.",
        "",
        ranking_text(rows),
    ]
    if chosen is not None:
        parts += [
            "",
            f"## Paired comparison with {chosen}",
            "",
            f"Each detector's ROC AUC minus {chosen}'s on the same cell (same task, same seed), over "
            f"the cells both completed: mean ± standard error of the differences (positive: better "
            f"than {chosen}), and the cells won, tied and lost. The reference is "
            + ("the suite's `reference`." if reference is not None else
               "the detector ranked first (set `reference` in the suite or `--reference` to choose)."),
            "",
            paired_text(rows, chosen),
        ]
    parts += [
        "",
        "## ROC AUC per task",
        "",
        per_task_text(rows),
    ]
    if failed:
        parts += ["", "## Failed cells", ""]
        parts += [f"- {r['detector']} / {r['task']} / seed {r['seed']}: {r.get('error', '')}" for r in failed]
    if notes:
        parts += ["", "## Notes", "", *(f"- {n}" for n in notes)]
    return "\n".join(parts) + "\n"
