"""One benchmark cell: training as the robot does, with the task's timestamps."""

import dataclasses

import numpy as np
import pytest

import novelty
import novelty.bench
from novelty.bench.build import CellError, check_input_layout, train_detector
from novelty.datasets import Dataset


def test_training_with_timestamps_continues_the_clock_on_each_pass():
    det = train_detector(novelty.make("hsom"), np.full((6, 16), 0.5), passes=2, timestamps=np.arange(6) * 0.5)
    # the second pass starts one step (0.5) after the first ended (2.5): 3.0 ... 5.5
    assert det.last_time_ == 5.5


def test_training_with_timestamps_is_the_stream_with_those_timestamps():
    X = np.random.default_rng(0).random((20, 16))
    t = np.cumsum(np.random.default_rng(1).uniform(0.1, 3.0, 20))
    trained = train_detector(novelty.make("hsom"), X, timestamps=t)
    streamed = novelty.make("hsom")
    streamed.stream(X, timestamps=t)
    np.testing.assert_array_equal(trained.novelty(X), streamed.novelty(X))
    untimed = train_detector(novelty.make("hsom"), X)
    assert not np.array_equal(untimed.novelty(X), trained.novelty(X))


# ---------------------------------------------------------------- the input a detector reads
class _Task:
    def __init__(self, metadata):
        self.metadata = metadata


@pytest.mark.parametrize("metadata", [
    {"inputs": "points"},                                                   # a task given inputs="points"
    {"columns": ["x", "y", "heading", "near_0", "end_x_0", "end_y_0"]},     # rows that name their columns
    {"sensor_columns": ["x", "y", "heading", "a", "b", "c"]},               # the user's own file
])
def test_a_map_takes_rows_that_say_they_are_the_points_input(metadata):
    check_input_layout(novelty.make("map-explore"), _Task(metadata), "mine")


@pytest.mark.parametrize("metadata, said", [
    ({}, "rows that do not say what they are"),                              # the UCI sonar's 60 values
    ({"inputs": "ring"}, "rows of the 'ring' input"),
    ({"sensor_columns": ["band_0", "band_1", "band_2"]}, "rows that do not say what they are"),
])
def test_a_map_refuses_rows_that_are_not_the_points_input(metadata, said):
    with pytest.raises(CellError, match=f"HabituatingMap reads rows of the 'points' input.*task 'mine' gives {said}"):
        check_input_layout(novelty.make("map-explore"), _Task(metadata), "mine")


def test_a_detector_that_states_no_input_takes_any_rows():
    check_input_layout(novelty.make("hsom"), _Task({}), "mine")


def test_a_benchmark_of_a_map_on_rows_without_poses_fails_the_cell_and_says_why():
    X = np.random.default_rng(0).random((40, 60))   # 3 + 3 x 19 columns: a map would read them as points
    task = Dataset("bands", X, y=np.r_[np.zeros(30), np.ones(10)].astype(int),
                   split=np.array(["train"] * 20 + ["test"] * 20))
    (row,) = novelty.bench.run(["map-explore"], task, seeds=1).rows
    assert row["status"] == "error" and "reads rows of the 'points' input" in row["error"]
    points = dataclasses.replace(task, metadata={**task.metadata, "inputs": "points"})
    (row,) = novelty.bench.run(["map-explore"], points, seeds=1).rows
    assert row["status"] == "ok"
