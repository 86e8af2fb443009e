"""A simulated task's rows as the points input: the same scans, labels and splits, with the pose and echoes beside."""

from dataclasses import replace

import numpy as np
import pytest

from novelty.datasets.inputs import with_inputs
from novelty.datasets.paper import paper_a_to_a_star
from novelty.io.scans.points import split_points
from novelty.sonar.robot import NOMAD_200


@pytest.fixture(scope="module")
def ring_task():
    return paper_a_to_a_star(seed=0, train_runs=1)


def test_the_ring_input_is_the_task_as_simulated(ring_task):
    assert with_inputs(ring_task, "ring") is ring_task


def test_the_points_input_carries_the_ring_the_pose_and_each_echo_where_the_ring_says(ring_task):
    task = with_inputs(ring_task, "points")
    poses, near, ends = split_points(task.X)
    assert np.array_equal(near, ring_task.X) and np.array_equal(poses[:, :2], ring_task.poses[:, :2])
    assert np.array_equal(task.y, ring_task.y) and task.metadata["inputs"] == "points"
    # each echo lies offset + T (1 - near) from the robot's centre
    T = float(ring_task.metadata["threshold_m"])
    reach = np.hypot(*(ends - poses[:, None, :2]).transpose(2, 0, 1))
    assert reach == pytest.approx(NOMAD_200.sonar_ring_radius + T * (1.0 - near))


def test_the_points_task_is_the_same_through_the_tasks_own_option(ring_task):
    assert np.array_equal(paper_a_to_a_star(seed=0, train_runs=1, inputs="points").X,
                          with_inputs(ring_task, "points").X)


def test_an_unknown_input_or_a_task_without_poses_is_refused(ring_task):
    with pytest.raises(ValueError, match="inputs must be one of 'ring', 'points'; got 'rings'"):
        with_inputs(ring_task, "rings")
    with pytest.raises(ValueError, match="needs the robot's pose at each scan.*has no poses"):
        with_inputs(replace(ring_task, poses=None), "points")


@pytest.mark.parametrize("name, options", [
    ("exploration-irregular", {"runs": 3, "warmup": 1}),
    ("exploration-return", {"before": 1, "absence": 1, "after": 1, "warmup": 1}),
    ("exploration-moving", {"runs": 2, "warmup": 1}),
])
def test_the_objects_that_come_and_go_give_the_points_input_of_their_own_scans(name, options):
    from novelty.datasets import load

    ring, points = load(name, seed=3, **options), load(name, seed=3, inputs="points", **options)
    poses, near, ends = split_points(points.X)
    assert np.array_equal(near, ring.X) and np.array_equal(poses[:, :2], ring.poses[:, :2])
    assert np.array_equal(points.run, ring.run) and points.metadata["inputs"] == "points"
    assert points.metadata["exploration"] == ring.metadata["exploration"]  # features, exposures, returns
    for column in ("feature", "exposure"):
        assert np.array_equal(points.columns[column], ring.columns[column])
