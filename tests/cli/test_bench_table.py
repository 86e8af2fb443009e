"""What ``novelty bench`` prints of a hold-out run: a table of words, a verdict, where the rest is."""

import re
from pathlib import Path

from novelty.bench import load_suite, quick_suite_path
from novelty.cli import _bench_table as shown

README = Path(__file__).resolve().parents[2] / "README.md"


def cell(detector, task, seed, auc, **metrics):
    return {"cell_id": f"{detector}-{task}-{seed}", "detector": detector, "task": task, "seed": seed,
            "status": "ok" if auc is not None else "error", "roc_auc": auc, **metrics}


def table_rows(text):
    return [[c.strip() for c in line.strip("|").split("|")] for line in text.splitlines()[2:]]


def test_the_table_has_four_columns_in_words_ranked_by_roc_auc():
    metrics = dict(tpr_at_5pct_fpr=0.25, false_alarms=2, train_time_s=0.5, route=True)
    rows = [cell("hsom", "t", 0, 0.6, **metrics), cell("hsom", "t", 1, 0.8, **metrics),
            cell("parzen", "t", 0, 0.9, **{**metrics, "tpr_at_5pct_fpr": 0.5}), cell("parzen", "t", 1, 0.9, **metrics)]
    text = shown.first_table(rows)
    assert [h.strip() for h in text.splitlines()[0].split("|")[1:-1]] == [
        "#", "detector", "ROC AUC (± sd over seeds)", "caught at 5% false alarms", "false alarms, clean pass",
        "learning (s)"]
    # parzen: 0.9 on both seeds; hsom: the mean 0.7 and the sd of 0.6 and 0.8 over its seeds
    assert table_rows(text) == [["1", "parzen", "0.900 ± 0.000", "38%", "2.0", "0.50"],
                                ["2", "hsom", "0.700 ± 0.141", "25%", "2.0", "0.50"]]
    assert shown.columns_in_words(rows).startswith("ROC AUC: how often a novel test scan scores above")


def test_tasks_without_a_route_have_no_false_alarm_column_and_a_failed_cell_is_counted():
    rows = [cell("lof", "table", 0, 0.7, tpr_at_5pct_fpr=0.1, train_time_s=0.1, route=False),
            cell("lof", "table", 1, None, route=False)]
    text = shown.first_table(rows)
    assert "clean pass" not in text and "False alarms" not in shown.columns_in_words(rows)
    assert text.splitlines()[0].rstrip(" |").endswith("failed cells")
    assert table_rows(text)[0][-1] == "1 of 2"


def test_the_verdict_names_the_first_the_papers_detector_and_what_may_be_claimed():
    rows = [cell(d, t, s, auc) for t in ("t1", "t2") for s in (0, 1)
            for d, auc in (("a", 0.9), ("hsom", 0.6), ("b", 0.8))]
    line = shown.verdict(rows)
    assert line.startswith("Verdict: a ranks first (ROC AUC 0.900); the paper's hsom ranks 3rd of 3 (0.600). ")
    assert line.endswith("No significance claim: with 2 tasks and 3 detectors no test can reach alpha = 0.05 "
                         "(see summary.md, Statistics).")
    assert "\n" not in line
    alone = [r for r in rows if r["detector"] == "hsom"]
    assert shown.verdict(alone).startswith("Verdict: hsom ranks first (ROC AUC 0.600). No Friedman test")


def test_the_verdict_names_where_the_guides_answer_for_frozen_detection_ranks():
    # the quick suite's two tasks may rank another first: the verdict tells the reader where the answer
    # of "Which detector?" stands, so that the terminal and the guides tell one story
    rows = [cell(d, t, s, auc) for t in ("t1", "t2") for s in (0, 1)
            for d, auc in (("som-distance", 0.9), ("hsom", 0.6), ("kmeans-stanley", 0.8))]
    assert shown.verdict(rows).startswith(
        'Verdict: som-distance ranks first (ROC AUC 0.900); kmeans-stanley, the answer of "Which detector?" to '
        "learning a clean area and flagging what differs (measured on the whole detection suite), ranks 2nd "
        "(0.800); the paper's hsom ranks 3rd of 3 (0.600). ")


def test_the_quick_suite_has_the_readmes_recommendations_beside_the_papers_detector():
    section = README.read_text(encoding="utf-8").split("## Which detector?", 1)[1]
    table = [row for row in section[section.index("| you want"):].split("\n\n", 1)[0].splitlines()[2:]
             if row.startswith("| ")]
    uses = {row.split("|")[1].strip(): re.search(r"`([\w-]+)`", row.split("|")[2]).group(1) for row in table}
    wanted = {name for question, name in uses.items()
              if question.startswith(("to learn a clean area", "a robot that keeps learning", "the paper's exact"))}
    assert len(wanted) == 3 and shown.PAPERS_DETECTOR in wanted, uses
    assert wanted <= {d.label for d in load_suite(quick_suite_path()).detectors}
