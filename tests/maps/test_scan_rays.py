"""A scan's rays by hand, and the compiled rays against the function run as Python."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty._jit import compiled
from novelty.maps import grid_kernels as kernels
from novelty.maps.scan_rays import _sorted_turn, cone_rays, ray_count, scan_rays, sector_width


def rays(x, y, near, ex, ey, arc=0.0, c=1.0, max_range=10.0, margin=1.0, run=scan_rays):
    near, ex, ey = (np.asarray(v, dtype=np.float64) for v in (near, ex, ey))
    n = ray_count(x, y, ex, ey, arc, c, max_range)
    out = [np.empty(n, dtype=np.bool_)] + [np.empty(n) for _ in range(4)]
    m, cut = run(x, y, near, ex, ey, arc, c, max_range, margin, *out)
    assert m == n
    return cut, *out


def test_each_sector_is_a_ray_to_its_end_point_its_free_stretch_a_margin_short_of_an_echo():
    cut, hit, ex, ey, fx, fy = rays(0.0, 0.0, [0.5, 0.0, 0.5], [3.0, 0.0, 0.5], [0.0, 4.0, 0.0])
    assert cut == 0 and hit.tolist() == [True, False, True]
    assert ex.tolist() == [3.0, 0.0, 0.5] and ey.tolist() == [0.0, 4.0, 0.0]
    # 3 m with an echo: free to 2 m; no echo: free all 4 m; an echo 0.5 m away: no free stretch
    assert fx[:2].tolist() == [2.0, 0.0] and fy[:2].tolist() == [0.0, 4.0] and math.isnan(fx[2])


def test_a_sector_beyond_max_range_is_cut_to_it_and_read_as_no_echo():
    cut, hit, ex, ey, fx, fy = rays(1.0, 1.0, [0.5, 0.5], [31.0, 1.0], [1.0, 4.0], max_range=10.0)
    assert cut == 1 and hit.tolist() == [False, True]
    assert (ex[0], ey[0], fx[0], fy[0]) == (11.0, 1.0, 11.0, 1.0)


def test_a_cone_is_read_as_rays_half_a_cell_apart_at_its_longest_sector():
    # 0.4 rad, 2 m, cells of 1 m: 1 + ceil(0.4 * 2 / 0.5) = 3 rays at -0.2, 0, 0.2 rad
    assert cone_rays(0.4, 2.0, 1.0) == 3 and cone_rays(0.0, 2.0, 1.0) == 1
    cut, hit, ex, ey, fx, fy = rays(0.0, 0.0, [0.5], [2.0], [0.0], arc=0.4)
    angles = [-0.2, 0.0, 0.2]
    np.testing.assert_allclose(ex, [2 * math.cos(a) for a in angles], rtol=1e-15)
    np.testing.assert_allclose(ey, [2 * math.sin(a) for a in angles], rtol=0, atol=1e-15)
    np.testing.assert_allclose(fx, [math.cos(a) for a in angles], rtol=1e-15)
    assert hit.tolist() == [True] * 3


def test_a_negative_arc_reads_each_sector_as_wide_as_the_angle_it_stands_for():
    ex, ey = np.array([1.0, 0.0, -2.0, 0.0]), np.array([0.0, 1.0, 0.0, -1.0])
    assert sector_width(0.0, 0.0, ex, ey) == math.pi / 2
    assert ray_count(0.0, 0.0, ex, ey, -1.0, 1.0, 10.0) == 4 * (1 + math.ceil(math.pi / 2 * 2.0 / 0.5))
    # one sector, or end points at the robot: no width
    assert sector_width(0.0, 0.0, np.array([1.0, 0.0]), np.array([0.0, 0.0])) == 0.0


coordinate = st.floats(-20, 20, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 1), coordinate, coordinate), min_size=1, max_size=12), coordinate, coordinate,
       st.sampled_from([0.0, 0.3, -1.0]), st.sampled_from([0.1, 0.5]), st.sampled_from([5.0, 40.0]))
def test_the_compiled_rays_are_the_rays_of_python(sectors, x, y, arc, c, max_range):
    near, ex, ey = (np.array(v) for v in zip(*sectors))
    python = rays(x, y, near, ex, ey, arc, c, max_range, c)
    compiled = rays(x, y, near, ex, ey, arc, c, max_range, c, run=kernels.rays)
    assert python[0] == compiled[0]
    for a, b in zip(python[1:], compiled[1:]):
        if np.asarray(a).dtype.kind == "f":
            # cos and sin compiled by LLVM and CPython's libm may round the last place apart on some CPUs
            # (seen once in 258 values on CI): the reals agree to that place, everything else exactly
            np.testing.assert_allclose(a, b, rtol=4e-16, atol=1e-13)
        else:
            np.testing.assert_array_equal(a, b)
    assert kernels.ray_count(x, y, ex, ey, arc, c, max_range) == ray_count(x, y, ex, ey, arc, c, max_range)


compiled_turn = compiled(_sorted_turn)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-math.pi, math.pi), min_size=1, max_size=40), st.integers(0, 39),
       st.sampled_from(["sorted", "turned", "as drawn"]))
def test_bearings_are_sorted_as_numpy_sorts_them_whether_in_order_turned_or_not(values, at, how):
    a = np.array(values)
    if how != "as drawn":
        a = np.sort(a)
    if how == "turned":
        a = np.concatenate([a[at % a.size:], a[:at % a.size]])
    expected = np.sort(a)
    assert _sorted_turn(a.copy()).tolist() == expected.tolist()
    assert compiled_turn(a.copy()).tolist() == expected.tolist()
