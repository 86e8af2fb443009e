"""The statistics of a run: paired differences, ranks per task and the tests between detectors.

The paired comparison (:func:`paired_text`) sets each detector against a
reference detector on the (task, seed) cells both completed: the mean and
standard error of the per-cell difference of ROC AUC, and the cells won, tied
and lost (see :func:`novelty.bench.stats.across_tasks.paired_comparison`). The reference
is the suite's ``reference``, or else the detector ranked first
(:func:`novelty.bench.reports.ranking.reference_of`). :func:`statistics_markdown`
reports Friedman's test, the average ranks, Nemenyi's critical difference
and the Wilcoxon-Holm pairs (:mod:`novelty.bench.stats.across_tasks`).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..stats import across_tasks as stats
from .format import format_table, number, p_is, p_value, signed
from .ranking import detector_order, reference_of

#: the family-wise significance level of the tests in the summary
ALPHA = 0.05

__all__ = ["paired_text", "task_ranks_text", "statistics_line", "statistics_markdown", "ALPHA"]


def paired_text(rows: Sequence[dict], reference: str | None = None) -> str:
    """Each detector's ROC AUC minus the reference's, cell by cell, detectors in rank order."""
    reference = reference_of(rows, reference)
    if reference is None:
        return ""
    order = detector_order(rows)
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
            body.append([r["detector"], str(r["n"]), signed(r["mean_diff"], r["se"]), str(r["wins"]),
                         str(r["ties"]), str(r["losses"]), p_value(p)])
    return format_table(header, body)


def task_ranks_text(rows: Sequence[dict]) -> str:
    """The rank of each detector on each task (1 = best, by mean ROC AUC over seeds; ties averaged)."""
    order = detector_order(rows)
    tasks, ranks = stats.task_ranks(stats.cell_table(rows, detectors=order))
    with np.errstate(invalid="ignore"):
        average = [np.nanmean(r) if np.any(~np.isnan(r)) else np.nan for r in ranks]
    body = [[d, *(number(float(x), 1) for x in r), number(float(a), 2)] for d, r, a in zip(order, ranks, average)]
    body.sort(key=lambda b: (b[-1] == "-", float(b[-1]) if b[-1] != "-" else 0.0))
    return format_table(["detector", *tasks, "average rank"], body)


def statistics_line(rows: Sequence[dict]) -> str:
    """One line for the terminal: Friedman's test over the complete cells, or why there is none."""
    result = stats.friedman(stats.cell_table(rows))
    if result is None:
        return "No Friedman test: it needs three detectors and two cells they all completed."
    return (f"Friedman's test over {result.n_cells} cells that all {result.k} detectors completed: "
            f"{p_is(result.pvalue)}; ranks, pairwise tests and the critical-difference diagram are in "
            "summary.md and plots/.")


def statistics_markdown(rows: Sequence[dict], alpha: float = ALPHA) -> list[str]:
    """The tests of a run: Friedman, average ranks, Nemenyi's CD, the Wilcoxon-Holm groups and pairs."""
    order = detector_order(rows)
    table = stats.cell_table(rows, detectors=order)
    result = stats.friedman(table)
    if result is None:
        return ["The tests need at least three detectors that completed at least two common cells."]
    complete = table.complete()
    pairs = stats.pairwise_wilcoxon(table)
    groups = stats.cliques(result.mean_ranks, pairs.significant(alpha))
    lines = [
        f"Over the {result.n_cells} cells (task, seed) that all {result.k} detectors completed: "
        f"Friedman chi2 = {result.statistic:.2f}, {p_is(result.pvalue)} "
        f"(Iman-Davenport F = {result.f:.2f}, {p_is(result.f_pvalue)}); "
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
        "" if j >= i else p_value(pairs.adjusted[i, j]) + ("*" if pairs.significant(alpha)[i, j] else "")
        for j in range(len(order) - 1))] for i in range(len(order))]
    lines.append(format_table(["detector", *short[:-1]], body))
    return lines
