"""The critical-difference diagram of a run (Demsar 2006, figure 1), for every protocol.

Detectors hang from their average rank; a bar joins each group of detectors
adjacent in rank among which no pair differs significantly.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from ..stats import across_tasks as stats
from ..stats.aggregate import task_table
from .figures import pyplot, save, seeds_text
from .ranking import detector_order
from .statistics import ALPHA

__all__ = ["draw_critical_difference", "plot_critical_difference"]


def draw_critical_difference(ax, names: Sequence[str], mean_ranks: Sequence[float],
                             groups: Sequence[Sequence[int]]) -> None:
    """A critical-difference diagram on ``ax`` (Demsar 2006, figure 1).

    The axis carries the average ranks (1 = best, on the left); each
    detector hangs from its rank, the better half labelled on the left, the
    rest on the right; a thick bar joins each group of ``groups`` (indices
    into ``names``), detectors whose differences are not significant.
    """
    k = len(names)
    ranks = np.asarray(mean_ranks, dtype=float)
    order = list(np.argsort(ranks, kind="stable"))
    bar_step, label_step = 0.12, 0.3
    top_label = 0.25 + bar_step * len(groups)
    ax.hlines(0, 1, k, color="k", linewidth=1)
    for r in range(1, k + 1):
        ax.vlines(r, 0, 0.08, color="k", linewidth=1)
        ax.text(r, 0.12, str(r), ha="center", va="bottom", fontsize=8)
    half = (k + 1) // 2
    for position, i in enumerate(order):
        left = position < half
        line = position if left else k - 1 - position
        y = -top_label - line * label_step
        end = 1 - 0.4 if left else k + 0.4
        ax.plot([ranks[i], ranks[i], end], [0, y, y], color="k", linewidth=0.8)
        ax.text(end - 0.08 if left else end + 0.08, y, f"{names[i]} ({ranks[i]:.2f})",
                ha="right" if left else "left", va="center", fontsize=8)
    for g, members in enumerate(groups):
        y = -0.15 - g * bar_step
        ax.hlines(y, ranks[members].min() - 0.05, ranks[members].max() + 0.05, color="k", linewidth=3)
    lowest = -top_label - (half - 1) * label_step
    ax.set(xlim=(1 - 0.4, k + 0.4), ylim=(lowest - 0.3, 0.45))
    ax.axis("off")


def plot_critical_difference(rows: Sequence[dict], out: Path, alpha: float = ALPHA) -> list[Path]:
    """``critical-difference.png``: average ranks over the complete tasks, Wilcoxon-Holm groups.

    Groups come from the Wilcoxon signed-rank test of each pair with Holm's
    correction (Benavoli, Corani & Mangili 2016), not from Nemenyi's critical
    difference, whose verdict on a pair depends on the other detectors in the
    comparison; the title names the test the bars come from and Friedman's p-value.
    Nothing is written when Friedman's test cannot apply (fewer than three
    detectors or two complete tasks).
    """
    order = detector_order(rows)
    table = task_table(rows, detectors=order)
    result = stats.friedman(table)
    if result is None:
        return []
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    groups = stats.cliques(result.mean_ranks, stats.pairwise_wilcoxon(table).significant(alpha))
    plt = pyplot()
    k = len(order)
    fig, ax = plt.subplots(figsize=(9, 1.2 + 0.3 * ((k + 1) // 2) + 0.12 * len(groups)))
    fig.subplots_adjust(left=0.27, right=0.73, top=0.8, bottom=0.02)
    draw_critical_difference(ax, order, result.mean_ranks, groups)
    complete = set(table.complete().tasks)
    seeds = seeds_text([r["seed"] for r in rows if r["task"] in complete and r.get("status") == "ok"])
    friedman_text = (f"Friedman p = {result.pvalue:.2g}" if result.min_pvalue <= alpha else
                     f"too few tasks for any test at alpha = {alpha}")
    fig.suptitle(f"Average rank of ROC AUC over {result.n_tasks} tasks (1 = best; each task the mean over "
                 f"{seeds}), in brackets; {friedman_text}\n"
                 f"bars join detectors no test separates (exact Wilcoxon signed-rank over tasks, Holm, "
                 f"alpha = {alpha})", fontsize=9)
    return [save(fig, out / "critical-difference.png", tight=False)]
