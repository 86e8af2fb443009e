"""The output folder: provenance of a run, one run at a time, and files that are whole whenever read."""

import json
import os
import re
import stat

import pytest

from novelty.bench import DetectorSpec, Suite, TaskSpec, results
from novelty.bench.results import OutputBusyError, ResultsStore
from novelty.bench.runner import run_bench


def test_a_checkout_reports_its_commit():
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?", results.git_revision())


def test_an_installed_package_reports_the_revision_its_build_recorded(tmp_path, monkeypatch):
    package = tmp_path / "novelty"
    package.mkdir()
    (package / results.BUILD_REVISION_FILE).write_text("0123abcd\n")
    monkeypatch.setattr(results, "_SOURCE_ROOT", tmp_path / "site-packages")  # no .git there
    monkeypatch.setattr(results.resources, "files", lambda name: tmp_path / name)
    assert results.git_revision() == "0123abcd"


def test_without_git_or_a_recorded_revision_it_says_unknown(tmp_path, monkeypatch):
    monkeypatch.setattr(results, "_SOURCE_ROOT", tmp_path)
    monkeypatch.setattr(results.resources, "files", lambda name: tmp_path / name)
    assert results.git_revision() == "unknown"
    assert results.provenance()["git_revision"] == "unknown"


def test_provenance_records_the_versions_that_matter():
    versions = json.loads(results.provenance()["versions"])
    assert {"novelty", "numpy", "scipy", "scikit-learn", "numba", "python"} <= set(versions)


@pytest.fixture
def small_suite(toy_registered):
    return Suite([DetectorSpec("hsom", {"n_rows": 3, "n_columns": 3})], [TaskSpec(toy_registered.TASK)],
                 memory=False).check()


def test_a_second_run_into_a_busy_folder_refuses(tmp_path, small_suite):
    store = ResultsStore(tmp_path)
    store.prepare()
    with store.lock():  # another run, as far as flock can tell (a separate open file)
        with pytest.raises(OutputBusyError, match=rf"Another novelty bench \(pid {os.getpid()}\) is "
                                                  rf"writing to {tmp_path}; wait .* or give another --out"):
            run_bench(small_suite, tmp_path, quiet=True, plots=False)
        assert not (tmp_path / "results.jsonl").exists()
    assert run_bench(small_suite, tmp_path, quiet=True, plots=False).ran == 1


def test_a_lock_file_left_by_a_dead_run_does_not_block(tmp_path, small_suite):
    (tmp_path / ".lock").write_text("999999\n")  # killed: its flock went with it
    assert run_bench(small_suite, tmp_path, quiet=True, plots=False).ran == 1


def test_results_are_written_through_unique_temporary_names(tmp_path, small_suite):
    (tmp_path / "results.csv.tmp").mkdir()  # a fixed temporary name, taken
    run_bench(small_suite, tmp_path, quiet=True, plots=False)
    names = set(os.listdir(tmp_path))
    assert {"results.csv", "results.jsonl", "summary.md"} <= names
    assert not [n for n in names if n.endswith(".tmp") and n != "results.csv.tmp"]
    assert stat.S_IMODE((tmp_path / "results.csv").stat().st_mode) == 0o666 & ~_umask()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
