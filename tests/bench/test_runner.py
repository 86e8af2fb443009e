"""Whole runs on the toy task: outputs, resume, failures, and every backend agreeing."""

import json

import numpy as np
import pytest

from novelty.bench import DetectorSpec, Suite, TaskSpec
from novelty.bench.cell import run_cell
from novelty.bench.holdout.evaluate import METRIC_COLUMNS
from novelty.bench.runner import run_bench

KEY = ("detector", "task", "seed")


@pytest.fixture
def suite(toy_registered):
    return Suite(
        [DetectorSpec("hsom", {"n_rows": 4, "n_columns": 4}, "hsom-4x4"),
         DetectorSpec("habituating", {"clusterer": "gwr"}, "gwr-stanley")],
        [TaskSpec(toy_registered.TASK)],
        seeds=[0, 1],
        name="toy",
    ).check()


def metric_table(rows):
    """The deterministic part of every row, keyed by (detector, task, seed)."""
    return {tuple(r[k] for k in KEY): {c: r.get(c) for c in ["status", *METRIC_COLUMNS]} for r in rows}


def test_a_run_writes_every_output(tmp_path, suite):
    report = run_bench(suite, tmp_path, quiet=True)
    assert report.ran == 4 and report.failed == 0
    names = {p.name for p in (tmp_path).iterdir()}
    assert {"results.csv", "results.jsonl", "summary.md", "cells"} <= names
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        assert report.notes == ["Plots skipped: matplotlib is not installed (pip install 'novelty-habituation[plot]')."]
    else:
        assert {p.name for p in (tmp_path / "plots").iterdir()} == {
            "roc.png", "ranking.png", "boxplot-roc-auc.png", f"route-{suite.tasks[0].name}.png"}
    rows = [json.loads(line) for line in (tmp_path / "results.jsonl").read_text().splitlines()]
    assert len(rows) == 4
    header = (tmp_path / "results.csv").read_text().splitlines()[0].split(",")
    for column in ("detector", "task", "seed", "roc_auc", "average_precision", "params", "versions",
                   "git_revision", "detection_delay", "integrated_novelty", "peak_memory_mb", "n_units"):
        assert column in header
    row = next(r for r in rows if r["detector"] == "hsom-4x4" and r["seed"] == 0)
    assert row["status"] == "ok" and row["n_units"] == 16 and row["train_passes"] == 2
    assert row["resting_novelty"] == pytest.approx(0.0476, abs=1e-4)
    assert json.loads(row["params"]) == {"n_columns": 4, "n_rows": 4}
    assert "numpy" in json.loads(row["versions"])
    summary = (tmp_path / "summary.md").read_text()
    assert "## Ranking" in summary and "hsom-4x4" in summary


def test_a_cell_trains_as_the_robot_then_scores_without_learning(toy_registered):
    import novelty

    cell = Suite([DetectorSpec("hsom")], [TaskSpec(toy_registered.TASK)], seeds=[3]).check().cells()[0]
    row, arrays = run_cell(cell)
    data = toy_registered.toy_task(seed=3)
    det = novelty.make("hsom", random_state=3)
    for _ in range(2):  # train_passes of the toy task
        det.partial_fit(data.train().X)
    expected = det.novelty(data.test().X)
    np.testing.assert_array_equal(arrays["novelty"], expected)
    assert row["threshold"] == det.novelty(data.train().X).max()
    assert row["max_novelty"] == expected.max()
    assert row["integrated_novelty"] == pytest.approx(np.sum(expected - det.resting_novelty))


@pytest.mark.parametrize("clean, source, n_scans", [
    ("none", "normal test scans", 24), ("runs", "clean test runs", 10), ("metadata", "clean pass", 10)])
def test_false_alarms_on_a_clean_pass(toy_registered, clean, source, n_scans):
    cell = Suite([DetectorSpec("hsom")], [TaskSpec(toy_registered.TASK, {"clean": clean})]).check().cells()[0]
    row, _ = run_cell(cell)
    assert row["status"] == "ok", row["error"]
    assert row["false_alarm_source"] == source
    assert row["false_alarm_rate"] * n_scans == pytest.approx(row["false_alarms"])


def test_a_failing_cell_is_recorded_and_the_run_goes_on(tmp_path, toy_registered):
    suite = Suite([DetectorSpec("hsom"), DetectorSpec(toy_registered.BROKEN)],
                  [TaskSpec(toy_registered.TASK)], seeds=[0]).check()
    report = run_bench(suite, tmp_path, quiet=True, plots=False)
    by_detector = {r["detector"]: r for r in report.rows}
    assert by_detector["hsom"]["status"] == "ok"
    broken = by_detector[toy_registered.BROKEN]
    assert broken["status"] == "error"
    assert broken["error"].startswith("FloatingPointError: this detector always fails")
    assert "Failed cells" in (tmp_path / "summary.md").read_text()


def test_a_rerun_resumes(tmp_path, suite):
    first = run_bench(suite, tmp_path, quiet=True, plots=False)
    assert (first.ran, first.skipped) == (4, 0)
    # interrupted run: drop one finished cell and tear the last line
    lines = (tmp_path / "results.jsonl").read_text().splitlines()
    (tmp_path / "results.jsonl").write_text("\n".join(lines[:3]) + "\n" + lines[3][:40])
    second = run_bench(suite, tmp_path, quiet=True, plots=False)
    assert (second.ran, second.skipped) == (1, 3)
    assert metric_table(second.rows) == metric_table(first.rows)
    third = run_bench(suite, tmp_path, quiet=True, plots=False)
    assert (third.ran, third.skipped) == (0, 4)


def test_failed_cells_are_run_again_on_resume(tmp_path, toy_registered):
    suite = Suite([DetectorSpec("hsom")], [TaskSpec(toy_registered.TASK, {"fail": True})], seeds=[0]).check()
    assert run_bench(suite, tmp_path, quiet=True, plots=False).failed == 1
    again = run_bench(suite, tmp_path, quiet=True, plots=False)
    assert again.ran == 1 and again.rows[0]["error"].startswith("RuntimeError: the toy task was asked to fail")


def results_csv_apart_from_machine_columns(folder):
    """results.csv's bytes with the columns that measure the machine blanked (the header kept)."""
    import csv
    import io

    from novelty.bench.results import MACHINE_COLUMNS

    text = (folder / "results.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(text)))
    blank = [j for j, name in enumerate(rows[0]) if name in MACHINE_COLUMNS]
    assert blank, "the timing columns are in the file"
    return [rows[0]] + [[("" if j in blank else c) for j, c in enumerate(r)] for r in rows[1:]]


def test_joblib_gives_the_serial_numbers(tmp_path, suite):
    serial = run_bench(suite, tmp_path / "serial", quiet=True, plots=False)
    parallel = run_bench(suite, tmp_path / "joblib", backend="joblib", jobs=2, quiet=True, plots=False)
    assert metric_table(parallel.rows) == metric_table(serial.rows)
    assert all(r["status"] == "ok" for r in parallel.rows)
    # the same file, row for row and byte for byte, apart from times, speeds, memory and the clock
    assert results_csv_apart_from_machine_columns(tmp_path / "joblib") == \
        results_csv_apart_from_machine_columns(tmp_path / "serial")


def test_results_csv_rows_are_in_canonical_order_whatever_order_cells_finish(tmp_path, suite):
    from novelty.bench.results import ResultsStore, canonical_order

    run_bench(suite, tmp_path, quiet=True, plots=False)
    store = ResultsStore(tmp_path)
    rows = store.rows()
    before = (tmp_path / "results.csv").read_bytes()
    store.write_csv(list(reversed(rows)))
    assert (tmp_path / "results.csv").read_bytes() == before
    assert [(r["detector"], r["seed"]) for r in canonical_order(rows)] == [
        ("gwr-stanley", 0), ("gwr-stanley", 1), ("hsom-4x4", 0), ("hsom-4x4", 1)]


@pytest.mark.slow
def test_dask_local_cluster_gives_the_serial_numbers(tmp_path, suite):
    distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")
    serial = run_bench(suite, tmp_path / "serial", quiet=True, plots=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        report = run_bench(suite, tmp_path / "dask", backend="dask", scheduler=cluster.scheduler_address,
                           quiet=True, plots=False)
    assert metric_table(report.rows) == metric_table(serial.rows)
    assert all(r["status"] == "ok" for r in report.rows)
    assert results_csv_apart_from_machine_columns(tmp_path / "dask") == \
        results_csv_apart_from_machine_columns(tmp_path / "serial")


def test_progress_lines_when_not_a_terminal(tmp_path, suite, capsys):
    import io

    stream = io.StringIO()
    run_bench(suite, tmp_path, plots=False, progress=stream)
    lines = stream.getvalue().splitlines()
    assert len(lines) == 4 and lines[0].startswith("[1/4] ") and "AUC" in lines[0]


def test_progress_bar_on_a_terminal_and_lines_in_ci(monkeypatch):
    import io

    from novelty.bench.progress import Progress, use_bar

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    row = {"detector": "d", "task": "t", "seed": 0, "status": "ok", "roc_auc": 0.9}
    monkeypatch.delenv("CI", raising=False)
    assert use_bar(Terminal()) and not use_bar(io.StringIO())
    monkeypatch.setenv("CI", "true")
    assert not use_bar(Terminal())
    stream = Terminal()
    with Progress(2, stream=stream, bar=True) as bar:
        bar.update(row)
        bar.update({**row, "status": "error", "error": "ValueError: x"})
    text = stream.getvalue()
    assert "2/2" in text and "FAILED ValueError: x" in text
