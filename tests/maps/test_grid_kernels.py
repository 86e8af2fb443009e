"""The compiled grid walk against its plain-Python run: the same cells, in the same order, for any ray."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.maps.grid_kernels import length, walk
from novelty.maps.grid_walk import walk_cells, walk_length

coordinate = st.one_of(
    st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False),
    st.integers(-500, 500).map(lambda k: k * 0.1),          # on boundaries of 0.1 m cells, as written
    st.integers(-40, 40).map(lambda k: k * 0.25),           # exactly on boundaries, corners included
    st.floats(-1e-3, 1e-3, allow_nan=False))                # about the origin, negative zero included


def compiled_cells(x0, y0, x1, y1, c):
    out = np.full((length(x0, y0, x1, y1, c) + 1, 2), -7, dtype=np.int64)
    n = walk(x0, y0, x1, y1, c, out)
    assert out[n:].tolist() == [[-7, -7]] * (out.shape[0] - n)   # nothing written past the walk
    return out[:n]


@settings(max_examples=1000, deadline=None)
@given(coordinate, coordinate, coordinate, coordinate, st.sampled_from([0.05, 0.1, 0.2, 0.25, 1.0]))
def test_the_compiled_walk_is_the_reference_walk(x0, y0, x1, y1, c):
    expected = walk_cells((x0, y0), (x1, y1), c)
    np.testing.assert_array_equal(compiled_cells(x0, y0, x1, y1, c), expected)
    assert length(x0, y0, x1, y1, c) == walk_length(x0, y0, x1, y1, c) == len(expected)


@given(coordinate, coordinate, st.sampled_from([0.1, 0.25]))
def test_a_ray_of_length_zero_is_its_cell(x, y, c):
    np.testing.assert_array_equal(compiled_cells(x, y, x, y, c), [[np.floor(x / c), np.floor(y / c)]])


def test_a_ray_of_a_kilometre_visits_its_ten_thousand_cells_once_each():
    cells = compiled_cells(0.05, 0.05, 1000.05, 0.05, 0.1)
    assert len(cells) == 10001 and len({tuple(c) for c in cells.tolist()}) == 10001
