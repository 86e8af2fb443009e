"""The SOM distance detector: the distance to the best-matching unit, learnt online, with any clusterer."""

import numpy as np
import pytest

import novelty
from novelty.baselines import SOMDistance
from novelty.clusterers.som import SOM


def test_som_distance_is_the_distance_to_the_best_matching_unit(blobs, far):
    det = SOMDistance(clusterer=SOM(n_rows=3, n_columns=3, init="sample")).fit(blobs)
    assert isinstance(det.clusterer_, SOM)
    W = det.clusterer_.weights_
    X = np.vstack([blobs[::11], far])
    expected = np.sqrt(((X[:, None, :] - W[None]) ** 2).sum(axis=2).min(axis=1))
    assert np.allclose(det.raw_novelty(X), expected, rtol=1e-10)


def test_som_distance_learns_online_before_scoring():
    det = SOMDistance(clusterer=SOM(n_rows=1, n_columns=1, learning_rate=0.5, init="uniform",
                                    init_range=(0.0, 1e-12)))
    assert det.score_learn_one([1.0, 0.0]) == 1.0  # first scan of a stream: fully novel
    assert det.raw_novelty([[1.0, 0.0]])[0] == pytest.approx(0.5, abs=1e-9)  # the unit moved half way
    det.learn_one([1.0, 0.0])
    assert det.raw_novelty([[1.0, 0.0]])[0] == pytest.approx(0.25, abs=1e-9)


def test_som_distance_takes_any_clusterer_by_name(blobs, far):
    det = SOMDistance(clusterer="gng", n_epochs=2).fit(blobs)
    assert novelty.registry.clusterers.name_of(det.clusterer_) == "gng"
    assert det.raw_novelty(far)[0] > det.raw_novelty(blobs).max()
