"""The project's squared-distance order (novelty.distances), against an independent emulation.

The emulation does the documented operations in exact rational arithmetic
(:class:`fractions.Fraction`), rounding each result to the nearest float64
as IEEE-754 does: it uses no numpy sum, so a change in how numpy sums cannot
change what it expects. The readable function, the learning drivers and batch
scoring must all give its bits.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from novelty import _kernels, registry
from novelty.distances import squared_distances

from ._kernels.kernel_helpers import both, kernel_learn, reference_learn

FEATURES = [1, 3, 7, 8, 9, 15, 16, 17, 24, 31, 64, 128, 129, 200, 300]


def _rounded(q: Fraction) -> Fraction:
    return Fraction(float(q))  # float(Fraction) rounds to nearest, ties to even


def emulated(w, x) -> float:
    """The documented order, each operation rounded once (module docstring of novelty.distances)."""
    q = [_rounded(_rounded(Fraction(a) - Fraction(b)) ** 2) for a, b in zip(w, x)]
    n = len(q)
    if n < 8:
        total = q[0]
        for v in q[1:]:
            total = _rounded(total + v)
        return float(total)
    end = n - n % 8
    sums = list(q[:8])
    for k in range(8, end):
        sums[k % 8] = _rounded(sums[k % 8] + q[k])
    pairs = [_rounded(sums[i] + sums[i + 1]) for i in range(0, 8, 2)]
    total = _rounded(_rounded(pairs[0] + pairs[1]) + _rounded(pairs[2] + pairs[3]))
    for v in q[end:]:
        total = _rounded(total + v)
    return float(total)


def _data(n_features: int, n_rows: int = 12, seed: int = 0):
    rng = np.random.default_rng(seed * 1000 + n_features)
    scale = rng.choice([1e-3, 1.0, 1e3], (n_rows, n_features))
    return rng.uniform(-1, 1, (n_rows, n_features)) * scale, rng.uniform(-1, 1, n_features)


@pytest.mark.parametrize("n_features", FEATURES)
def test_the_readable_function_follows_the_documented_order(n_features):
    W, x = _data(n_features)
    expected = np.array([emulated(w, x) for w in W])
    np.testing.assert_array_equal(squared_distances(W, x), expected)
    assert float(squared_distances(W[0], x)) == expected[0]  # two vectors: one distance


def test_batches_of_rows_and_hand_computed_values():
    assert float(squared_distances(np.array([3.0, 0.0]), np.array([0.0, 4.0]))) == 25.0
    # nine features: eight running sums of one square each, then the ninth added last
    assert float(squared_distances(np.arange(9.0), np.zeros(9))) == float(sum(k * k for k in range(9)))
    X, W = np.random.default_rng(1).uniform(size=(5, 20)), np.random.default_rng(2).uniform(size=(5, 20))
    np.testing.assert_array_equal(squared_distances(X, W),
                                  [float(squared_distances(a, b)) for a, b in zip(X, W)])


@pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")
@pytest.mark.parametrize("n_features", FEATURES)
def test_the_compiled_paths_follow_the_documented_order(n_features):
    X, _ = _data(n_features, n_rows=30, seed=1)
    clusterer = registry.clusterers.make("online-kmeans", n_clusters=7).initialize(X, 0)
    synapse = registry.synapses.make("stanley").initialize(7)
    W = clusterer.weights_.copy()
    # batch scoring, on the weights as they are
    score = _kernels.scorer(clusterer, synapse)
    rows, dist = np.empty(len(X), dtype=np.int64), np.empty(len(X))
    score(clusterer, synapse, X, rows, dist)
    np.testing.assert_array_equal(dist, [emulated(W[j], x) for j, x in zip(rows, X)])
    # learning: the first scan's distances are to the initial weights
    (fast_c, fast_s), (slow_c, slow_s) = both(clusterer, synapse)
    d_fast, d_slow = np.empty(len(X)), np.empty(len(X))
    reference_learn(slow_c, slow_s, X, np.ones(len(X)), 1.0, d_slow)
    _, winners = kernel_learn(fast_c, fast_s, X, np.ones(len(X)), 1.0, d_fast)
    np.testing.assert_array_equal(d_fast, d_slow)
    assert d_fast[0] == emulated(W[winners[0]], X[0])
