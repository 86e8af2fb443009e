"""The summary.md of a run: its sections in order and how the run was made (tests.bench.hand_rows)."""

from novelty.bench.holdout.summary import summary_sections
from novelty.bench.reports.summary import summary_markdown


def test_the_summary_puts_the_protocols_sections_first_then_the_paired_comparison(rows):
    text = summary_markdown(rows, reference="ref", sections=summary_sections(rows))
    assert text.index("## Ranking") < text.index("## Paired comparison with ref") < text.index(
        "## ROC AUC per task")
    assert "The reference is the given `reference`." in text
    assert "12 cells: 3 detectors x 2 tasks x 2 seeds (0, 1); 1 failed." in text
    assert "## Paired comparison with a" in summary_markdown(rows)      # the first label, b ranks first


def test_the_sections_in_order_each_from_its_module(rows):
    from novelty.bench.reports.statistics import statistics_markdown, task_ranks_text

    text = summary_markdown(rows, reference="ref")
    assert text.index("## Paired comparison") < text.index("## Ranks per task") < text.index("## Statistics")
    section = text[text.index("## Ranks per task"):text.index("## Statistics")]
    assert task_ranks_text(rows) in section
    assert "\n".join(statistics_markdown(rows)) in text[text.index("## Statistics"):]


def test_the_summary_records_how_the_run_was_made(rows):
    for r in rows:
        r.update(versions="{}", git_revision="abc123")
    run = {"command": "novelty bench --quick", "versions": '{"numpy": "2.0", "python": "3.11.7"}',
           "git_revision": "def456+dirty"}
    text = summary_markdown(rows, run=run)
    assert text.endswith("## How this run was made\n\n- command: `novelty bench --quick`\n"
                         "- versions: numpy 2.0, python 3.11.7\n- revision: def456+dirty\n"
                         "- cells from earlier runs were computed at revision abc123\n")


def test_one_task_and_one_seed_are_counted_in_the_singular(rows):
    one = [r for r in rows if r["task"] == rows[0]["task"] and r["seed"] == rows[0]["seed"]]
    first = summary_markdown(one).splitlines()[2]
    assert first.startswith(f"{len(one)} cells: 3 detectors x 1 task x 1 seed ({rows[0]['seed']}); "), first
