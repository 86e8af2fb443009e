"""One benchmark cell: training as the robot does, with the task's timestamps."""

import numpy as np

import novelty
from novelty.bench.build import train_detector


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
