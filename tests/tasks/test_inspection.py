"""The inspection tasks: objects inserted into a simulated corridor, labelled around where they lie."""

import numpy as np
import pytest

from novelty import datasets


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
