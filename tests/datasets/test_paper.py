"""The registered simulated datasets and tasks."""

import numpy as np
import pytest

from novelty import datasets
from novelty.registry import InvalidParameterError

PAPER = ["paper-a", "paper-a-star", "paper-b", "paper-c", "paper-control"]


def test_every_builtin_is_listed_with_a_description():
    names = datasets.available()
    for name in PAPER + ["paper-a-to-a-star", "paper-a-to-b", "paper-a-to-c", "inspection",
                         "inspection-easy", "inspection-medium", "inspection-hard",
                         "uci-wall-following", "uci-wall-following-novelty", "uci-sonar",
                         "uci-sonar-mines"]:
        assert names[name]


def test_paper_environment_loads_by_run_and_seed():
    ds = datasets.load("paper-a", run=2, seed=1)
    assert ds.X.shape == (100, 16)
    assert ds.metadata["map"] == "a" and ds.metadata["runs"] == [2]
    np.testing.assert_array_equal(ds.X, datasets.load("paper-a", run=2, seed=1).X)
    assert not np.array_equal(ds.X, datasets.load("paper-a", run=3, seed=1).X)
    two = datasets.load("paper-c", runs=2)
    assert two.run.tolist() == [0] * 100 + [1] * 100


def test_unknown_parameter_is_refused_with_the_valid_ones():
    with pytest.raises(InvalidParameterError, match="Valid parameters: run, runs, seed"):
        datasets.load("paper-b", rnu=1)


def test_a_to_a_star_labels_lie_around_the_opened_door():
    task = datasets.load("paper-a-to-a-star", seed=0, train_runs=2)
    assert task.metadata["train_passes"] == 1 and task.metadata["train_runs"] == 2
    train, test = task.train(), task.test()
    assert len(train) == 200 and len(test) == 100
    assert train.y.sum() == 0
    novel = test.distance[test.y == 1]
    assert 5 <= novel.size <= 30
    assert np.abs(novel - 3.0).max() < 1.6  # the 0.9 m doorway and about a metre either side


def test_inspection_labels_lie_around_the_inserted_objects():
    for difficulty in ("easy", "medium", "hard"):
        task = datasets.load(f"inspection-{difficulty}", seed=1)
        test = task.test()
        positions = np.array([n["position"] for n in task.metadata["novelties"]])
        assert len(positions) == 2 and np.all(np.diff(np.sort(positions)) >= 3.0)
        assert test.y.sum() > 0
        gap = np.abs(test.distance[test.y == 1][:, None] - positions[None, :]).min(axis=1)
        # an object's half-width plus the 2 m salient range plus the ring's reach
        assert gap.max() < 3.0
        assert task.train().y.sum() == 0
        assert all(n["inserted"] for n in task.metadata["novelties"])


def test_inspection_is_deterministic_and_seeds_differ():
    one = datasets.load("inspection", seed=4, difficulty="medium", train_runs=1)
    two = datasets.load("inspection", seed=4, difficulty="medium", train_runs=1)
    np.testing.assert_array_equal(one.X, two.X)
    np.testing.assert_array_equal(one.y, two.y)
    other = datasets.load("inspection", seed=5, difficulty="medium", train_runs=1)
    assert one.metadata["corridor"] != other.metadata["corridor"]


def test_easy_novelties_are_perceived_on_more_scans_than_hard_ones():
    easy = np.mean([datasets.load("inspection-easy", seed=s, train_runs=1).test().y.mean()
                    for s in range(3)])
    hard = np.mean([datasets.load("inspection-hard", seed=s, train_runs=1).test().y.mean()
                    for s in range(3)])
    assert easy > hard


def test_inspection_refuses_unknown_difficulty():
    with pytest.raises(ValueError, match="difficulty"):
        datasets.load("inspection", difficulty="extreme")
