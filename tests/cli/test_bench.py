"""``novelty bench``: the reference option, the exit code when cells fail, seeds, the suites its help cites."""

import sys
from pathlib import Path

import pytest

import novelty
from novelty.cli import main
from novelty.cli.bench import EXAMPLES

sys.path.insert(0, str(Path(__file__).parents[1] / "bench"))
import toy  # noqa: E402


@pytest.fixture
def toy_task():
    from novelty.datasets import registry as datasets

    datasets.register(toy.TASK, toy.toy_task, description="A tiny synthetic task (tests).", replace=True)
    novelty.register_detector(toy.BROKEN, toy.broken_detector, replace=True)
    yield toy.TASK
    datasets.unregister(toy.TASK)
    novelty.registry.detectors.unregister(toy.BROKEN)


def bench(tmp_path, *detectors, extra=()):
    argv = ["bench", "--task", f"{toy.TASK} n_test=24", "--seeds", "1", "--out", str(tmp_path / "b"),
            "--no-plots", "--no-memory", "--quiet", *extra]
    for d in detectors:
        argv += ["--detector", d]
    return main(argv)


def test_the_paired_comparison_is_printed_against_the_reference(toy_task, tmp_path, capsys):
    assert bench(tmp_path, "hsom n_rows=3 n_columns=3", "parzen", extra=["--reference", "parzen"]) == 0
    out = capsys.readouterr().out
    assert out.index("| # | detector") < out.index("ΔROC AUC vs parzen (mean ± se)")
    assert "No Friedman test: it needs three detectors" in out
    summary = (tmp_path / "b" / "summary.md").read_text()
    assert "## Paired comparison with parzen" in summary
    assert f"- command: `novelty bench --task '{toy.TASK} n_test=24' --seeds 1" in summary


def test_an_unknown_reference_is_a_user_error(toy_task, tmp_path, capsys):
    assert bench(tmp_path, "hsom", extra=["--reference", "lof"]) == 2
    assert "reference 'lof' is not a detector" in capsys.readouterr().err


def test_a_partial_failure_exits_0_and_says_how_many_failed(toy_task, tmp_path, capsys):
    assert bench(tmp_path, "hsom", toy.BROKEN) == 0
    assert "1 of 2 cells failed" in capsys.readouterr().out


def test_a_bench_where_every_cell_fails_exits_1(toy_task, tmp_path, capsys):
    assert bench(tmp_path, toy.BROKEN) == 1
    err = capsys.readouterr().err
    assert "every cell failed (1 of 1), nothing was measured" in err
    assert "FloatingPointError: this detector always fails" in err


def test_a_wrong_label_of_a_files_task_is_refused_before_any_cell_runs(tmp_path, capsys):
    (tmp_path / "scans.csv").write_text("a,novel\n0.1,0\n0.2,0\n0.3,0\n0.9,1\n")
    argv = ["bench", "--detector", "hsom", "--task", f"files path={tmp_path / 'scans.csv'} label=nove train_rows=2",
            "--out", str(tmp_path / "b"), "--quiet"]
    assert main(argv) == 2
    assert ("novelty bench: error: Task 'scans': label: no column 'nove'; the file has a, novel."
            in capsys.readouterr().err)
    assert not (tmp_path / "b").exists()  # nothing ran


def test_zero_seeds_from_the_command_line_is_one_clear_error(capsys):
    assert main(["bench", "--quick", "--seeds", "0", "--out", "unused"]) == 2
    assert "must be at least 1" in capsys.readouterr().err


def test_every_suite_file_the_help_cites_exists():
    root = Path(__file__).parents[2]
    cited = [word for example in EXAMPLES for word in example.split() if word.endswith(".toml")
             and "/" in word]
    assert cited
    for path in cited:
        assert (root / path).is_file(), path


def test_a_task_file_among_what_the_bench_writes_is_refused_before_any_cell_runs(tmp_path, capsys):
    out = tmp_path / "b"
    (out / "cells").mkdir(parents=True)
    scans = "novel,a,b\n" + "".join(f"{i % 2},{i},{i}\n" for i in range(20))
    for name in ("results.csv", "cells/mine.csv"):
        (out / name).write_text(scans)
        assert main(["bench", "--detector", "hsom", "--task", f"files path={out / name} train_rows=10 label=novel",
                     "--seeds", "1", "--out", str(out), "--quiet"]) == 2
        assert "is among the files novelty bench writes in --out" in capsys.readouterr().err
        assert (out / name).read_text() == scans
    assert not (out / "results.jsonl").exists()
