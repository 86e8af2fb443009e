"""Four weights moved in one vector (novelty._kernels._lanes) as the scalar arithmetic moves them, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from novelty import _kernels
from novelty.clusterers.base import move_towards

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@pytest.fixture(scope="module", params=["vector", "plain"])
def move(request):
    """The inlined helper (the vector, and its plain twin), compiled alone for the test."""
    from numba import njit

    from novelty._kernels import _lanes

    helper = _lanes.move_four_vector if request.param == "vector" else _lanes.move_four_plain

    @njit
    def move(WT, f, j0, x, rates, count):
        helper(WT, f, j0, x, rates[0], rates[1], rates[2], rates[3], count)

    return move


_values = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=100, deadline=None)
@given(W=hnp.arrays(np.float64, (3, 9), elements=_values), x=_values,
       rates=hnp.arrays(np.float64, 4, elements=st.floats(0, 1)), f=st.integers(0, 2),
       j0=st.integers(0, 5), count=st.integers(0, 4))
def test_move_four_moves_the_counted_lanes_as_move_towards(move, W, x, rates, f, j0, count):
    want = W.copy()
    for q in range(count):
        want[f, j0 + q] = move_towards(want[f, j0 + q], x, rates[q])
    move(W, f, j0, x, rates, count)
    assert np.array_equal(W.view(np.int64), want.view(np.int64))
