"""The points input's layout: rows written from a sensor ring at known bearings, read back, and refused."""

import math

import numpy as np
import pytest

from novelty.io.scans.points import check_points, points_columns, ring_points, split_points


def test_a_ring_at_known_bearings_puts_each_echo_offset_plus_range_along_its_axis_in_the_world():
    # robot at (1, 2) facing +y; sensors ahead and to its left, 0.25 m from the centre, T = 4 m:
    # near 0.75 is 1 m from the sensor (1.25 m from the centre), near 0 is no echo: free 4.25 m along its axis
    row = ring_points([[0.75, 0.0]], [[1.0, 2.0, math.pi / 2]], [0.0, math.pi / 2], 4.0, offset=0.25)
    assert row.shape == (1, 3 + 3 * 2)
    assert row[0, :5].tolist() == [1.0, 2.0, math.pi / 2, 0.75, 0.0]
    assert row[0, 5:] == pytest.approx([1.0, 1.0 - 4.25, 2.0 + 1.25, 2.0])


def test_the_heading_is_wrapped_into_minus_pi_to_pi():
    row = ring_points([[0.5]], [[0.0, 0.0, 3 * math.pi / 2]], [0.0], 4.0)
    assert row[0, 2] == pytest.approx(-math.pi / 2)
    assert row[0, 4:] == pytest.approx([0.0, -2.0])


def test_rows_split_back_into_poses_nearness_and_end_points_under_their_column_names():
    row = ring_points([[0.75, 0.0]], [[1.0, 2.0, 0.0]], [0.0, math.pi], 4.0)
    poses, near, ends = split_points(row)
    assert points_columns(2) == ["x", "y", "heading", "near_0", "near_1", "x_0", "x_1", "y_0", "y_1"]
    assert row[0] == pytest.approx([1.0, 2.0, 0.0, 0.75, 0.0, 2.0, -3.0, 2.0, 2.0])
    assert poses.tolist() == [[1.0, 2.0, 0.0]] and near.tolist() == [[0.75, 0.0]]
    assert ends.reshape(-1) == pytest.approx([2.0, 2.0, -3.0, 2.0])


@pytest.mark.parametrize("rows, message", [
    (np.zeros((2, 7)), "3 \\+ 3n columns, n >= 1\\); got 7 columns"),
    (np.zeros((2, 3)), "got 3 columns"),
    (np.c_[np.zeros((1, 3)), [[2.0]], [[0.0]], [[0.0]]], "nearness in \\[0, 1\\]"),
])
def test_rows_without_the_layout_are_refused_saying_what_it_is(rows, message):
    with pytest.raises(ValueError, match=message):
        check_points(rows, "MyDetector")


def test_a_ring_and_poses_that_do_not_match_are_refused():
    with pytest.raises(ValueError, match="Expected rings \\(m, n\\), poses \\(m, 3\\) and n bearings"):
        ring_points([[0.5, 0.5]], [[0.0, 0.0, 0.0]], [0.0], 4.0)
    with pytest.raises(ValueError, match="threshold must be positive"):
        ring_points([[0.5]], [[0.0, 0.0, 0.0]], [0.0], 0.0)
