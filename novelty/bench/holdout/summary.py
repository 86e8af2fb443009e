"""The hold-out table: detectors ranked, with every metric of a hold-out cell.

Ranked by ROC AUC averaged over tasks, mean ± standard deviation over seeds
(:func:`novelty.bench.reports.ranking.rank_detectors`); the other columns
are means over the detector's successful cells of the metrics of
:data:`novelty.bench.holdout.metrics.METRICS`, and what the machine and the
model show (training time, peak memory, units).

Shares its name with ``novelty/bench/exploration/summary.py``, ``novelty/bench/reports/summary.py``,
``novelty/reproduce/experiments/summary.py``: each benchmark protocol's package holds its own
metrics, plots and summary; the reports and the paper's experiments summarise a run of theirs.
"""

from __future__ import annotations

import math
from typing import Sequence

from ..reports.format import escape, format_table, mean_spread, number
from ..reports.ranking import RANK_BY, rank_detectors
from . import metrics

__all__ = ["ranking_text", "summary_sections", "shown_metrics", "any_route"]

#: what the table shows of the machine and the model besides the metrics
_MACHINE = ["train_time_s", "score_scans_per_s", "peak_memory_mb", "n_units"]


def any_route(rows: Sequence[dict]) -> bool:
    """Whether a task of the run has a route (rows written before the column existed count as having one)."""
    return any(r.get("route", True) not in (False, "False") for r in rows if r.get("status") == "ok") \
        or not any(r.get("status") == "ok" for r in rows)


def shown_metrics(rows: Sequence[dict]) -> list:
    """The metrics the ranking shows: every one with a heading, the route metrics only where a task has a route."""
    route = any_route(rows)
    return [m for m in metrics.METRICS if m.heading is not None and (route or not m.route)]


def ranking_text(rows: Sequence[dict]) -> str:
    """The ranked table printed at the end of ``novelty bench``.

    Its columns: ``#``, ``detector``, then each metric of
    :func:`shown_metrics` (ROC AUC with its spread over seeds), ``train s``,
    ``MiB``, ``units``, ``failed``.
    """
    records = rank_detectors(rows, [m.column for m in metrics.METRICS] + _MACHINE)
    shown = shown_metrics(rows)
    header = ["#", "detector",
              *(m.heading + (" (± sd over seeds)" if m.column == RANK_BY else "") for m in shown),
              "train s", "MiB", "units", "failed"]
    body = [[
        str(r["rank"]), r["detector"],
        *(mean_spread(r[m.column], r[f"{RANK_BY}_sd"]) if m.column == RANK_BY else number(r[m.column], m.digits)
          for m in shown),
        number(r["train_time_s"], 3), number(r["peak_memory_mb"], 2),
        "-" if math.isnan(r["n_units"]) else f"{r['n_units']:.0f}",
        f"{r['failed']}/{r['cells']}" if r["failed"] else "0",
    ] for r in records]
    return format_table(header, body)


def summary_sections(rows: Sequence[dict]) -> list[str]:
    """The ranking section of ``summary.md``, then how each task split its scans."""
    route = ("detection delay in scans (first novel scan to first alarm, at a threshold set from the "
             "training novelty only: its maximum unless a note below says otherwise), false alarms on a "
             "clean pass (or the normal test scans), integrated novelty over the test part with the resting "
             "activity subtracted, " if any_route(rows) else "")
    no_route = ("" if all(r.get("route", True) not in (False, "False") for r in rows if r.get("status") == "ok")
                else " Route metrics (delay, false alarms, integrated novelty) are left out for tasks whose "
                "scans lie along no route (tables of scans drawn at random).")
    return [
        "## Ranking",
        "",
        "Ranked by ROC AUC averaged over tasks, mean ± standard deviation over seeds. Other columns "
        "are means over cells: average precision, true-positive rate at 1% and 5% false-positive "
        f"rate, {route}the maximum novelty, training time, peak memory (MiB, traced), model size in units."
        + no_route,
        "",
        ranking_text(rows),
        *_splits_section(rows),
    ]


def _splits_section(rows: Sequence[dict]) -> list[str]:
    """How each task's training and test parts were made, as its rows record it."""
    said: dict[str, str] = {}
    for r in rows:
        if r.get("status") == "ok" and r.get("task_split"):
            said.setdefault(r["task"], r["task_split"])
    if not said:
        return []
    return ["", "## How each task was split", "",
            *(f"- {escape(task)}: {text}." for task, text in said.items())]
