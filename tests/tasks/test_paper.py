"""The paper's simulated environments and the tasks built from them."""

import numpy as np

from novelty import datasets


def test_paper_environment_loads_by_run_and_seed():
    ds = datasets.load("paper-a", run=2, seed=1)
    assert ds.X.shape == (100, 16)
    assert ds.metadata["map"] == "a" and ds.metadata["runs"] == [2]
    np.testing.assert_array_equal(ds.X, datasets.load("paper-a", run=2, seed=1).X)
    assert not np.array_equal(ds.X, datasets.load("paper-a", run=3, seed=1).X)
    two = datasets.load("paper-c", runs=2)
    assert two.run.tolist() == [0] * 100 + [1] * 100


def test_a_to_a_star_labels_lie_around_the_opened_door():
    task = datasets.load("paper-a-to-a-star", seed=0, train_runs=2)
    assert task.metadata["train_passes"] == 1 and task.metadata["train_runs"] == 2
    train, test = task.train(), task.test()
    assert len(train) == 200 and len(test) == 100
    assert train.y.sum() == 0
    novel = test.distance[test.y == 1]
    assert 5 <= novel.size <= 30
    assert np.abs(novel - 3.0).max() < 1.6  # the 0.9 m doorway and about a metre either side
