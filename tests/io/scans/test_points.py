"""The points input's layout: rows written from a sensor ring at known bearings, read back, and refused."""

import math

import numpy as np
import pytest

from novelty.io.ros.messages import Sweep
from novelty.io.scans.points import check_points, points_columns, ring_points, split_points, sweep_points
from novelty.io.scans.sectors import sector_index


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


# ------------------------------------------------------------------ sweep_points: every sector at once
def sector_ends_one_by_one(sweep, sectors, threshold):
    """The readable form: each sector's nearest beam (the first of the least distance), its middle beam
    without an echo, its end point or ``threshold`` along that beam."""
    angles, ranges, origins = sweep.angles, sweep.ranges, sweep.origins
    echo = np.isfinite(ranges)
    unit = np.c_[np.cos(angles), np.sin(angles)]
    ends = origins + np.where(echo, ranges, 0.0)[:, None] * unit
    distance = np.where(echo, np.hypot(ends[:, 0], ends[:, 1]), np.inf)
    index = sector_index(angles, sectors)
    out = np.empty((sectors, 2))
    for k in range(sectors):
        beams = np.flatnonzero(index == k)
        j = beams[np.argmin(distance[beams])] if np.isfinite(distance[beams]).any() else beams[len(beams) // 2]
        if distance[j] <= threshold:
            out[k] = ends[j]
        else:
            direction = ends[j] if echo[j] else unit[j]
            out[k] = threshold * direction / np.hypot(*direction)
    return out


def random_sweep(rng, beams):
    angles = np.linspace(-math.pi / 2, math.pi / 2, beams)
    ranges = rng.choice([0.5, 1.0, 2.0, 3.5, 4.0, 6.0, np.inf], size=beams)   # ties and no echo
    origins = np.tile(rng.uniform(-0.3, 0.3, 2), (beams, 1))
    return Sweep(0.0, origins, angles, ranges, np.array([*rng.uniform(-5, 5, 2), rng.uniform(-4, 4)]))


@pytest.mark.parametrize("beams, sectors", [(180, 180), (180, 16), (181, 7), (30, 30), (1080, 180), (5, 1)])
def test_each_sectors_end_point_is_the_one_by_one_readings_exactly(beams, sectors):
    rng = np.random.default_rng(beams * 1000 + sectors)
    sweeps = [random_sweep(rng, beams) for _ in range(20)]
    sweeps.append(Sweep(0.0, np.zeros((beams, 2)), sweeps[0].angles, np.full(beams, np.inf), np.zeros(3)))
    rows = sweep_points(sweeps, sectors, 4.0)
    for sweep, row in zip(sweeps, rows):
        ends = sector_ends_one_by_one(sweep, sectors, 4.0)
        x, y, yaw = sweep.pose
        c, s = math.cos(yaw), math.sin(yaw)
        assert np.array_equal(row[3 + sectors:3 + 2 * sectors], x + c * ends[:, 0] - s * ends[:, 1])
        assert np.array_equal(row[3 + 2 * sectors:], y + s * ends[:, 0] + c * ends[:, 1])


def test_more_sectors_than_beams_is_refused_saying_which_hold_no_beam():
    sweep = random_sweep(np.random.default_rng(0), 4)
    with pytest.raises(ValueError, match="2 of 6 sectors hold no beam"):
        sweep_points([sweep], 6, 4.0)
