"""``novelty run`` on the user's files and on a live stream from standard input."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import novelty
from novelty.cli import EXIT_PIPE_CLOSED, main
from novelty.sonar.preprocessing import preprocess

ENV = {**os.environ, "PYTHONPATH": str(Path(novelty.__file__).parents[1])}
ROS = """%time,field.header.seq,field.header.stamp,field.header.frame_id,field.ranges0,field.ranges1
1700000000000000000,1,1700000000000000000,sonar,1.0,inf
1700000000500000000,2,1700000000500000000,sonar,2.0,3.0
1700000001000000000,3,1700000001000000000,sonar,1.0,inf
"""


def novelty_command(*args, **kwargs):
    return subprocess.Popen([sys.executable, "-m", "novelty.cli", *args], env=ENV, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kwargs)


def rows(text: str) -> list[list[str]]:
    return [line.split(",") for line in text.strip().splitlines()]


def test_a_ros_export_is_scored_on_its_ranges_with_its_stamps(tmp_path, capsys):
    path = tmp_path / "sonar.csv"
    path.write_text(ROS)
    assert main(["run", "hsom", "--data", str(path), "--columns", "field.ranges*", "--preprocess", "paper",
                 "--param", "n_rows=3"]) == 0
    table = rows(capsys.readouterr().out)
    assert table[0] == ["scan", "novelty", "alarm", "time"]
    assert [r[3] for r in table[1:]] == ["1700000000.0", "1700000000.5", "1700000001.0"]
    X = preprocess([[1.0, np.inf], [2.0, 3.0], [1.0, np.inf]])
    expected = novelty.make("hsom", n_rows=3).stream(X, timestamps=[0.0, 0.5, 1.0])
    np.testing.assert_allclose([float(r[1]) for r in table[1:]], expected, rtol=1e-9)
    assert [int(r[2]) for r in table[1:]] == (expected > 0.5).astype(int).tolist()


def test_a_ros_export_without_chosen_columns_is_refused(tmp_path, capsys):
    path = tmp_path / "sonar.csv"
    path.write_text(ROS)
    assert main(["run", "hsom", "--data", str(path)]) == 2
    assert "Choose the sensor columns with columns= (--columns), e.g. 'field.ranges*'" in capsys.readouterr().err


def test_score_takes_the_same_column_options(tmp_path, capsys):
    path, model = tmp_path / "scans.csv", tmp_path / "m.npz"
    path.write_text("when,a,b,note,novel\n0,0.1,0.2,x,0\n1,0.9,0.8,y,1\n")
    det = novelty.make("hsom", n_rows=2).fit(np.array([[0.1, 0.2]]))
    det.save(model)
    assert main(["score", "--model", str(model), "--data", str(path), "--columns", "1,2", "--label", "novel",
                 "--time", "when"]) == 0
    table = rows(capsys.readouterr().out)
    assert table[0] == ["scan", "novelty", "alarm", "y", "time"]
    np.testing.assert_allclose([float(r[1]) for r in table[1:]], det.novelty([[0.1, 0.2], [0.9, 0.8]]))
    assert [r[3] for r in table[1:]] == ["0", "1"]


@pytest.mark.slow
def test_stdin_is_scored_a_line_at_a_time_as_the_lines_arrive():
    """Each scan's row comes back before the next line is written: nothing is read ahead."""
    X = np.random.default_rng(0).random((4, 3))
    proc = novelty_command("run", "hsom", "--data", "-", "--label", "y", stdin=subprocess.PIPE)
    proc.stdin.write("a,b,c,y\n")
    got = []
    for i, x in enumerate(X):
        proc.stdin.write(",".join(str(float(v)) for v in x) + f",{int(i == 3)}\n")
        proc.stdin.flush()
        if i == 0:
            assert proc.stdout.readline() == "scan,novelty,alarm,y\n"
        got.append(proc.stdout.readline().strip().split(","))
    proc.stdin.close()
    assert proc.wait(timeout=120) == 0 and proc.stdout.read() == ""
    expected = novelty.make("hsom").stream(X)
    np.testing.assert_allclose([float(r[1]) for r in got], expected, rtol=1e-9)
    assert [r[0] for r in got] == ["0", "1", "2", "3"] and [r[3] for r in got] == ["0", "0", "0", "1"]


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["list"], ["run", "hsom", "--data", "DATA"]])
def test_a_closed_output_pipe_ends_the_command_quietly(argv, tmp_path):
    data = tmp_path / "scans.csv"
    np.savetxt(data, np.random.default_rng(0).random((20000, 4)), delimiter=",")
    proc = novelty_command(*[str(data) if a == "DATA" else a for a in argv])
    assert proc.stdout.readline()
    proc.stdout.close()  # as 'head -1' does (the output, 20,000 rows, is more than a pipe holds)
    assert proc.wait(timeout=120) == EXIT_PIPE_CLOSED
    assert proc.stderr.read() == ""


@pytest.mark.parametrize("argv, message", [
    (["run", "lof", "--data", "-"], "lof learns in batch only; it cannot score a stream"),
    (["run", "hsom", "--data", "-", "--passes", "2"], "--passes and --bin-length need the whole file"),
    (["run", "hsom", "--data", "-", "--out", "x.csv"], "the novelty goes to standard output"),
])
def test_what_a_stream_cannot_do_is_refused(argv, message, capsys):
    assert main(argv) == 2
    assert message in capsys.readouterr().err


def test_a_bad_line_on_stdin_names_its_line(monkeypatch, capsys):
    import io

    monkeypatch.setattr(sys, "stdin", io.StringIO("a,b\n0.1,0.2\n0.3,oops\n"))
    assert main(["run", "hsom", "--data", "-"]) == 2
    captured = capsys.readouterr()
    assert len(rows(captured.out)) == 2  # the first scan was written before the bad line was read
    assert "standard input, line 3, column 'b': expected a number, got text 'oops'" in captured.err


def test_alarm_policy_k_of_n_on_a_file(tmp_path, capsys):
    X = np.random.default_rng(0).random((40, 3))
    path = tmp_path / "scans.csv"
    np.savetxt(path, X, delimiter=",")
    assert main(["run", "hsom", "--data", str(path), "--param", "n_rows=3", "--alarm", "k-of-n:2,3,0.6"]) == 0
    table = rows(capsys.readouterr().out)
    nov = novelty.make("hsom", n_rows=3).stream(X)
    above = nov > 0.6
    expected = [int(above[max(0, i - 2):i + 1].sum() >= 2) for i in range(len(X))]
    assert [int(r[2]) for r in table[1:]] == expected and 0 < sum(expected) < len(X)


def test_alarm_policy_hysteresis_on_stdin(monkeypatch, capsys):
    import io

    from novelty.alarms import Hysteresis

    X = np.random.default_rng(1).random((30, 2))
    monkeypatch.setattr(sys, "stdin", io.StringIO("a,b\n" + "".join(f"{x[0]},{x[1]}\n" for x in X.tolist())))
    assert main(["run", "hsom", "--data", "-", "--param", "n_rows=2", "--alarm", "hysteresis:0.8,0.3"]) == 0
    table = rows(capsys.readouterr().out)
    nov = novelty.make("hsom", n_rows=2).stream(X)
    assert [int(r[2]) for r in table[1:]] == Hysteresis(0.8, 0.3).run(nov).astype(int).tolist()


@pytest.mark.parametrize("spec, message", [
    ("k-of-n:3", r"--alarm: Alarm 'k-of-n:3' takes k-of-n:K,N[,T]; got 1 value."),
    ("sometimes", r"--alarm: Unknown alarm 'sometimes'; expected one of threshold[:T], k-of-n:K,N[,T]"),
])
def test_a_bad_alarm_policy_is_a_user_error(spec, message, tmp_path, capsys):
    path = tmp_path / "scans.csv"
    np.savetxt(path, np.random.default_rng(0).random((5, 2)), delimiter=",")
    assert main(["run", "hsom", "--data", str(path), "--alarm", spec]) == 2
    assert message in capsys.readouterr().err


def test_the_alarm_follows_the_detectors_threshold(tmp_path, capsys):
    path = tmp_path / "scans.csv"
    X = np.random.default_rng(2).random((40, 4))
    np.savetxt(path, X, delimiter=",")
    assert main(["run", "hsom", "--data", str(path), "--param", "n_rows=3", "--param", "threshold=0.7"]) == 0
    table = rows(capsys.readouterr().out)[1:]
    novelty_ = np.array([float(r[1]) for r in table])
    assert 0 < (novelty_ > 0.7).sum() < len(table)
    assert [int(r[2]) for r in table] == (novelty_ > 0.7).astype(int).tolist()


@pytest.mark.parametrize("line, message", [
    ("0.3,0.4,", "standard input, line 3, column 'y' (the label): expected a number, got an empty cell."),
    ("0.3,nan,1", "standard input, line 3, column 'b': expected a finite number, got nan."),
    ("0.3,0.4,nan", "standard input, line 3, column 'y' (the label): expected a finite number, got nan."),
])
def test_a_bad_cell_on_stdin_names_its_line_and_column(monkeypatch, capsys, line, message):
    import io

    monkeypatch.setattr(sys, "stdin", io.StringIO(f"a,b,y\n0.1,0.2,0\n{line}\n"))
    assert main(["run", "hsom", "--data", "-"]) == 2
    assert message in capsys.readouterr().err


def test_save_to_a_fifo_or_a_link_is_refused_before_the_scans_are_read(tmp_path, capsys):
    data = tmp_path / "scans.csv"
    data.write_text("a,b\n0.1,0.2\n0.3,0.4\n")
    fifo = tmp_path / "pipe.npz"
    os.mkfifo(fifo)
    link = tmp_path / "link.npz"
    link.symlink_to(tmp_path / "elsewhere.npz")
    for target, kind in ((fifo, "FIFO"), (link, "symbolic link")):
        assert main(["run", "hsom", "--data", str(data), "--param", "n_rows=2", "--save", str(target)]) == 2
        captured = capsys.readouterr()
        assert kind in captured.err and "only a regular file is replaced" in captured.err
        assert captured.out == ""  # refused before any scan was scored
    assert os.path.islink(link) and not (tmp_path / "elsewhere.npz").exists()


def test_a_fifo_as_data_is_refused_at_once_with_the_message_the_bench_gives(tmp_path, capsys):
    fifo = tmp_path / "scans.csv"
    os.mkfifo(fifo)  # no writer: opening it would block forever
    assert main(["run", "hsom", "--data", str(fifo)]) == 2
    run_says = capsys.readouterr().err
    assert "is a FIFO (named pipe), not a regular file" in run_says
    assert main(["bench", "--detector", "hsom", "--task", f"files path={fifo}", "--out", str(tmp_path / "b"),
                 "--quiet"]) == 2
    bench_says = capsys.readouterr().err
    assert run_says.split("error: ")[1] in bench_says


@pytest.mark.parametrize("stdin, message", [
    (b"a,b\n\x00\xff\xfe,1\n", "standard input, line 2"),
    (b"a,b\n0.1,0.2\n" + b"0," * 3_000_000 + b"\n", "standard input, line 3: longer than 4194304 characters"),
])
def test_binary_or_endless_stdin_is_a_user_error(stdin, message):
    proc = subprocess.run([sys.executable, "-m", "novelty.cli", "run", "hsom", "--data", "-"], env=ENV,
                          input=stdin, capture_output=True, timeout=300)
    err = proc.stderr.decode()
    assert proc.returncode == 2, err
    assert message in err and "internal error" not in err


def _same_file_targets(tmp_path, data):
    """``data`` under other names: itself, a hard link, a symbolic link, a path through a link's folder."""
    hard = tmp_path / "hard.csv"
    os.link(data, hard)
    soft = tmp_path / "soft.csv"
    soft.symlink_to(data)
    (tmp_path / "again").symlink_to(tmp_path)
    return [data, hard, soft, tmp_path / "again" / data.name]


def test_an_output_naming_the_data_file_is_refused_before_anything_is_read_or_written(tmp_path, capsys):
    data = tmp_path / "scans.csv"
    data.write_text("a,b\n0.1,0.2\n0.3,0.4\n")
    for target in _same_file_targets(tmp_path, data):
        for option in ("--out", "--save"):
            assert main(["run", "hsom", "--data", str(data), "--param", "n_rows=2", option, str(target)]) == 2
            captured = capsys.readouterr()
            assert f"{option} {target} is the file --data names" in captured.err and captured.out == ""
    assert data.read_text() == "a,b\n0.1,0.2\n0.3,0.4\n"


def test_out_and_save_naming_one_file_are_refused(tmp_path, capsys):
    data = tmp_path / "scans.csv"
    data.write_text("a,b\n0.1,0.2\n0.3,0.4\n")
    model = tmp_path / "m.npz"
    assert main(["run", "hsom", "--data", str(data), "--param", "n_rows=2", "--out", str(model),
                 "--save", str(model)]) == 2
    assert "--out and --save name one file" in capsys.readouterr().err
    assert not model.exists()


def test_a_recording_is_never_replaced_by_its_output(tmp_path, capsys):
    bag = tmp_path / "rec.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n not read")
    folder = tmp_path / "rosbag2"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("not read")
    for data, out in ((bag, bag), (folder, folder / "run_0.mcap"), (folder, folder / "metadata.yaml")):
        assert main(["run", "hsom", "--data", str(data), "--out", str(out)]) == 2
        assert "--data names" in capsys.readouterr().err
    assert bag.read_bytes() == b"#ROSBAG V2.0\n not read" and (folder / "metadata.yaml").read_text() == "not read"
    assert sorted(p.name for p in folder.iterdir()) == ["metadata.yaml"]
