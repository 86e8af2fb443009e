"""``novelty plot`` of a run output names its x axis for what it is and draws what the output has."""

import numpy as np
import pytest

from novelty.cli import main


@pytest.mark.parametrize("distance, label", [
    (np.arange(8) * 0.1, "distance along the route (m)"),
    (np.r_[np.arange(4), np.arange(4)] * 0.1, "scan"),  # the distance starts again: runs, drawn in order
    (None, "scan"),
])
def test_the_x_axis_says_scan_when_the_distance_is_not_the_axis(distance, label, tmp_path, monkeypatch):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    columns = {"scan": np.arange(8), "novelty": np.linspace(1, 0.1, 8)}
    if distance is not None:
        columns["distance"] = distance
    np.savez(tmp_path / "run.npz", **columns)
    labels = []
    monkeypatch.setattr(figure.Figure, "savefig",
                        lambda fig, *a, **k: labels.append(fig.axes[0].get_xlabel()))
    assert main(["plot", str(tmp_path / "run.npz"), "--out", str(tmp_path / "run.png")]) == 0
    assert labels == [label]


def test_a_file_that_is_not_utf8_is_named_in_a_user_error(tmp_path, capsys):
    path = tmp_path / "novelty.csv"
    path.write_bytes(b"scan,novelty\n0,\xff\xfe\n")
    assert main(["plot", str(path), "--out", str(tmp_path / "p.png")]) == 2
    err = capsys.readouterr().err
    assert f"{path} is not UTF-8 text" in err and "internal error" not in err


def test_runs_and_alarms_of_a_run_output_are_drawn_and_named(tmp_path, monkeypatch):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    (tmp_path / "run.csv").write_text("scan,novelty,alarm,distance,run\n0,1,1,0.1,0\n1,0.5,0,0.2,0\n"
                                      "2,0.9,1,0.1,1\n3,0.3,0,0.2,1\n")
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    assert main(["plot", str(tmp_path / "run.csv"), "--out", str(tmp_path / "run.png")]) == 0
    names = [t.get_text() for t in drawn[0].axes[0].get_legend().get_texts()]
    assert names == ["novelty", "alarm raised", "run start"]


def test_a_path_names_its_start_and_alarms_and_x_without_y_is_drawn_along_the_scans(tmp_path, monkeypatch,
                                                                                  capsys):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    (tmp_path / "path.csv").write_text("scan,novelty,alarm,x,y\n0,1,1,0,0\n1,0.5,0,1,2\n")
    assert main(["plot", str(tmp_path / "path.csv"), "--out", str(tmp_path / "path.png")]) == 0
    assert [t.get_text() for t in drawn[0].axes[0].get_legend().get_texts()] == ["start", "alarm raised"]
    (tmp_path / "x.csv").write_text("scan,novelty,x\n0,1,0.5\n1,0.5,0.7\n")
    assert main(["plot", str(tmp_path / "x.csv"), "--out", str(tmp_path / "x.png")]) == 0
    assert "has an 'x' column but no 'y'" in capsys.readouterr().err
    assert drawn[1].axes[0].get_xlabel() == "scan"


def test_a_plot_never_replaces_what_it_reads(tmp_path, capsys):
    run_output = tmp_path / "novelty.csv"
    run_output.write_text("scan,novelty\n0,0.5\n1,0.25\n")
    folder = tmp_path / "bench"
    (folder / "cells").mkdir(parents=True)
    (folder / "results.jsonl").write_text("{}\n")
    for results, out in ((run_output, run_output), (folder, folder / "results.jsonl"),
                         (folder / "results.jsonl", folder / "cells" / "a.npz")):
        assert main(["plot", str(results), "--out", str(out)]) == 2
        assert "RESULTS names" in capsys.readouterr().err
    assert run_output.read_text() == "scan,novelty\n0,0.5\n1,0.25\n" and (folder / "results.jsonl").read_text() == "{}\n"
    assert not (folder / "cells" / "a.npz").exists()
