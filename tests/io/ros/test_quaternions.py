"""Quaternions: products, rotations and slerp against rotation matrices and angles worked out by hand."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.io.ros.quaternions import conjugate, matrix, multiply, normalized, rotate, slerp, yaw

from ...io.scenes import quaternion

angle = st.floats(-math.pi, math.pi)


@settings(max_examples=50, deadline=None)
@given(angle, angle, angle, angle, angle, angle)
def test_products_are_matrix_products(r1, p1, y1, r2, p2, y2):
    a, b = quaternion(r1, p1, y1), quaternion(r2, p2, y2)
    np.testing.assert_allclose(matrix(multiply(a, b)), matrix(a) @ matrix(b), atol=1e-12)
    np.testing.assert_allclose(matrix(multiply(a, conjugate(a))), np.eye(3), atol=1e-12)
    assert yaw(quaternion(0.0, 0.0, y1)) == pytest.approx(y1, abs=1e-12) or abs(abs(y1) - math.pi) < 1e-9


def test_rotations_by_hand():
    assert rotate(quaternion(yaw=math.pi / 2), (1.0, 0.0, 0.0)) == pytest.approx((0.0, 1.0, 0.0), abs=1e-12)
    assert rotate(quaternion(roll=math.pi), (0.0, 1.0, 0.0)) == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)
    with pytest.raises(ValueError, match="not a rotation"):
        normalized((0.0, 0.0, 0.0, 0.0))


@settings(max_examples=50, deadline=None)
@given(angle, angle, st.floats(0.0, 1.0))
def test_slerp_turns_evenly_along_the_shorter_arc(y1, y2, t):
    turn = (y2 - y1 + math.pi) % (2 * math.pi) - math.pi
    if abs(abs(turn) - math.pi) < 1e-6:
        return   # half a turn either way: both arcs are as short
    got = yaw(slerp(quaternion(yaw=y1), quaternion(yaw=y2), t))
    want = (y1 + t * turn + math.pi) % (2 * math.pi) - math.pi
    assert abs((got - want + math.pi) % (2 * math.pi) - math.pi) < 1e-9
