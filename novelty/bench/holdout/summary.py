"""The hold-out table: detectors ranked, with every metric of a hold-out cell.

Ranked by ROC AUC averaged over tasks, mean ± standard deviation over seeds
(:func:`novelty.bench.reports.ranking.rank_detectors`); the other columns
are means over the detector's successful cells of the metrics of
:data:`novelty.bench.holdout.metrics.METRICS`, and what the machine and the
model show (training time, peak memory, units).
"""

from __future__ import annotations

import math
from typing import Sequence

from ..reports.format import format_table, mean_spread, number
from ..reports.ranking import RANK_BY, rank_detectors
from . import metrics

__all__ = ["ranking_text", "summary_sections"]

#: what the table shows of the machine and the model besides the metrics
_MACHINE = ["train_time_s", "score_scans_per_s", "peak_memory_mb", "n_units"]


def ranking_text(rows: Sequence[dict]) -> str:
    """The ranked table printed at the end of ``novelty bench``."""
    records = rank_detectors(rows, [m.column for m in metrics.METRICS] + _MACHINE)
    shown = [m for m in metrics.METRICS if m.heading is not None]
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
    """The ranking section of ``summary.md``."""
    return [
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
