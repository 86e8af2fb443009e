"""The novelty command line: every command through main([...]), one through a subprocess."""

import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import novelty
import novelty.cli
from novelty.cli import COMMANDS, build_parser, main

sys.path.insert(0, str(Path(__file__).parents[1] / "bench"))
import toy  # noqa: E402


@pytest.fixture
def toy_task():
    from novelty.datasets import registry as datasets

    datasets.register(toy.TASK, toy.toy_task, description="A tiny synthetic task (tests).", replace=True)
    yield toy.TASK
    datasets.unregister(toy.TASK)


@pytest.fixture
def scans(tmp_path):
    rng = np.random.default_rng(0)
    X = rng.random((30, 5))
    path = tmp_path / "scans.csv"
    header = "s0,s1,s2,s3,s4,distance"
    np.savetxt(path, np.c_[X, np.arange(30) * 0.1], delimiter=",", header=header, comments="")
    return path, X


def one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err
    assert len(err.splitlines()) == 1, err
    return err


@pytest.mark.parametrize("command", [None, *COMMANDS])
def test_help_has_examples(command, capsys):
    assert main(([command] if command else []) + ["--help"]) == 0
    out = capsys.readouterr().out
    assert "examples:" in out and "novelty" in out


def test_list_shows_every_kind(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for title in ("Detectors", "Clusterers", "Synapses", "Datasets and tasks"):
        assert title in out
    assert "hsom" in out and "The paper's Habituating SOM" in out and "stanley" in out


def test_list_one_kind(toy_task, capsys):
    assert main(["list", "datasets"]) == 0
    out = capsys.readouterr().out
    assert toy_task in out and "A tiny synthetic task" in out and "Detectors" not in out


def test_run_then_score(scans, tmp_path, capsys):
    path, X = scans
    out, model = tmp_path / "novelty.csv", tmp_path / "model.npz"
    assert main(["run", "hsom", "--data", str(path), "--param", "n_rows=4", "-p", "alpha=1.2",
                 "--out", str(out), "--save", str(model)]) == 0
    det = novelty.make("hsom", n_rows=4, alpha=1.2)
    expected = det.stream(X)
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert table.dtype.names == ("scan", "novelty", "alarm", "threshold", "distance")
    np.testing.assert_array_equal(table["alarm"], expected > 0.5)
    np.testing.assert_allclose(table["novelty"], expected, rtol=1e-9)
    np.testing.assert_allclose(table["distance"], np.arange(30) * 0.1)
    capsys.readouterr()
    assert main(["score", "--model", str(model), "--data", str(path)]) == 0
    scored = capsys.readouterr().out.splitlines()
    assert scored[0] == "scan,novelty,alarm,threshold,distance" and len(scored) == 31
    np.testing.assert_allclose([float(line.split(",")[1]) for line in scored[1:]], det.novelty(X), rtol=1e-9)


def test_run_reads_npz_and_writes_npz(tmp_path):
    X = np.random.default_rng(1).random((12, 3))
    np.savez(tmp_path / "scans.npz", X=X, y=np.r_[np.zeros(10), np.ones(2)])
    assert main(["run", "habituating", "--data", str(tmp_path / "scans.npz"), "--passes", "2",
                 "--out", str(tmp_path / "out.npz")]) == 0
    with np.load(tmp_path / "out.npz") as out:
        assert set(out.files) == {"scan", "novelty", "alarm", "threshold", "y"}
        det = novelty.make("habituating")
        det.stream(X)
        np.testing.assert_allclose(out["novelty"], det.stream(X))


def test_bench_from_the_command_line(toy_task, tmp_path, capsys):
    out = tmp_path / "bench"
    code = main(["bench", "--detector", "hsom n_rows=3 n_columns=3", "--detector", "habituating",
                 "--task", f"{toy_task} n_test=24", "--seeds", "2", "--out", str(out), "--no-plots"])
    assert code == 0
    captured = capsys.readouterr()
    assert "| # | detector" in captured.out and "hsom[n_rows=3,n_columns=3]" in captured.out
    assert "[4/4]" in captured.err  # plain progress lines: not a terminal
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    assert len(rows) == 4 and {r["seed"] for r in rows} == {0, 1}
    # a rerun resumes
    assert main(["bench", "--detector", "hsom n_rows=3 n_columns=3", "--detector", "habituating",
                 "--task", f"{toy_task} n_test=24", "--seeds", "2", "--out", str(out), "--no-plots"]) == 0
    assert "Resuming: 4 of 4 cells" in capsys.readouterr().err


def test_bench_from_a_suite_file_and_plot(toy_task, tmp_path, capsys):
    pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")
    suite = tmp_path / "suite.toml"
    suite.write_text(f'[suite]\nname = "t"\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "{toy_task}"\n')
    out = tmp_path / "bench"
    assert main(["bench", str(suite), "--out", str(out), "--quiet", "--no-memory"]) == 0
    assert (out / "plots" / "ranking.png").is_file()
    assert main(["plot", str(out), "--out", str(tmp_path / "route.png")]) == 0
    assert (tmp_path / "route.png").stat().st_size > 1000


def test_plot_a_run_output(scans, tmp_path):
    pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")
    path, _ = scans
    assert main(["run", "hsom", "--data", str(path), "--out", str(tmp_path / "n.csv")]) == 0
    assert main(["plot", str(tmp_path / "n.csv"), "--out", str(tmp_path / "n.png")]) == 0
    assert (tmp_path / "n.png").stat().st_size > 1000


def test_simulate(tmp_path, capsys):
    try:
        from novelty.sonar import simulate  # noqa: F401
    except ImportError:
        assert main(["simulate", "paper-a", "--out", str(tmp_path / "a.npz")]) == 2
        assert "not available" in one_error_line(capsys)
        return
    assert main(["simulate", "paper-a", "--runs", "2", "--seed", "3", "--out", str(tmp_path / "a.npz")]) == 0
    with np.load(tmp_path / "a.npz") as data:
        assert data["X"].ndim == 2 and set(np.unique(data["run"])) == {0, 1}


def test_a_simulated_task_csv_runs_through_a_detector(tmp_path):
    """A task export carries text columns (split, feature ids); only the sensors are read."""
    pytest.importorskip("novelty.sonar")
    task_csv, out = tmp_path / "task.csv", tmp_path / "novelty.csv"
    assert main(["simulate", "paper-a-to-a-star", "--seed", "1", "--out", str(task_csv)]) == 0
    task = novelty.datasets.load("paper-a-to-a-star", seed=1)
    assert main(["run", "hsom", "--data", str(task_csv), "--out", str(out)]) == 0
    rows = out.read_text().splitlines()
    assert rows[0].split(",")[:5] == ["scan", "novelty", "alarm", "threshold", "y"] and len(rows) == len(task) + 1
    expected = novelty.make("hsom").stream(task.X)
    got = np.array([float(r.split(",")[1]) for r in rows[1:]])
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
    assert [int(float(r.split(",")[4])) for r in rows[1:]] == task.y.tolist()


@pytest.mark.parametrize("argv, message", [
    (["run", "hsomm", "--data", "DATA"], "Unknown detector 'hsomm'. Did you mean 'hsom'"),
    (["run", "hsom", "--data", "DATA", "--param", "n_row=3"], "did you mean 'n_rows'"),
    (["run", "hsom", "--data", "DATA", "--param", "n_rows=0"], "must be an int in [1, inf)"),
    (["run", "hsom", "--data", "DATA", "--param", "n_rows"], "name=value"),
    (["run", "hsom", "--data", "missing.csv"], "Data file not found"),
    (["run", "hsom", "--data", "BAD"], "column 's1': expected a number, got text 'abc'"),
    (["score", "--model", "missing.npz", "--data", "DATA"], "Model file not found"),
    (["score", "--model", "DATA", "--data", "DATA"], "error"),
    (["bench", "SUITE", "--out", "OUT"], "not valid TOML"),
    (["bench", "missing.toml", "--out", "OUT"], "Suite file not found"),
    (["bench", "--detector", "nope", "--task", "nope", "--out", "OUT"], "Unknown detector 'nope'"),
    (["bench", "--out", "OUT"], "Nothing to run"),
    (["bench", "--quick", "--jobs", "0", "--out", "OUT"], "--jobs must be at least 1"),
    (["bench", "--frobnicate"], "unrecognized arguments: --frobnicate"),
    (["run"], "the following arguments are required"),
    (["plot", "missing.jsonl", "--out", "x.png"], "Results not found"),
    (["list", "widgets"], "invalid choice"),
])
def test_user_errors_are_one_line_and_exit_2(argv, message, scans, tmp_path, capsys):
    path, _ = scans
    bad = tmp_path / "bad.csv"
    bad.write_text("s0,s1\n0.1,abc\n")
    suite = tmp_path / "bad.toml"
    suite.write_text("[[detectors]\nname = 'hsom'\n")
    swap = {"DATA": str(path), "BAD": str(bad), "SUITE": str(suite), "OUT": str(tmp_path / "out")}
    assert main([swap.get(a, a) for a in argv]) == 2
    assert message in one_error_line(capsys)


@pytest.mark.slow
def test_the_console_command_in_a_subprocess(tmp_path):
    import os

    env = {**os.environ, "PYTHONPATH": str(Path(novelty.__file__).parents[1])}
    ok = subprocess.run([sys.executable, "-m", "novelty.cli", "list", "detectors"], capture_output=True,
                        text=True, env=env, timeout=120)
    assert ok.returncode == 0 and "hsom" in ok.stdout
    bad = subprocess.run([sys.executable, "-m", "novelty.cli", "run", "hsomm", "--data", "x.csv"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert bad.returncode == 2
    assert len(bad.stderr.strip().splitlines()) == 1
    assert bad.stderr.startswith("novelty run: error: Unknown detector 'hsomm'. Did you mean 'hsom'")


def test_a_damaged_model_file_is_a_user_error(scans, tmp_path, capsys):
    path, X = scans
    model = tmp_path / "deep.npz"
    meta = np.frombuffer(b"[" * 100_000 + b"]" * 100_000, dtype=np.uint8)
    np.savez(model, meta=meta)  # metadata nested beyond any parser's recursion
    assert main(["score", "--model", str(model), "--data", str(path)]) == 2
    assert "nested too deeply" in one_error_line(capsys)


def test_cell_timeout_is_checked(tmp_path, capsys):
    argv = ["bench", "--quick", "--cell-timeout", "-1", "--out", str(tmp_path / "out")]
    assert main(argv) == 2
    assert "cell_timeout must be a positive number of seconds; got -1.0" in one_error_line(capsys)


# ------------------------------------------------------ the module's examples
def _session(text):
    """The example command lines of ``text``: indented lines, and quoted strings, that start with 'novelty '."""
    return re.findall(r"(?m)^\s+(novelty [^\n]*?)\s*$", text), re.findall(r'"(novelty [^"]*)"', text)


def test_the_docstrings_examples_run_as_written(tmp_path, monkeypatch, capsys):
    session, quoted = _session(novelty.cli.__doc__)
    assert len(session) == 6 and set(quoted) <= set(session), (session, quoted)
    monkeypatch.chdir(tmp_path)
    for line in session:
        argv = shlex.split(line)
        assert main(argv[1:]) == 0, (line, capsys.readouterr().err)
    assert {"corridor-a.npz", "novelty.csv", "hsom.npz", "rescored.csv", "route.png", "results"} <= {
        p.name for p in tmp_path.iterdir()}
    scans = len(np.load("corridor-a.npz")["X"])
    assert len(Path("novelty.csv").read_text().splitlines()) == len(Path("rescored.csv").read_text().splitlines())
    assert len(Path("rescored.csv").read_text().splitlines()) == scans + 1  # a header and a row a scan
    assert (tmp_path / "results" / "first" / "results.csv").is_file()


def test_novelty_help_lists_the_docstrings_session():
    session, _ = _session(novelty.cli.__doc__)
    assert _session(build_parser().epilog)[0] == session

