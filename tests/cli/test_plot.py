"""``novelty plot`` of a run output names its x axis for what it is."""

import numpy as np
import pytest

from novelty.cli import main


@pytest.mark.parametrize("distance, label", [
    (np.arange(8) * 0.1, "distance along the route (m)"),
    (np.r_[np.arange(4), np.arange(4)] * 0.1, "scan (runs one after another)"),  # distance starts again
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
