"""The grid walk: hand-computed rays, its properties, exact rational arithmetic, and the numpy form of many rays.

On dyadic coordinates (multiples of 1/16 within +-64, cells of 1/2 or 1/4 m)
every difference in equation (1) is exact and the crossings' ``t`` differ by far
more than a rounding when they differ at all, so the float walk must be the
exact one, crossing by crossing.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.maps.grid_walk import walk_cells, walk_length, walk_lengths, walk_rays


# ------------------------------------------------------------------ by hand
@pytest.mark.parametrize("start, end, cells", [
    # along a corridor of 0.5 m cells, right then left
    ((0.1, 0.2), (1.4, 0.2), [(0, 0), (1, 0), (2, 0)]),
    ((1.4, 0.2), (0.1, 0.2), [(2, 0), (1, 0), (0, 0)]),
    # negative coordinates: floor, not truncation
    ((-0.1, -0.1), (-1.2, -0.3), [(-1, -1), (-2, -1), (-3, -1)]),
    ((-0.2, 0.2), (0.2, -0.2), [(-1, 0), (0, 0), (0, -1)]),             # through the origin: x first
    # a ray along a boundary line lies in the cells above it (half-open cells)
    ((0.25, 0.5), (1.75, 0.5), [(0, 1), (1, 1), (2, 1), (3, 1)]),
    ((1.75, 0.5), (0.25, 0.5), [(3, 1), (2, 1), (1, 1), (0, 1)]),
    ((0.5, 0.25), (0.5, -0.8), [(1, 0), (1, -1), (1, -2)]),
    # a diagonal through corners: the vertical side first, so the corner's own cell is visited
    ((0.25, 0.25), (1.25, 1.25), [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2)]),
    ((1.25, 1.25), (0.25, 0.25), [(2, 2), (1, 2), (1, 1), (0, 1), (0, 0)]),
    # ... unless it goes left and up: the corner's own cell lies up, on the right of the vertical side
    ((0.25, 0.25), (-0.75, 1.25), [(0, 0), (0, 1), (-1, 1), (-1, 2), (-2, 2)]),
    # length zero, and a ray inside one cell
    ((0.3, 0.3), (0.3, 0.3), [(0, 0)]),
    ((0.1, 0.1), (0.4, 0.2), [(0, 0)]),
])
def test_hand_computed_rays_of_half_metre_cells(start, end, cells):
    assert walk_cells(start, end, 0.5).tolist() == [list(c) for c in cells]
    assert walk_length(*start, *end, 0.5) == len(cells)


def test_a_start_on_a_boundary_stepping_back_leaves_its_cell_at_once():
    # x = 0.5 lies in cell 1; stepping left the ray meets the boundary x = 0.5 at t = 0
    assert walk_cells((0.5, 0.1), (0.2, 0.1), 0.5).tolist() == [[1, 0], [0, 0]]


def test_a_shallow_ray_over_ten_metres_of_ten_centimetre_cells():
    # y rises 0.1 m over 10 m: one horizontal crossing, at x = 5.05 (y = 0.1 at t = 0.5)
    cells = walk_cells((0.05, 0.05), (10.05, 0.15), 0.1)
    assert len(cells) == 102
    assert cells[50].tolist() == [50, 0] and cells[51].tolist() == [50, 1]
    assert cells[-1].tolist() == [100, 1]


# ------------------------------------------------------------------ exact arithmetic
def exact_walk(x0, y0, x1, y1, c):
    """The traversal in rational arithmetic: the crossings sorted by their exact t; on a tie, the one crossed
    upwards or rightwards first (the vertical one when both are crossed the same way)."""
    x0, y0, x1, y1, c = map(Fraction, (x0, y0, x1, y1, c))
    i, j = x0 // c, y0 // c
    events = []
    for axis, (a0, a1, k0) in enumerate(((x0, x1, i), (y0, y1, j))):
        k1 = a1 // c
        step = 1 if k1 > k0 else -1
        for k in range(int(abs(k1 - k0))):
            cell = k0 + step * k
            boundary = (cell + (step > 0)) * c
            events.append(((boundary - a0) / (a1 - a0), axis, step))
    left_and_up = x1 < x0 and y1 > y0
    cells = [(int(i), int(j))]
    for _, axis, step in sorted(events, key=lambda e: (e[0], e[1] ^ left_and_up)):
        i, j = (i + step, j) if axis == 0 else (i, j + step)
        cells.append((int(i), int(j)))
    return cells


dyadic = st.integers(-1024, 1024).map(lambda k: k / 16)


@settings(max_examples=400, deadline=None)
@given(dyadic, dyadic, dyadic, dyadic, st.sampled_from([0.25, 0.5, 1.0]))
def test_on_dyadic_coordinates_the_walk_is_the_exact_one(x0, y0, x1, y1, c):
    assert [tuple(cell) for cell in walk_cells((x0, y0), (x1, y1), c).tolist()] == exact_walk(x0, y0, x1, y1, c)


@settings(max_examples=300, deadline=None)
@given(dyadic, dyadic, dyadic, dyadic, st.sampled_from([0.25, 0.5]))
def test_every_point_of_the_ray_lies_in_a_cell_of_the_walk_and_every_cell_touches_the_ray(x0, y0, x1, y1, c):
    cells = {tuple(cell) for cell in walk_cells((x0, y0), (x1, y1), c).tolist()}
    p0, p1, size = (Fraction(x0), Fraction(y0)), (Fraction(x1), Fraction(y1)), Fraction(c)
    for k in range(65):
        t = Fraction(k, 64)
        point = [a + t * (b - a) for a, b in zip(p0, p1)]
        assert (int(point[0] // size), int(point[1] // size)) in cells
    for i, j in cells:   # the closed square meets the closed segment (Liang & Barsky's clipping)
        low, high = Fraction(0), Fraction(1)
        for a, b, k in ((p0[0], p1[0], i), (p0[1], p1[1], j)):
            d = b - a
            lo, hi = k * size, (k + 1) * size
            if d == 0:
                assert lo <= a <= hi
                continue
            t0, t1 = sorted(((lo - a) / d, (hi - a) / d))
            low, high = max(low, t0), min(high, t1)
        assert low <= high, f"cell {(i, j)} does not touch the ray"


# ------------------------------------------------------------------ any floats
coordinate = st.one_of(
    st.floats(-50, 50, allow_nan=False, allow_infinity=False),
    st.integers(-500, 500).map(lambda k: k * 0.1),         # on a boundary, as 0.1 m cells put it
    st.integers(-40, 40).map(lambda k: k * 0.25))


@settings(max_examples=300, deadline=None)
@given(coordinate, coordinate, coordinate, coordinate, st.sampled_from([0.1, 0.2, 0.25, 1.0]))
def test_the_walk_steps_by_one_side_from_the_start_cell_to_the_end_cell(x0, y0, x1, y1, c):
    cells = walk_cells((x0, y0), (x1, y1), c)
    assert cells[0].tolist() == [np.floor(x0 / c), np.floor(y0 / c)]
    assert cells[-1].tolist() == [np.floor(x1 / c), np.floor(y1 / c)]
    steps = np.diff(cells, axis=0)
    assert np.all(np.abs(steps).sum(axis=1) == 1)
    # never back: each axis moves only the way the ray goes
    assert np.all(steps[:, 0] * np.sign(x1 - x0) >= 0) and np.all(steps[:, 1] * np.sign(y1 - y0) >= 0)


rays = st.lists(st.tuples(coordinate, coordinate, coordinate, coordinate), min_size=1, max_size=8)


@settings(max_examples=300, deadline=None)
@given(rays, st.sampled_from([0.1, 0.2, 0.5]))
def test_the_rays_at_once_are_the_rays_one_by_one(segments, c):
    starts, ends = np.array([s[:2] for s in segments]), np.array([s[2:] for s in segments])
    cells, offsets = walk_rays(starts, ends, c)
    assert np.diff(offsets).tolist() == walk_lengths(starts, ends, c).tolist()
    for r, (start, end) in enumerate(zip(starts, ends)):
        np.testing.assert_array_equal(cells[offsets[r]:offsets[r + 1]], walk_cells(start, end, c))


def test_no_rays():
    cells, offsets = walk_rays(np.empty((0, 2)), np.empty((0, 2)), 0.1)
    assert cells.shape == (0, 2) and offsets.tolist() == [0]
