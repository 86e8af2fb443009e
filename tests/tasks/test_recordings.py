"""Runs, marks, places, visits and exploration tasks from recordings."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty import datasets
from novelty.tasks.recordings import (Mark, mark_features, place_features, read_marks, recording_task, split_runs,
                                      visit_counts)


def _flaser(t, x, ranges):
    return f"FLASER {len(ranges)} {' '.join(map(str, ranges))} {x} 0 0 {x} 0 0 {t} host {t}\n"


@pytest.fixture
def logs(tmp_path):
    """Two drives along a corridor: x = t metres; a box (1 m ahead) from 2 to 3 s in the first only."""
    paths = []
    for k, box in enumerate([(2.0, 3.0), None]):
        lines = []
        for t in np.arange(0.0, 6.0, 0.5):
            near = box is not None and box[0] <= t <= box[1]
            lines.append(_flaser(t, t, [1.0 if near else 3.0] * 4))
        lines.append(_flaser(20.0, 0.0, [3.0] * 4))      # after a 14 s gap: back at the start
        path = tmp_path / f"drive{k}.log"
        path.write_text("".join(lines))
        paths.append(path)
    return paths


def test_marks_from_csv_with_their_errors(tmp_path):
    good = tmp_path / "marks.csv"
    good.write_text("feature,start,end,x,y,radius\nbox,2,3,,,\ndoor,,,1,0,0.5\nbin,0,9,4,0,1\n")
    marks = read_marks(good)
    assert marks == [Mark("box", 2.0, 3.0), Mark("door", x=1.0, y=0.0, radius=0.5),
                     Mark("bin", 0.0, 9.0, 4.0, 0.0, 1.0)]
    for text, match in [("name,start\nbox,1\n", "header must name 'feature'"),
                        ("feature,start,end\nbox,1,x\n", "line 2: end is 'x', not a number"),
                        ("feature,start,end\nbox,3,1\n", "line 2: end 1.0 is before start 3.0"),
                        ("feature,x,y\nbox,1,2\n", "line 2: a region needs x, y and radius"),
                        ("feature,x,y,radius\nbox,1,2,0\n", "radius must be positive"),
                        ("feature,start\n", "no marks")]:
        bad = tmp_path / "bad.csv"
        bad.write_text(text)
        with pytest.raises(ValueError, match=match):
            read_marks(bad)


def test_marks_by_time_and_region():
    marks = [Mark("box", 1.0, 2.0), Mark("bin", 0.0, 1.0, x=0.0, y=0.0, radius=1.0)]
    poses = [[0.0, 0.0, 0], [0.0, 0.5, 0], [5.0, 5.0, 0], [0.0, 0.0, 0]]
    # bin: within 1 m and in [0, 1] s; box: in [1, 2] s wherever
    assert mark_features(marks, [0.0, 1.0, 1.5, 3.0], poses) == [("bin",), ("bin", "box"), ("box",), ()]
    with pytest.raises(ValueError, match="region, but the recording has no poses"):
        mark_features(marks, [0.0])


def test_places_runs_and_visits():
    assert place_features([[-0.1, 2.5, 0]], 2.0) == [("place -1,1",)]
    assert split_runs([0, 1, 2, 10, 11], gap=5).tolist() == [0, 0, 0, 1, 1]
    assert split_runs([0, 1, 2, 10, 11], intervals=[(0.5, 2), (10, 10)]).tolist() == [-1, 0, 0, 1, -1]
    with pytest.raises(ValueError, match="one of the two"):
        split_runs([0, 1])
    with pytest.raises(ValueError, match="not overlapping"):
        split_runs([0, 1], intervals=[(0, 2), (1, 3)])
    # a square loop of side 4 driven twice; radius 1, leave 2: the last scan of the first lap, at (0, 1),
    # closes the loop (1 m from the start, after going 4 m away), the second lap revisits every place,
    side = np.linspace(0, 4, 5)[:-1]
    lap = np.concatenate([np.c_[side, 0 * side], np.c_[4 + 0 * side, side], np.c_[4 - side, 4 + 0 * side],
                          np.c_[0 * side, 4 - side]])
    counts = visit_counts(np.vstack([lap, lap]), radius=1.0)
    assert counts.tolist() == [0] * 15 + [1] * 16 + [2]     # and closes it again: a third visit
    # hovering at the edge (1.0, 2.5, 1.0 m away) without going beyond leave=2 m is one visit
    assert visit_counts(np.c_[[0.0, 1.0, 1.8, 1.0], [0, 0, 0, 0]], radius=1.0).tolist() == [0, 0, 0, 0]


def test_an_exploration_task_from_two_drives_and_a_csv(logs, tmp_path):
    marks = tmp_path / "marks.csv"
    marks.write_text("feature,start,end\nbox,2,3\n")
    task = recording_task(logs, marks=marks, gap=5.0, sectors=2)
    # drive 0 splits at its gap into runs 0 (warm-up) and 1; drive 1 into runs 2 and 3
    assert task.metadata["exploration"]["warmup_runs"] == 1
    assert np.unique(task.run).tolist() == [0, 1, 2, 3] and len(task) == 26
    assert task.columns["environment"][[0, 12, 13, 25]].tolist() == ["drive0.log#0", "drive0.log#1",
                                                                     "drive1.log#0", "drive1.log#1"]
    # the box is marked 2..3 s in both files (times are per file); the first drive's is in the warm-up
    box = task.columns["feature"] == "box"
    assert box.sum() == 6 and task.columns["exposure"][box].tolist() == [0, 0, 0, 1, 1, 1]
    assert task.X[4].tolist() == [0.75, 0.75] and task.X[0].tolist() == [0.25, 0.25]
    assert task.poses.shape == (26, 3) and task.columns["time"][12] == 20.0
    # the box first met in the warm-up: y (first exposure) there, none in the scored runs
    assert task.train().run.max() == 0 and np.flatnonzero(task.y).tolist() == [4, 5, 6]


def test_places_make_a_task_and_the_registry_builds_it(logs, tmp_path):
    task = datasets.load("recording", paths=[str(p) for p in logs], places=2.0, sectors=2)
    assert np.unique(task.run).tolist() == [0, 1]
    # the second drive passes the first's places only: all familiar, nothing tracked
    assert set(task.columns["feature"].tolist()) == {""} and task.y.sum() == 0
    # a third drive further on (x = 10..15.5 m): its places are new, the first at x 10-12 m
    longer = tmp_path / "longer.log"
    longer.write_text("".join(_flaser(t, 10 + t, [3.0] * 4) for t in np.arange(0.0, 6.0, 0.5)))
    task = recording_task([*logs, longer], places=2.0, sectors=2)
    new = task.run == 2
    assert task.columns["feature"][new][:4].tolist() == ["place 5,0"] * 4
    assert task.y[new].all() and not task.y[~new].any()
    with pytest.raises(ValueError, match="Say what is tracked"):
        recording_task(logs)


def _visits_by_hand(poses, radius, leave):
    """The definition, a scan at a time: entries into the disc after being beyond leave."""
    out = []
    for i, here in enumerate(poses):
        entries, away = 0, True
        for there in poses[:i + 1]:
            d = float(np.hypot(*(np.asarray(there) - here)))
            if d <= radius and away:
                entries, away = entries + 1, False
            elif d > leave:
                away = True
        out.append(entries - 1)
    return out


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 8), st.integers(0, 8)), min_size=1, max_size=30))
def test_visit_counts_match_the_definition(points):
    poses = np.array(points, dtype=float)
    assert visit_counts(poses, 1.5, 3.0).tolist() == _visits_by_hand(poses, 1.5, 3.0)


def test_poses_that_are_not_finite_are_refused():
    # NaN odometry has no place on a grid and no distance to another pose
    poses = [[0.0, 0.0, 0.0], [float("nan"), 1.0, 0.0]]
    with pytest.raises(ValueError, match=r"pose 1 is \[nan, 1.0, 0.0\]; positions must be finite"):
        place_features(poses, 1.0)
    with pytest.raises(ValueError, match="pose 1 is"):
        visit_counts(poses, 1.0)
