"""The compiled distance helpers (novelty._kernels._distances) against numpy, exactly."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from novelty import _kernels

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@pytest.fixture(scope="module")
def first_least():
    """The inlined helper, compiled alone for the test."""
    from numba import njit

    from novelty._kernels._distances import first_least as helper

    return njit(lambda d, n: helper(d, n))


# squared distances: non-negative, subnormal to huge, +inf (a unit proven farther), repeated
_distances = st.one_of(st.sampled_from([0.0, 5e-324, 1e-300, 1.0, np.nextafter(1.0, 2.0), 1e300,
                                        np.inf]),
                       st.floats(0, 1e308, allow_nan=False))


@settings(max_examples=300, deadline=None)
@given(d=hnp.arrays(np.float64, st.integers(1, 150), elements=_distances), data=st.data())
def test_first_least_is_argmin(first_least, d, data):
    """The first index of the least value, as ``np.argmin``, over any prefix ``d[:n]``."""
    n = data.draw(st.integers(1, len(d)))
    assert first_least(d, n) == np.argmin(d[:n])


def test_first_least_takes_the_first_of_equal_values(first_least):
    d = np.array([3.0, 1.0, 2.0, 1.0, 1.0, 0.5, 0.5])
    assert first_least(d, 5) == 1
    assert first_least(d, 7) == 5
    assert first_least(np.full(33, np.inf), 33) == 0
    d = np.full(100, 2.0)
    d[[70, 90]] = 1.0
    assert first_least(d, 100) == 70 and first_least(d, 80) == 70 and first_least(d, 70) == 0


@pytest.fixture(scope="module")
def distances():
    """``distances_cols`` on a transposed copy with zero columns of room (compiled alone)."""
    from numba import njit

    from novelty._kernels._distances import distances_cols

    @njit
    def run(WT, n, x):
        out = np.full(WT.shape[1], -1.0)
        distances_cols(WT, x, np.empty((8, WT.shape[1])), out, n)
        return out

    return run


@pytest.mark.parametrize("n_features", [3, 9, 16, 20, 30])
@pytest.mark.parametrize("n_units", [1, 7, 8, 13, 100])
def test_distances_over_whole_vectors_equal_the_readable_order(distances, n_features, n_units):
    """The units' distances in the project's order, whether the loop runs past them into the room
    (whole vectors of columns, as the engine holds them) or not (no room)."""
    from novelty._kernels._distances import VECTOR
    from novelty.distances import squared_distances

    rng = np.random.default_rng(n_units * 100 + n_features)
    W, x = rng.normal(0, 1, (n_units, n_features)), rng.normal(0, 1, n_features)
    for columns in (n_units, n_units + (-n_units) % VECTOR + VECTOR):
        WT = np.zeros((n_features, columns))
        WT[:, :n_units] = W.T
        out = distances(WT, n_units, x)
        assert np.array_equal(out[:n_units], squared_distances(W, x))
