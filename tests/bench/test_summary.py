"""The summary of a run: the ranked table and the paired comparison, on a hand-made results table."""

import math

import pytest

from novelty.bench import stats
from novelty.bench.summary import paired_text, reference_of, summary_markdown

#: ROC AUC by detector, task and seed; None: the cell failed
AUC = {
    "ref": {("t1", 0): 0.80, ("t1", 1): 0.70, ("t2", 0): 0.60, ("t2", 1): 0.90},
    "a": {("t1", 0): 0.90, ("t1", 1): 0.70, ("t2", 0): 0.50, ("t2", 1): None},
    "b": {("t1", 0): 0.85, ("t1", 1): 0.75, ("t2", 0): 0.70, ("t2", 1): 0.95},
}


def rows_of(table):
    rows = []
    for detector, cells in table.items():
        for (task, seed), auc in cells.items():
            status = "ok" if auc is not None else "error"
            rows.append({"cell_id": f"{detector}-{task}-{seed}", "detector": detector, "task": task,
                         "seed": seed, "status": status, "roc_auc": auc,
                         "error": "" if auc is not None else "RuntimeError: boom"})
    return rows


@pytest.fixture
def rows():
    return rows_of(AUC)


def test_the_cell_table_holds_nan_for_a_failed_cell(rows):
    table = stats.cell_table(rows)
    assert table.detectors == ["ref", "a", "b"]
    assert table.cells == [("t1", 0), ("t1", 1), ("t2", 0), ("t2", 1)]
    assert table.row("b").tolist() == [0.85, 0.75, 0.70, 0.95]
    assert math.isnan(table.row("a")[3])
    assert table.complete().cells == [("t1", 0), ("t1", 1), ("t2", 0)]


def test_paired_differences_by_hand(rows):
    records = {r["detector"]: r for r in stats.paired_comparison(stats.cell_table(rows), "ref")}
    # a - ref on the three shared cells: +0.10, 0.00, -0.10 -> mean 0, sd 0.1, se 0.1 / sqrt(3)
    a = records["a"]
    assert a["n"] == 3 and (a["wins"], a["ties"], a["losses"]) == (1, 1, 1)
    assert a["mean_diff"] == pytest.approx(0.0, abs=1e-12)
    assert a["se"] == pytest.approx(0.1 / math.sqrt(3))
    # b - ref: +0.05, +0.05, +0.10, +0.05 -> mean 0.0625, sd 0.025, se 0.0125
    b = records["b"]
    assert b["n"] == 4 and (b["wins"], b["ties"], b["losses"]) == (4, 0, 0)
    assert b["mean_diff"] == pytest.approx(0.0625)
    assert b["se"] == pytest.approx(0.0125)
    ref = records["ref"]
    assert (ref["n"], ref["mean_diff"], ref["ties"]) == (4, 0.0, 4)


def test_a_single_shared_cell_has_no_standard_error():
    rows = rows_of({"ref": {("t", 0): 0.5}, "a": {("t", 0): 0.75}})
    (_, a) = stats.paired_comparison(stats.cell_table(rows), "ref")
    assert a["mean_diff"] == 0.25 and math.isnan(a["se"]) and a["wins"] == 1


def test_an_unknown_reference_names_the_detectors(rows):
    with pytest.raises(ValueError, match="'parzen' is not in this run; expected one of ref, a, b"):
        stats.paired_comparison(stats.cell_table(rows), "parzen")


def test_the_default_reference_is_the_detector_ranked_first(rows):
    # mean over seeds of the task mean: b 0.8125, ref 0.75, a 0.70
    assert reference_of(rows) == "b"
    assert reference_of(rows, "ref") == "ref"
    assert reference_of([]) is None


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


def test_the_summary_puts_the_ranking_first_then_the_paired_comparison(rows):
    text = summary_markdown(rows, reference="ref")
    assert text.index("## Ranking") < text.index("## Paired comparison with ref") < text.index(
        "## ROC AUC per task")
    assert "The reference is the suite's `reference`." in text
    assert "12 cells: 3 detectors x 2 tasks x 2 seeds (0, 1); 1 failed." in text
    assert "## Paired comparison with b" in summary_markdown(rows)


def test_the_statistics_section_by_hand(rows):
    # complete cells t1/0, t1/1, t2/0; ranks (ref, a, b): (3, 1, 2), (2.5, 2.5, 1), (2, 3, 1)
    text = summary_markdown(rows, reference="ref")
    assert text.index("## Paired comparison") < text.index("## Ranks per task") < text.index("## Statistics")
    assert "Over the 3 cells (task, seed) that all 3 detectors completed: Friedman chi2 = " in text
    assert "| b        | 1.33         | A      |" in text
    assert "| a        | 2.17         | A      |" in text
    assert "| ref      | 2.50         | A      |" in text
    assert "2 / 2^3 = 0.25; after Holm's correction over 3 pairs no pair can reach alpha = 0.05" in text


def test_ranks_per_task_average_over_tasks(rows):
    # t1 means: ref 0.75, a 0.80, b 0.80 -> 3, 1.5, 1.5; t2: ref 0.75, a 0.50, b 0.825 -> 2, 3, 1
    text = summary_markdown(rows)
    section = text[text.index("## Ranks per task"):text.index("## Statistics")]
    assert "| b        | 1.5 | 1.0 | 1.25         |" in section
    assert "| ref      | 3.0 | 2.0 | 2.50         |" in section


def test_the_summary_records_how_the_run_was_made(rows):
    for r in rows:
        r.update(versions="{}", git_revision="abc123")
    run = {"command": "novelty bench --quick", "versions": '{"numpy": "2.0", "python": "3.11.7"}',
           "git_revision": "def456+dirty"}
    text = summary_markdown(rows, run=run)
    assert text.endswith("## How this run was made\n\n- command: `novelty bench --quick`\n"
                         "- versions: numpy 2.0, python 3.11.7\n- revision: def456+dirty\n"
                         "- cells from earlier runs were computed at revision abc123\n")
