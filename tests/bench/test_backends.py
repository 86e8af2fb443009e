"""Every failure inside a cell -- an exception, a dead worker, a timeout, non-finite
scores -- is a recorded failed cell, and the run goes on, on every backend."""

import pytest

import faulty
import novelty
from novelty import bench
from novelty.bench import DetectorSpec, Suite, TaskSpec
from novelty.bench.results import read_rows
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


@pytest.mark.slow
def test_a_worker_that_dies_fails_its_cell_only(tmp_path, faulty_registered):
    suite = toy_suite(faulty_registered, "hsom", faulty.CRASH)
    report = run_bench(suite, tmp_path, backend="joblib", jobs=2, quiet=True, plots=False)
    rows = by_detector(report)
    assert report.ran == 2 and report.failed == 1
    assert rows["hsom", 0]["status"] == "ok"  # it ran beside the crash, then alone
    assert rows[faulty.CRASH, 0]["status"] == "error"
    assert "worker process died" in rows[faulty.CRASH, 0]["error"]


@pytest.mark.slow
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


# ------------------------------------------------ no code from the working directory
LAUNCH = """
import sys
sys.path[:0] = [{repo!r}, {bench_tests!r}]
import novelty, toy
from novelty import bench
from novelty.bench import DetectorSpec, Suite, TaskSpec
from novelty.bench.results import read_rows
from novelty.bench.runner import run_bench
from novelty.datasets import registry


def main():
    registry.register(toy.TASK, toy.toy_task, replace=True)
    for backend, timeout in (("joblib", None), ("serial", 60), ("dask", None)):
        if backend == "dask":
            try:
                import distributed  # noqa: F401
            except ImportError:
                continue
        suite = Suite([DetectorSpec("hsom", {{"n_rows": 2, "n_columns": 2}})], [TaskSpec(toy.TASK)],
                      seeds=[0, 1], memory=False, cell_timeout=timeout).check()
        report = run_bench(suite, backend, backend=backend, jobs=2, quiet=True, plots=False)
        assert report.failed == 0, report.rows
        print(backend, "ran", report.ran)


if __name__ == "__main__":  # spawned children import this file again
    main()
"""


@pytest.mark.slow
def test_no_worker_imports_modules_planted_in_the_working_directory(tmp_path):
    # a launcher outside the working directory, as the installed 'novelty' script is
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(novelty.__file__).resolve().parents[1]
    launcher = tmp_path / "launcher" / "launch.py"
    launcher.parent.mkdir()
    launcher.write_text(LAUNCH.format(repo=str(repo), bench_tests=str(Path(__file__).parent)))
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    for name in ("numpy", "joblib", "multiprocessing"):
        (cwd / f"{name}.py").write_text(f"open({str(tmp_path / ('MARKER-' + name))!r}, 'w').close()\n")
    proc = subprocess.run([sys.executable, str(launcher)], cwd=cwd, capture_output=True, text=True,
                          timeout=600, env={k: v for k, v in __import__("os").environ.items()
                                            if k != "PYTHONSAFEPATH"})
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "joblib ran 2" in proc.stdout and "serial ran 2" in proc.stdout
    assert sorted(p.name for p in tmp_path.glob("MARKER-*")) == []


@pytest.mark.slow
def test_a_keyboard_interrupt_raised_in_a_worker_is_a_failed_cell_and_rerun_on_resume(tmp_path, faulty_registered):
    suite = toy_suite(faulty_registered, faulty.INTERRUPT, "hsom")
    report = run_bench(suite, tmp_path, backend="joblib", jobs=2, quiet=True, plots=False)
    rows = by_detector(report)
    assert rows[faulty.INTERRUPT, 0]["error"] == "KeyboardInterrupt: raised inside the cell's worker"
    assert rows["hsom", 0]["status"] == "ok"
    again = run_bench(suite, tmp_path, backend="joblib", jobs=2, quiet=True, plots=False)
    assert again.ran == 1 and again.failed == 1  # the failed cell runs again, the ok one does not


def test_a_keyboard_interrupt_in_the_bench_process_still_stops_the_bench(tmp_path, faulty_registered):
    # serial cells run in the bench's own process: there the interrupt is the user's
    report = run_bench(toy_suite(faulty_registered, faulty.INTERRUPT, "hsom"), tmp_path, quiet=True, plots=False)
    assert report.interrupted and report.rows == []  # stopped at the first cell, which is not recorded


def test_an_interrupted_run_in_python_raises_after_keeping_the_finished_cells(tmp_path, faulty_registered):
    detectors = ["hsom n_rows=3 n_columns=3", f"{faulty.INTERRUPT} n_rows=3 n_columns=3"]
    with pytest.raises(KeyboardInterrupt, match=r"interrupted after 1 cells \(their rows are in .*resume\)"):
        bench.run(detectors, faulty_registered.TASK, out=tmp_path, plots=False)
    assert [r["detector_name"] for r in read_rows(tmp_path / "results.jsonl")] == ["hsom"]
    with pytest.raises(KeyboardInterrupt, match=r"after 0 cells \(give out= to keep"):
        bench.run(detectors[::-1], faulty_registered.TASK, plots=False)
