"""The statistics of a run over tasks, on a hand-made results table (tests.bench.hand_rows)."""

from novelty.bench.reports.statistics import paired_text, seeds_text, statistics_markdown, task_ranks_text


def test_the_paired_table_over_tasks_in_rank_order(rows):
    lines = paired_text(rows, "ref").splitlines()
    assert "ΔROC AUC vs ref (mean ± se)" in lines[0] and "| tasks |" in lines[0]
    cells = [[c.strip() for c in line.strip("|").split("|")] for line in lines[2:]]
    # b - ref per task: +0.05, +0.075; a - ref: +0.05, -0.25. Two tasks: no p-value can reach 0.05,
    # so none is shown; the Bayesian probabilities are
    assert [c[:7] for c in cells] == [
        ["b", "2", "+0.062 ± 0.012", "2", "0", "0", "-"],
        ["ref", "2", "(reference)", "-", "-", "-", "-"],
        ["a", "2", "-0.100 ± 0.150", "1", "0", "1", "-"],
    ]
    assert cells[0][7] == "-"   # the Bayesian test from five tasks on


def test_with_two_tasks_the_statistics_say_why_there_is_no_claim(rows):
    text = "\n".join(statistics_markdown(rows))
    assert text.startswith("Unit: the task (the mean over its seeds).")
    assert "Over the 2 tasks that all 3 detectors completed" in text
    assert "no p-value, as no ranking of so few tasks can reach alpha" in text and "p =" not in text
    assert "With 2 tasks no pair of detectors can differ significantly" in text
    assert "2 / 2^2 = 0.5" in text and "(k!)^(1 - N) = 0.167" in text
    assert "The pairwise p-values are not shown" in text


def test_seeds_per_task_with_their_interval_or_one_value(rows):
    rows = [r for r in rows if r["detector"] == "b"]
    for r in rows:
        if r["task"] == "t2":
            r["roc_auc"] = 0.7
    text = seeds_text(rows)
    # the Student-t interval 0.800 ± 0.635 (two seeds, t = 12.7) truncated to [0, 1], where ROC AUC lies
    assert "| b        | 0.800 [0.165, 1.000] | 0.700 (1 value, 2 seeds) |" in text


def test_ranks_per_task_average_over_tasks(rows):
    # t1 means: ref 0.75, a 0.80, b 0.80 -> 3, 1.5, 1.5; t2: ref 0.75, a 0.50, b 0.825 -> 2, 3, 1
    text = task_ranks_text(rows)
    assert "| b        | 1.5 | 1.0 | 1.25         |" in text
    assert "| ref      | 3.0 | 2.0 | 2.50         |" in text
