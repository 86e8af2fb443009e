"""The statistics of a run on a hand-made results table (tests.bench.hand_rows)."""

from novelty.bench.reports.statistics import paired_text, statistics_markdown, task_ranks_text


def test_the_paired_table_in_rank_order(rows):
    lines = paired_text(rows, "ref").splitlines()
    assert "ΔROC AUC vs ref (mean ± se)" in lines[0]
    cells = [[c.strip() for c in line.strip("|").split("|")] for line in lines[2:]]
    # b - ref: 4 of 4 positive, exact p = 2 / 2^4, times 3 pairs (Holm, the smallest p);
    # a - ref: +0.1, 0, -0.1, the zero's rank split, R+ = R- = 3: p = 1
    assert cells == [
        ["b", "4", "+0.062 ± 0.013", "4", "0", "0", "0.375"],
        ["ref", "4", "(reference)", "-", "-", "-", "-"],
        ["a", "3", "+0.000 ± 0.058", "1", "1", "1", "1.000"],
    ]


def test_the_statistics_section_by_hand(rows):
    # complete cells t1/0, t1/1, t2/0; ranks (ref, a, b): (3, 1, 2), (2.5, 2.5, 1), (2, 3, 1)
    text = "\n".join(statistics_markdown(rows))
    assert text.startswith("Over the 3 cells (task, seed) that all 3 detectors completed: Friedman chi2 = ")
    assert "| b        | 1.33         | A      |" in text
    assert "| a        | 2.17         | A      |" in text
    assert "| ref      | 2.50         | A      |" in text
    assert "2 / 2^3 = 0.25; after Holm's correction over 3 pairs no pair can reach alpha = 0.05" in text


def test_ranks_per_task_average_over_tasks(rows):
    # t1 means: ref 0.75, a 0.80, b 0.80 -> 3, 1.5, 1.5; t2: ref 0.75, a 0.50, b 0.825 -> 2, 3, 1
    text = task_ranks_text(rows)
    assert "| b        | 1.5 | 1.0 | 1.25         |" in text
    assert "| ref      | 3.0 | 2.0 | 2.50         |" in text
