"""The statistics of a run, over tasks: paired differences, ranks per task and the tests.

The unit of every table here is the task: the seeds of a task are averaged
first (:func:`novelty.bench.stats.aggregate.task_table`), because seeds of one
task are repeated measurements of it, not independent data sets.

- :func:`paired_text`: each detector against a reference detector on the
  tasks both completed: the mean and standard error of the per-task
  difference of ROC AUC, the tasks won, tied and lost, the Holm-adjusted
  exact Wilcoxon p-value, and the Bayesian signed-rank test's probabilities
  (Benavoli et al. 2017) that the detector is practically worse, equivalent
  or better (region of practical equivalence ± :data:`~novelty.bench.stats.bayesian.ROPE`).
  The reference is the suite's ``reference``, or else the detector ranked
  first (:func:`novelty.bench.reports.ranking.reference_of`).
- :func:`seeds_text`: the per-task mean with its confidence interval over
  seeds, and which tasks' seeds repeated one measurement.
- :func:`statistics_markdown`: Friedman's test, the average ranks, Nemenyi's
  critical difference and the Wilcoxon-Holm pairs
  (:mod:`novelty.bench.stats.across_tasks`), or, when there are too few tasks
  for a test to reach the level, why it cannot.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..stats import across_tasks as stats
from ..stats.aggregate import task_table
from ..stats.bayesian import ROPE, bayesian_signed_rank
from .format import format_table, number, p_is, p_value, signed
from .ranking import detector_order, reference_of

#: the family-wise significance level of the tests in the summary
ALPHA = 0.05
#: the fewest tasks the Bayesian signed-rank test is shown for (our choice: on fewer, its posterior
#: rests on a handful of differences; two differences of one sign already give P(better) = 0.96)
MIN_TASKS_BAYES = 5

__all__ = ["paired_text", "seeds_text", "task_ranks_text", "statistics_line", "statistics_markdown",
           "too_few_tasks", "repeated_text", "ALPHA", "MIN_TASKS_BAYES"]


def _table(rows: Sequence[dict]):
    return task_table(rows, detectors=detector_order(rows))


def paired_text(rows: Sequence[dict], reference: str | None = None) -> str:
    """Each detector's ROC AUC minus the reference's, task by task (means over seeds), in rank order."""
    reference = reference_of(rows, reference)
    table = _table(rows)
    if reference is None or reference not in table.detectors:  # no row of it yet (an interrupted run)
        return ""
    records = stats.paired_comparison(table, reference)
    adjusted = stats.pairwise_wilcoxon(table).adjusted[table.detectors.index(reference)]
    if _pairs_cannot_reach(table):  # a p-value that cannot reach the level says nothing: not shown
        adjusted = np.full(adjusted.shape, np.nan)
    ref = table.row(reference)
    header = ["detector", "tasks", f"ΔROC AUC vs {reference} (mean ± se)", "wins", "ties", "losses",
              "p (Wilcoxon, Holm)", "P(worse, equiv., better)"]
    body = []
    for r, p, values in zip(records, adjusted, table.values):
        if r["detector"] == reference:
            body.append([r["detector"], str(r["n"]), "(reference)", "-", "-", "-", "-", "-"])
            continue
        bayes = bayesian_signed_rank(values, ref)
        body.append([r["detector"], str(r["n"]), signed(r["mean_diff"], r["se"]), str(r["wins"]),
                     str(r["ties"]), str(r["losses"]), p_value(p),
                     f"{bayes.left:.2f}, {bayes.equivalent:.2f}, {bayes.right:.2f}"
                     if bayes.n >= MIN_TASKS_BAYES else "-"])
    return format_table(header, body)


def seeds_text(rows: Sequence[dict]) -> str:
    """ROC AUC per detector and task: the mean over seeds and its 95 % interval (unit: seed within a task).

    A cell reads ``0.812 [0.790, 0.834]``; ``0.812 (1 value, 3 seeds)`` when
    the seeds gave one value (a fixed split and a deterministic detector).
    """
    table = _table(rows)
    body = []
    for i, d in enumerate(table.detectors):
        line = [d]
        for t in range(len(table.tasks)):
            n, k, (low, high) = table.n_seeds[i, t], table.n_distinct[i, t], table.ci[i, t]
            if n == 0:
                line.append("-")
            elif k == 1 and n > 1:
                line.append(f"{number(table.values[i, t])} (1 value, {n} seeds)")
            elif n == 1:
                line.append(number(table.values[i, t]))
            else:
                line.append(f"{number(table.values[i, t])} [{number(low)}, {number(high)}]")
        body.append(line)
    return format_table(["detector", *table.tasks], body)


def _pairs_cannot_reach(table, alpha: float = ALPHA) -> bool:
    n = int((~np.isnan(table.values)).all(axis=0).sum())
    k = len(table.detectors)
    return n < 1 or stats.wilcoxon_min_p(n) * max(k * (k - 1) // 2, 1) > alpha


def repeated_text(rows: Sequence[dict]) -> str:
    """A sentence naming the tasks whose seeds repeated one measurement for every detector ("" if none)."""
    repeated = _table(rows).repeated_tasks()
    if not repeated:
        return ""
    return (f"On {', '.join(repeated)} every detector gave the same value on every seed (a fixed split "
            "and deterministic detectors): the seeds repeat one measurement, so each such task is one "
            "measurement, without a spread.")


def task_ranks_text(rows: Sequence[dict]) -> str:
    """The rank of each detector on each task (1 = best, by mean ROC AUC over seeds; ties averaged)."""
    table = _table(rows)
    ranks = stats.task_ranks(table)
    with np.errstate(invalid="ignore"):
        average = [np.nanmean(r) if np.any(~np.isnan(r)) else np.nan for r in ranks]
    body = [[d, *(number(float(x), 1) for x in r), number(float(a), 2)]
            for d, r, a in zip(table.detectors, ranks, average)]
    body.sort(key=lambda b: (b[-1] == "-", float(b[-1]) if b[-1] != "-" else 0.0))
    return format_table(["detector", *table.tasks, "average rank"], body)


def too_few_tasks(k: int, n: int, alpha: float = ALPHA) -> list[str]:
    """Why the tests cannot reach ``alpha`` with ``k`` detectors on ``n`` tasks ([] when they can).

    >>> too_few_tasks(3, 2)[0][:60]
    'With 2 tasks no pair of detectors can differ significantly: '
    """
    lines = []
    pairs = k * (k - 1) // 2
    floor = stats.wilcoxon_min_p(n)
    if floor * max(pairs, 1) > alpha:
        lines.append(f"With {n} tasks no pair of detectors can differ significantly: the smallest "
                     f"two-sided p-value of Wilcoxon's signed-rank test on {n} tasks is 2 / 2^{n} = "
                     f"{floor:.3g}" + (f", times {pairs} pairs by Holm's correction" if pairs > 1 else "")
                     + f", above alpha = {alpha}. More tasks are needed, not more seeds: seeds of one "
                     "task are not independent data sets.")
    if k >= 3 and stats.friedman_min_p(k, n) > alpha:
        lines.append(f"Friedman's test cannot reach alpha = {alpha} either: with {k} detectors and {n} "
                     f"tasks its smallest p-value is (k!)^(1 - N) = {stats.friedman_min_p(k, n):.3g}.")
    return lines


def statistics_line(rows: Sequence[dict], alpha: float = ALPHA) -> str:
    """One line for the terminal: Friedman's test over tasks, or why there is none."""
    table = _table(rows)
    result = stats.friedman(table)
    if result is None:
        return "No Friedman test: it needs three detectors and two tasks they all completed."
    if result.min_pvalue > alpha:
        return (f"No significance claim: with {result.n_tasks} tasks and {result.k} detectors no test "
                f"can reach alpha = {alpha} (see summary.md, Statistics).")
    pairs = (f" With {result.n_tasks} tasks no pair of detectors can differ significantly (Wilcoxon's "
             f"smallest p is {stats.wilcoxon_min_p(result.n_tasks):.3g})." if _pairs_cannot_reach(table, alpha)
             else "")
    return (f"Friedman's test over the {result.n_tasks} tasks that all {result.k} detectors completed: "
            f"{p_is(result.pvalue)}; ranks, pairwise tests and the critical-difference diagram are in "
            f"summary.md and plots/.{pairs}")


def statistics_markdown(rows: Sequence[dict], alpha: float = ALPHA) -> list[str]:
    """The tests of a run over tasks: Friedman, average ranks, Nemenyi's CD, the Wilcoxon-Holm groups and pairs."""
    table = _table(rows)
    result = stats.friedman(table)
    lines = [f"Unit: the task (the mean over its seeds). {repeated_text(rows)}".rstrip(), ""]
    if result is None:
        return lines + ["The tests need at least three detectors that completed at least two common tasks."]
    few = too_few_tasks(result.k, result.n_tasks, alpha)
    pairs = stats.pairwise_wilcoxon(table)
    groups = stats.cliques(result.mean_ranks, pairs.significant(alpha))
    f_text = "infinite (every task ranks the detectors alike)" if np.isinf(result.f) else f"{result.f:.2f}"
    if result.min_pvalue > alpha:  # its p-value would say nothing: the reason instead (below)
        test = "no p-value, as no ranking of so few tasks can reach alpha (below)"
    else:
        verdict = "the detectors differ" if result.pvalue <= alpha else "no difference shown"
        test = (f"exact {p_is(result.pvalue)} (each task's ranking permuted at random "
                f"{stats.RANDOM_RANKINGS:,} times): {verdict} at alpha = {alpha}")
    lines += [
        f"Over the {result.n_tasks} tasks that all {result.k} detectors completed: Friedman chi2 = "
        f"{result.statistic:.2f} (Iman-Davenport F = {f_text}), {test}. Nemenyi's critical difference "
        f"of average ranks: {stats.nemenyi_cd(result.k, result.n_tasks, alpha):.2f}.",
        "",
    ]
    if few:
        lines += [*few, ""]
    lines += [
        "Average rank over these tasks (1 = best) and the groups of detectors adjacent in rank among which "
        f"no pair differs (exact Wilcoxon signed-rank over tasks, Holm-corrected over all pairs, alpha = "
        f"{alpha}); the critical-difference diagram (plots/critical-difference.png) draws them as bars.",
        "",
    ]
    by_rank = np.argsort(result.mean_ranks, kind="stable")
    lines.append(format_table(["detector", "average rank", "groups"], [
        [table.detectors[i], f"{result.mean_ranks[i]:.2f}",
         " ".join(chr(ord("A") + g) for g, members in enumerate(groups) if i in members) or "-"]
        for i in by_rank]))
    if _pairs_cannot_reach(table, alpha):
        lines += ["", "The pairwise p-values are not shown: with so few tasks none can reach alpha (above)."]
        return lines + _bayes_note()
    lines += ["", "Pairwise exact Wilcoxon signed-rank tests over the tasks both detectors completed, "
              "Holm-adjusted p-values (row vs column; * at or below alpha):", ""]
    order = table.detectors
    short = [str(i + 1) for i in range(len(order))]
    body = [[f"{short[i]} {order[i]}", *(
        "" if j >= i else p_value(pairs.adjusted[i, j]) + ("*" if pairs.significant(alpha)[i, j] else "")
        for j in range(len(order) - 1))] for i in range(len(order))]
    lines.append(format_table(["detector", *short[:-1]], body))
    return lines + _bayes_note()


def _bayes_note() -> list[str]:
    return ["", "The Bayesian signed-rank test (Benavoli et al. 2017) of each detector against the reference "
            "is in the paired comparison: P(worse, equivalent, better), equivalent meaning within a region "
            f"of practical equivalence of ± {ROPE} ROC AUC; it states probabilities, not significance, and "
            f"is shown from {MIN_TASKS_BAYES} tasks on."]
