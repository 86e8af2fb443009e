"""Boxes, cylinders and walls: entry distances, nearest points and depths computed by hand."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.tasks.objects.shapes import Box, Cylinder, Wall


def test_a_ray_enters_an_upright_box_at_its_near_face():
    box = Box("crate", x=3.0, y=0.0, length=1.0, width=2.0)     # x in [2.5, 3.5], y in [-1, 1]
    origins = [[0.0, 0.0], [0.0, 0.9], [0.0, 1.1], [3.0, 0.0], [5.0, 0.0], [3.0, -3.0]]
    dirs = [[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    # through the face x = 2.5; grazing inside; passing above; from inside; behind it; from below into y = -1
    assert box.entry(origins, dirs).tolist() == [2.5, 2.5, math.inf, 0.0, math.inf, 2.0]


def test_a_turned_box_is_entered_at_its_corner():
    # a unit square turned by 45 degrees: its corner on the x axis at 3 - sqrt(2) / 2
    box = Box("diamond", x=3.0, y=0.0, length=1.0, width=1.0, yaw=math.pi / 4)
    assert box.entry([[0.0, 0.0]], [[1.0, 0.0]])[0] == pytest.approx(3 - math.sqrt(0.5))


def test_a_ray_meets_a_circle_where_the_quadratic_says():
    pole = Cylinder("pole", x=0.0, y=4.0, radius=1.0)
    # straight at it: 3 m; offset by 0.6 m: 4 - sqrt(1 - 0.36) = 3.2; 1 m off: tangent at 4; beyond: miss
    got = pole.entry([[0.0, 0.0], [0.6, 0.0], [1.0, 0.0], [1.5, 0.0], [0.0, 6.0]], [[0.0, 1.0]] * 5)
    assert got.tolist() == pytest.approx([3.0, 3.2, 4.0, math.inf, math.inf])


def test_a_wall_is_a_thin_box_along_its_segment():
    wall = Wall("panel", x1=2.0, y1=-1.0, x2=2.0, y2=1.0, thickness=0.2)
    assert wall.box.length == pytest.approx(2.0) and wall.box.width == 0.2
    assert wall.entry([[0.0, 0.5], [4.0, 0.0], [0.0, 1.5]], [[1.0, 0.0], [-1.0, 0.0], [1.0, 0.0]]).tolist() == \
        pytest.approx([1.9, 1.9, math.inf])


def test_nearest_points_and_depths():
    box = Box("crate", x=0.0, y=0.0, length=2.0, width=1.0)
    assert box.closest([[3.0, 2.0], [0.5, 0.1]]).tolist() == [[1.0, 0.5], [0.5, 0.1]]
    # inside: the distance to the nearest face; outside: minus the distance to the box
    assert box.depth([[0.0, 0.0], [0.9, 0.0], [4.0, 4.5]]).tolist() == pytest.approx([0.5, 0.1, -5.0])
    pole = Cylinder("pole", x=1.0, y=1.0, radius=0.5)
    assert pole.closest([[4.0, 1.0]]).tolist() == [[1.5, 1.0]]
    assert pole.depth([[1.0, 1.0], [1.0, 3.0]]).tolist() == [0.5, -1.5]


def test_an_object_stands_from_start_until_end():
    box = Box("crate", 0.0, 0.0, 1.0, 1.0, start=10.0, end=20.0)
    assert box.present([9.9, 10.0, 19.9, 20.0]).tolist() == [False, True, True, False]


@pytest.mark.parametrize("make, match", [
    (lambda: Box("", 0, 0, 1, 1), "needs a name"),
    (lambda: Box("b", 0, 0, 0.0, 1), "length must be a positive length"),
    (lambda: Cylinder("c", 0, 0, -1.0), "radius must be a positive length"),
    (lambda: Cylinder("c", 0, 0, 1.0, start=5.0, end=5.0), "start .* must be before end"),
    (lambda: Wall("w", 1, 1, 1, 1), "length must be a positive length"),
])
def test_bad_objects_are_refused(make, match):
    with pytest.raises(ValueError, match=match):
        make()


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-3, 3), y=st.floats(-3, 3), yaw=st.floats(-4, 4), angle=st.floats(-4, 4),
       length=st.floats(0.2, 2), width=st.floats(0.2, 2))
def test_a_ray_enters_a_box_on_its_surface(x, y, yaw, angle, length, width):
    box = Box("b", x, y, length, width, yaw)
    origin = np.array([[5.0, -4.0]])
    u = np.array([[math.cos(angle), math.sin(angle)]])
    t = box.entry(origin, u)[0]
    if math.isfinite(t):   # the entry point lies on the surface; a step before it lies outside
        assert abs(box.depth(origin + t * u)[0]) < 1e-9
        assert box.depth(origin + (t - 1e-3) * u)[0] < 0
    else:                  # a miss: no point along the ray is inside
        ts = np.linspace(0, 20, 2001)[:, None]
        assert np.all(box.depth(origin + ts * u) <= 1e-9)
