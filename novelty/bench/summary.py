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

import json
import math
from collections import defaultdict
from typing import Iterable, Sequence

import numpy as np

from . import metrics, stats

#: the family-wise significance level of the tests in the summary
ALPHA = 0.05
#: the metric detectors are ranked by
RANK_BY = "roc_auc"

__all__ = ["rank_detectors", "per_task", "format_table", "summary_markdown", "ranking_text",
           "paired_text", "reference_of", "task_ranks_text", "statistics_markdown", "statistics_line", "ALPHA"]


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
    table = stats.cell_table(rows, detectors=order)
    records = stats.paired_comparison(table, reference)
    adjusted = stats.pairwise_wilcoxon(table).adjusted[order.index(reference)]
    header = ["detector", "cells", f"ΔROC AUC vs {reference} (mean ± se)", "wins", "ties", "losses",
              "p (Wilcoxon, Holm)"]
    body = []
    for r, p in zip(records, adjusted):
        if r["detector"] == reference:
            body.append([r["detector"], str(r["n"]), "(reference)", "-", "-", "-", "-"])
        else:
            body.append([r["detector"], str(r["n"]), _signed(r["mean_diff"], r["se"]), str(r["wins"]),
                         str(r["ties"]), str(r["losses"]), _p(p)])
    return format_table(header, body)


def _p(value: float) -> str:
    if math.isnan(value):
        return "-"
    return "< 0.001" if value < 0.001 else f"{value:.3f}"


def _p_is(value: float) -> str:
    text = _p(value)
    return f"p {text}" if text.startswith("<") else f"p = {text}"


def task_ranks_text(rows: Sequence[dict]) -> str:
    """The rank of each detector on each task (1 = best, by mean ROC AUC over seeds; ties averaged)."""
    order = [r["detector"] for r in rank_detectors(rows)]
    tasks, ranks = stats.task_ranks(stats.cell_table(rows, detectors=order))
    with np.errstate(invalid="ignore"):
        average = [np.nanmean(r) if np.any(~np.isnan(r)) else np.nan for r in ranks]
    body = [[d, *(_fmt(float(x), 1) for x in r), _fmt(float(a), 2)] for d, r, a in zip(order, ranks, average)]
    body.sort(key=lambda b: (b[-1] == "-", float(b[-1]) if b[-1] != "-" else 0.0))
    return format_table(["detector", *tasks, "average rank"], body)


def statistics_line(rows: Sequence[dict]) -> str:
    """One line for the terminal: Friedman's test over the complete cells, or why there is none."""
    result = stats.friedman(stats.cell_table(rows))
    if result is None:
        return "No Friedman test: it needs three detectors and two cells they all completed."
    return (f"Friedman's test over {result.n_cells} cells that all {result.k} detectors completed: "
            f"{_p_is(result.pvalue)}; ranks, pairwise tests and the critical-difference diagram are in "
            "summary.md and plots/.")


def statistics_markdown(rows: Sequence[dict], alpha: float = ALPHA) -> list[str]:
    """The tests of a run: Friedman, average ranks, Nemenyi's CD, the Wilcoxon-Holm groups and pairs."""
    order = [r["detector"] for r in rank_detectors(rows)]
    table = stats.cell_table(rows, detectors=order)
    result = stats.friedman(table)
    if result is None:
        return ["The tests need at least three detectors that completed at least two common cells."]
    complete = table.complete()
    pairs = stats.pairwise_wilcoxon(table)
    groups = stats.cliques(result.mean_ranks, pairs.significant(alpha))
    lines = [
        f"Over the {result.n_cells} cells (task, seed) that all {result.k} detectors completed: "
        f"Friedman chi2 = {result.statistic:.2f}, {_p_is(result.pvalue)} "
        f"(Iman-Davenport F = {result.f:.2f}, {_p_is(result.f_pvalue)}); "
        f"Nemenyi's critical difference of average ranks at alpha = {alpha}: "
        f"{stats.nemenyi_cd(result.k, result.n_cells, alpha):.2f}.",
        "",
        "Average rank over these cells (1 = best) and the groups of detectors adjacent in rank among which "
        f"no pair differs (Wilcoxon signed-rank, Holm-corrected over all pairs, alpha = {alpha}); the "
        "critical-difference diagram (plots/critical-difference.png) draws them as bars.",
        "",
    ]
    by_rank = np.argsort(result.mean_ranks, kind="stable")
    lines.append(format_table(["detector", "average rank", "groups"], [
        [complete.detectors[i], f"{result.mean_ranks[i]:.2f}",
         " ".join(chr(ord("A") + g) for g, members in enumerate(groups) if i in members) or "-"]
        for i in by_rank]))
    n_pairs = result.k * (result.k - 1) // 2
    smallest = 2.0 ** (1 - result.n_cells)
    if smallest * n_pairs > alpha:
        lines += ["", f"With {result.n_cells} cells the smallest two-sided p-value of the exact Wilcoxon "
                  f"test is 2 / 2^{result.n_cells} = {smallest:.3g}; after Holm's correction over "
                  f"{n_pairs} pairs no pair can reach alpha = {alpha}. More seeds or tasks are needed "
                  "to separate detectors pair by pair."]
    lines += ["", "Pairwise Wilcoxon signed-rank tests over the cells both detectors completed, "
              "Holm-adjusted p-values (row vs column; * at or below alpha):", ""]
    short = [str(i + 1) for i in range(len(order))]
    body = [[f"{short[i]} {order[i]}", *(
        "" if j >= i else _p(pairs.adjusted[i, j]) + ("*" if pairs.significant(alpha)[i, j] else "")
        for j in range(len(order) - 1))] for i in range(len(order))]
    lines.append(format_table(["detector", *short[:-1]], body))
    return lines


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
                     reference: str | None = None, run: dict | None = None) -> str:
    """The ``summary.md`` of a run.

    ``reference``: the detector of the paired comparison (default: the one
    ranked first); ``run``: how the run was made (``command``, ``versions``
    as JSON, ``git_revision``), recorded at the end.
    """
    rows = list(rows)
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
        *_paired_section(rows, reference),
        "",
        "## ROC AUC per task",
        "",
        "Mean ± standard deviation over seeds.",
        "",
        per_task_text(rows),
        "",
        "## Ranks per task",
        "",
        "Rank of each detector on each task by its mean ROC AUC over seeds (1 = best, ties share the "
        "average rank), and the average over tasks.",
        "",
        task_ranks_text(rows),
        "",
        "## Statistics",
        "",
        *statistics_markdown(rows),
    ]
    if failed:
        parts += ["", "## Failed cells", ""]
        parts += [f"- {r['detector']} / {r['task']} / seed {r['seed']}: {r.get('error', '')}" for r in failed]
    if notes:
        parts += ["", "## Notes", "", *(f"- {n}" for n in notes)]
    parts += ["", "## How this run was made", "", *_provenance_lines(rows, run or {})]
    return "\n".join(parts) + "\n"


def _paired_section(rows: Sequence[dict], reference: str | None) -> list[str]:
    chosen = reference_of(rows, reference)
    if chosen is None:
        return []
    how = ("the suite's `reference`." if reference is not None else
           "the detector ranked first (set `reference` in the suite or `--reference` to choose).")
    return [
        "",
        f"## Paired comparison with {chosen}",
        "",
        f"Each detector's ROC AUC minus {chosen}'s on the same cell (same task, same seed), over "
        f"the cells both completed: mean ± standard error of the differences (positive: better "
        f"than {chosen}), the cells won, tied and lost, and the Holm-adjusted p-value of the "
        f"Wilcoxon signed-rank test of the pair (see Statistics). The reference is {how}",
        "",
        paired_text(rows, chosen),
    ]


def _provenance_lines(rows: Sequence[dict], run: dict) -> list[str]:
    lines = []
    if run.get("command"):
        lines.append(f"- command: `{run['command']}`")
    if run.get("versions"):
        versions = json.loads(run["versions"])
        lines.append("- versions: " + ", ".join(f"{k} {v}" for k, v in sorted(versions.items())))
    if run.get("git_revision"):
        lines.append(f"- revision: {run['git_revision']}")
    older = sorted({str(r.get("git_revision") or "unknown") for r in rows if "versions" in r}
                   - {run.get("git_revision")})
    if older:
        lines.append(f"- cells from earlier runs were computed at revision {', '.join(older)}")
    return lines or ["- not recorded"]
