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
    (legend,) = drawn[0].legends   # below the axes: it covers nothing
    assert drawn[0].axes[0].get_legend() is None
    assert [t.get_text() for t in legend.get_texts()] == ["novelty", "alarm raised", "run start"]


def test_the_threshold_column_of_a_run_is_drawn(tmp_path, monkeypatch):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    (tmp_path / "run.csv").write_text("scan,novelty,alarm,threshold\n0,1,,\n1,0.5,,\n2,0.9,1,0.7\n3,0.3,0,0.7\n")
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    assert main(["plot", str(tmp_path / "run.csv"), "--out", str(tmp_path / "run.png")]) == 0
    (legend,) = drawn[0].legends
    assert [t.get_text() for t in legend.get_texts()] == ["novelty", "alarm threshold", "alarm raised"]


def test_a_path_names_its_start_and_alarms_and_x_without_y_is_drawn_along_the_scans(tmp_path, monkeypatch,
                                                                                  capsys):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    (tmp_path / "path.csv").write_text("scan,novelty,alarm,x,y\n0,1,1,0,0\n1,0.5,0,1,2\n")
    assert main(["plot", str(tmp_path / "path.csv"), "--out", str(tmp_path / "path.png")]) == 0
    (legend,) = drawn[0].legends
    assert [t.get_text() for t in legend.get_texts()] == ["start", "alarm raised (on the path)", "novelty",
                                                          "alarm raised"]
    (tmp_path / "x.csv").write_text("scan,novelty,x\n0,1,0.5\n1,0.5,0.7\n")
    assert main(["plot", str(tmp_path / "x.csv"), "--out", str(tmp_path / "x.png")]) == 0
    assert "has an 'x' column but no 'y'" in capsys.readouterr().err
    assert drawn[1].axes[0].get_xlabel() == "scan"


@pytest.mark.parametrize("protocol, task", [("holdout", "inspection-easy"), ("exploration", "exploration-open-door")])
def test_every_kind_of_bench_folder_is_plotted(protocol, task, tmp_path, monkeypatch):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    out = tmp_path / protocol
    assert main(["bench", "--protocol", protocol, "--detector", "hsom n_rows=3 n_columns=3", "--detector",
                 "nearest-memory", "--task", f"{task} seed=0", "--seeds", "1", "--out", str(out), "--no-plots",
                 "--quiet", "--no-memory"]) == 0
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    assert main(["plot", str(out), "--out", str(tmp_path / "p.png")]) == 0
    (fig,) = drawn
    assert [ax.get_title(loc="left").split(" (")[0] for ax in fig.axes] == ["hsom[n_rows=3,n_columns=3]",
                                                                            "nearest-memory"]
    (legend,) = fig.legends
    assert "novelty" in [t.get_text() for t in legend.get_texts()]


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
