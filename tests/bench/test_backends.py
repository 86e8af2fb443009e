"""Every failure inside a cell -- an exception, a dead worker, a timeout, non-finite
scores -- is a recorded failed cell, and the run goes on, on every backend."""

import pytest

import faulty
import novelty
from novelty.bench import DetectorSpec, Suite, TaskSpec
from novelty.bench.runner import run_bench


@pytest.fixture
def faulty_registered(toy_registered):
    for name, factory in faulty.FACTORIES.items():
        novelty.register_detector(name, factory, replace=True)
    yield toy_registered
    for name in faulty.FACTORIES:
        novelty.registry.detectors.unregister(name)


def toy_suite(toy, *detectors, seeds=(0,), timeout=None):
    return Suite([DetectorSpec(d, {"n_rows": 3, "n_columns": 3}) for d in detectors],
                 [TaskSpec(toy.TASK)], seeds=list(seeds), memory=False, cell_timeout=timeout).check()


def by_detector(report):
    return {(r["detector"], r["seed"]): r for r in report.rows}


def test_a_worker_that_dies_fails_its_cell_only(tmp_path, faulty_registered):
    suite = toy_suite(faulty_registered, "hsom", faulty.CRASH)
    report = run_bench(suite, tmp_path, backend="joblib", jobs=2, quiet=True, plots=False)
    rows = by_detector(report)
    assert report.ran == 2 and report.failed == 1
    assert rows["hsom", 0]["status"] == "ok"  # it ran beside the crash, then alone
    assert rows[faulty.CRASH, 0]["status"] == "error"
    assert "worker process died" in rows[faulty.CRASH, 0]["error"]


def test_a_cell_past_its_timeout_fails_and_the_run_goes_on(tmp_path, faulty_registered):
    """Serial cells under a timeout run in a worker process, with the numbers of this one."""
    from test_runner import metric_table

    suite = toy_suite(faulty_registered, faulty.HANG, "hsom", timeout=8)
    report = run_bench(suite, tmp_path, quiet=True, plots=False)
    rows = by_detector(report)
    assert rows[faulty.HANG, 0]["error"] == "TimeoutError: the cell ran longer than its timeout of 8 s"
    plain = run_bench(toy_suite(faulty_registered, "hsom"), tmp_path / "plain", quiet=True, plots=False)
    assert metric_table([rows["hsom", 0]]) == metric_table(plain.rows)


def test_sys_exit_in_a_cell_is_a_failed_cell_in_serial(tmp_path, faulty_registered):
    report = run_bench(toy_suite(faulty_registered, faulty.EXIT, "hsom"), tmp_path, quiet=True,
                       plots=False)
    rows = by_detector(report)
    assert rows[faulty.EXIT, 0]["status"] == "error" and rows["hsom", 0]["status"] == "ok"
    assert rows[faulty.EXIT, 0]["error"].startswith("SystemExit: 4")
    assert (tmp_path / "summary.md").exists()


def test_non_finite_scores_fail_the_cell(tmp_path, faulty_registered):
    report = run_bench(toy_suite(faulty_registered, faulty.NAN, seeds=(0, 1)), tmp_path, quiet=True,
                       plots=False)
    rows = by_detector(report)
    assert rows[faulty.NAN, 0]["status"] == "ok"
    assert rows[faulty.NAN, 1]["status"] == "error"
    assert rows[faulty.NAN, 1]["error"] == ("CellError: the detector scored 1 of 30 test scans "
                                            "NaN or infinite")
    summary = (tmp_path / "summary.md").read_text()
    assert "Failed cells" in summary and faulty.NAN in summary.split("Failed cells")[1]
