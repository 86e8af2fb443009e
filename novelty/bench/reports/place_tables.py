"""Objects in seen and in unseen places, apart: each detector's mean score on each, per recording.

The objects tasks say whether each object's place was seen before it appeared
(:mod:`novelty.tasks.objects.places`); a hold-out cell then reports the ROC AUC
of the objects in seen places and of those in unseen places, each against
the same normal scans (``roc_auc_seen``, ``roc_auc_unseen``), an exploration
cell their first-encounter AUC (``first_encounter_auc_seen``,
``first_encounter_auc_unseen``). :func:`place_means` averages them per
recording (a cell without such objects left out) and over the recordings;
:func:`places_text` writes the table.
"""

from __future__ import annotations

import math

from .format import format_table

__all__ = ["PLACE_COLUMNS", "place_means", "places_text"]

#: per protocol, the columns of a cell's AUC on objects in seen and in unseen places, and their counts
PLACE_COLUMNS = {"holdout": ("roc_auc_seen", "roc_auc_unseen", "n_novel_seen", "n_novel_unseen"),
                 "exploration": ("first_encounter_auc_seen", "first_encounter_auc_unseen", "n_first_seen",
                                 "n_first_unseen")}


def _mean(values) -> float:
    kept = [v for v in values if v is not None and not math.isnan(v)]
    return sum(kept) / len(kept) if kept else math.nan


def _recording(row: dict) -> str:
    """The recording of a row's task: the last word of the task's registered name (``...-radish-intel``)."""
    return row["task_name"].rpartition("-")[2]


def place_means(rows: list[dict]) -> dict:
    """``{detector: {"seen": {recording: mean, ..., "mean": m}, "unseen": {...}, "count_seen": {...},
    "count_unseen": {...}}}`` over the rows that report places (NaN where a recording has no such object).

    >>> rows = [{"detector": "d", "task_name": "inspection-objects-radish-intel", "roc_auc_seen": 0.9,
    ...          "roc_auc_unseen": float("nan"), "n_novel_seen": 5, "n_novel_unseen": 0},
    ...         {"detector": "d", "task_name": "inspection-objects-radish-intel", "roc_auc_seen": 0.7,
    ...          "roc_auc_unseen": 0.4, "n_novel_seen": 3, "n_novel_unseen": 2}]
    >>> m = place_means(rows)["d"]
    >>> round(m["seen"]["intel"], 3), m["unseen"]["intel"], m["count_seen"]["intel"], m["count_unseen"]["mean"]
    (0.8, 0.4, 8, 2)
    """
    protocol = "exploration" if any(r.get("policy") for r in rows) else "holdout"
    seen, unseen, n_seen, n_unseen = PLACE_COLUMNS[protocol]
    rows = [r for r in rows if r.get(seen) is not None or r.get(unseen) is not None]
    recordings = list(dict.fromkeys(_recording(r) for r in rows))
    out = {}
    for detector in dict.fromkeys(r["detector"] for r in rows):
        mine = [r for r in rows if r["detector"] == detector]
        found = {}
        for key, column in (("seen", seen), ("unseen", unseen)):
            means = {rec: _mean(r[column] for r in mine if _recording(r) == rec) for rec in recordings}
            found[key] = {**means, "mean": _mean(means.values())}
        for key, column in (("count_seen", n_seen), ("count_unseen", n_unseen)):
            counts = {rec: sum(r.get(column) or 0 for r in mine if _recording(r) == rec) for rec in recordings}
            found[key] = {**counts, "mean": sum(counts.values())}
        out[detector] = found
    return out


def places_text(rows: list[dict]) -> str:
    """The table of :func:`place_means`: per detector, seen and unseen side by side for each recording and
    over them (the mean of the recordings' means); the last line counts the objects' scans (hold-out) or
    first sights (exploration) of the first detector's cells."""
    means = place_means(rows)
    if not means:
        raise ValueError("No row reports objects in seen and unseen places (a task with a seen_place column).")
    recordings = [k for k in next(iter(means.values()))["seen"] if k != "mean"]
    keys = [*recordings, "mean"]

    def shown(v: float) -> str:
        return "-" if math.isnan(v) else f"{v:.3f}"

    body = [[f"`{d}`", *(shown(m[kind][k]) for k in keys for kind in ("seen", "unseen"))] for d, m in means.items()]
    first = next(iter(means.values()))
    counted = "first sights" if any(r.get("policy") for r in rows) else "objects' scans"
    body.append([counted, *(str(first[kind][k]) for k in keys for kind in ("count_seen", "count_unseen"))])
    headings = [f"{k} {kind}" for k in keys for kind in ("seen", "unseen")]
    return format_table(["detector", *headings], body)
