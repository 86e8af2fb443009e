"""The compiled grid walk against its plain-Python run: the same cells, in the same order, for any ray; a scan's
bounds against its cells counted."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.maps.grid_kernels import length, scan_bounds, scan_sizes, walk
from novelty.maps.grid_walk import walk_cells, walk_length
from novelty.maps.scan_rays import sector_width

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


def scan_rows(rng, n_rows, sectors, reach):
    """Rows of the points input about a wandering pose, far from the origin or across it."""
    pose = np.c_[rng.uniform(-1, 1, (n_rows, 2)) * rng.choice([1.0, 1e5]), rng.uniform(-4, 4, n_rows)]
    bearings = pose[:, 2:3] + np.linspace(-np.pi / 2, np.pi / 2, sectors)
    r = rng.uniform(0.0, reach, (n_rows, sectors))
    near = np.where(rng.random((n_rows, sectors)) < 0.8, rng.uniform(0.01, 1, (n_rows, sectors)), 0.0)
    return np.c_[pose, near, pose[:, :1] + r * np.cos(bearings), pose[:, 1:2] + r * np.sin(bearings)]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([1, 7, 180]), st.sampled_from([0.03, 0.1, 0.2]),
       st.sampled_from([-1.0, 0.0, 0.05]), st.sampled_from([0.5, 4.0, 30.0]))
def test_a_scans_bound_is_never_below_its_cells_and_is_their_count_where_it_exceeds_most(seed, sectors, c, arc,
                                                                                          reach):
    X = scan_rows(np.random.default_rng(seed), 5, sectors, reach)
    exact, bound, widths = np.empty(5, dtype=np.int64), np.empty(5, dtype=np.int64), np.empty(5)
    longest, cut = scan_sizes(X, sectors, c, 20.0, arc, c, 10**9, exact)
    rays, longest_bound, cut_bound = scan_bounds(X, sectors, c, 20.0, arc, c, 10**9, bound, widths)
    assert np.all(bound >= exact) and longest_bound >= longest and cut_bound == cut
    n = 3 + sectors
    expected = [sector_width(x[0], x[1], x[n:n + sectors], x[n + sectors:]) if arc < 0 else arc for x in X]
    assert widths.tolist() == expected
    most = int(exact.min())   # a row over it is counted exactly, as scan_sizes counts it
    over, count = np.empty(5, dtype=np.int64), np.empty(5, dtype=np.int64)
    scan_bounds(X, sectors, c, 20.0, arc, c, most, over, widths)
    scan_sizes(X, sectors, c, 20.0, arc, c, most, count)
    assert np.all((over == count) | (over <= most)) and np.all((over > most) == (count > most))
