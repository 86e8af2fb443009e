"""Online k-means by hand: running means, or a constant learning rate."""

import numpy as np

from novelty.clusterers.kmeans import OnlineKMeans


def test_online_kmeans_by_hand():
    km = OnlineKMeans(n_clusters=2).initialize(np.array([[0.0, 0.0], [1.0, 1.0]]), random_state=0)
    km.weights_[:] = [[0.0, 0.0], [1.0, 1.0]]
    for x in ([0.5, 0.0], [1.0, 0.5], [0.25, 0.5]):
        m, growth = km.learn_one(np.array(x))
        assert m.neighbours.size == 0 and growth.added == 0
    np.testing.assert_allclose(km.weights_, [[0.25, 0.5 / 3], [1.0, 0.75]])   # running means
    np.testing.assert_array_equal(km.counts_, [3, 2])
    const = OnlineKMeans(n_clusters=1, learning_rate=0.5).initialize(np.zeros((1, 1)))
    const.learn_one(np.ones(1))
    const.learn_one(np.ones(1))
    np.testing.assert_array_equal(const.weights_, [[0.75]])
