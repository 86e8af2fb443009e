"""The lane-wise helpers (novelty._kernels._lanes) against the scalar arithmetic they replace, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from novelty import _kernels
from novelty.clusterers.base import move_towards

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@pytest.fixture(scope="module")
def helpers():
    """The inlined helpers, compiled alone for the test."""
    from numba import njit

    from novelty._kernels._lanes import difference, minus_one, move_four

    @njit
    def move(WT, f, j0, x, rates, count):
        move_four(WT, f, j0, x, rates[0], rates[1], rates[2], rates[3], count)

    @njit
    def differences(w, x):
        minus = minus_one()
        out = np.empty_like(w)
        for j in range(w.size):  # a loop, vectorised as in the distances
            out[j] = difference(w[j], x[j], minus)
        return out

    return move, differences


_values = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=100, deadline=None)
@given(W=hnp.arrays(np.float64, (3, 9), elements=_values), x=_values,
       rates=hnp.arrays(np.float64, 4, elements=st.floats(0, 1)), f=st.integers(0, 2),
       j0=st.integers(0, 5), count=st.integers(0, 4))
def test_move_four_moves_the_counted_lanes_as_move_towards(helpers, W, x, rates, f, j0, count):
    move, _ = helpers
    want = W.copy()
    for q in range(count):
        want[f, j0 + q] = move_towards(want[f, j0 + q], x, rates[q])
    move(W, f, j0, x, rates, count)
    assert np.array_equal(W.view(np.int64), want.view(np.int64))


def test_difference_is_the_subtraction_bit_for_bit(helpers):
    """Signed zeros, subnormals, the largest floats (their difference overflows) and inf, every
    pair, and random values: ``fma(x, -1, w)`` rounds as ``w - x``."""
    _, differences = helpers
    special = np.array([0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.0, -1.0,
                        np.nextafter(1.0, 2.0), 1 / 3, 1e308, -1e308, np.inf, -np.inf])
    w, x = np.repeat(special, special.size), np.tile(special, special.size)
    rng = np.random.default_rng(0)
    w = np.concatenate([w, rng.normal(0, 1, 1000), rng.uniform(0, 1, 1000) * 10.0 ** rng.integers(-300, 300, 1000)])
    x = np.concatenate([x, rng.normal(0, 1, 1000), rng.uniform(0, 1, 1000) * 10.0 ** rng.integers(-300, 300, 1000)])
    with np.errstate(over="ignore", invalid="ignore"):
        want = w - x
    assert np.array_equal(differences(w, x).view(np.int64), want.view(np.int64))
