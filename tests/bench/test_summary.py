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
    assert cells == [
        ["b", "4", "+0.062 ± 0.013", "4", "0", "0"],
        ["ref", "4", "(reference)", "-", "-", "-"],
        ["a", "3", "+0.000 ± 0.058", "1", "1", "1"],
    ]


def test_the_summary_puts_the_ranking_first_then_the_paired_comparison(rows):
    text = summary_markdown(rows, reference="ref")
    assert text.index("## Ranking") < text.index("## Paired comparison with ref") < text.index(
        "## ROC AUC per task")
    assert "The reference is the suite's `reference`." in text
    assert "12 cells: 3 detectors x 2 tasks x 2 seeds (0, 1); 1 failed." in text
    assert "## Paired comparison with b" in summary_markdown(rows)
