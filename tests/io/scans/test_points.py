"""The points input's layout: rows written from a sensor ring at known bearings, read back, and refused."""

import math

import numpy as np
import pytest

from novelty.io.ros.messages import Sweep
from novelty.io.scans import points
from novelty.io.scans.points import (PointsMaker, check_points, points_columns, reference_points, ring_points,
                                      split_points, sweep_points)
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


# ------------------------------------------------------------------ a sweep's row, one sweep at a time
def reference_ends(sweep, sectors: int, threshold: float) -> np.ndarray:
    """Each sector's end point, sector by sector: its nearest beam (the first of equals), or its middle beam
    where none returned; the echo where it is within ``threshold``, else ``threshold`` along the beam."""
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


@pytest.mark.parametrize("seed", range(6))
def test_a_sweeps_end_points_are_those_of_each_sectors_nearest_beam_exactly(seed):
    rng = np.random.default_rng(seed)
    n, sectors = int(rng.integers(40, 400)), int(rng.integers(1, 40))
    angles = np.sort(rng.uniform(-np.pi, np.pi, n)) if seed % 2 else -np.pi + 2 * np.pi / n * np.arange(n)
    ranges = np.round(rng.uniform(0.2, 8.0, n), 1)   # rounded: equal distances, the first of them taken
    ranges[rng.random(n) < 0.2] = np.inf
    ranges[rng.random(n) < 0.1] = np.nan
    ranges[sector_index(angles, sectors) == 0] = np.inf   # a sector without an echo: its middle beam
    origins = np.zeros((n, 2)) + (rng.normal(0, 0.2, 2) if seed % 3 else 0.0)
    sweep = Sweep(0.0, origins, angles, ranges, np.array([1.0, -2.0, 0.7]))
    maker = PointsMaker(sectors, 4.0)
    row = maker(sweep)
    ends = reference_ends(sweep, sectors, 4.0)
    c, s = math.cos(0.7), math.sin(0.7)
    np.testing.assert_array_equal(row[3 + sectors:3 + 2 * sectors], 1.0 + c * ends[:, 0] - s * ends[:, 1])
    np.testing.assert_array_equal(row[3 + 2 * sectors:], -2.0 + s * ends[:, 0] + c * ends[:, 1])
    np.testing.assert_array_equal(row, maker(sweep))                  # the geometry kept: the same row
    np.testing.assert_array_equal(row, sweep_points([sweep], sectors, 4.0)[0])


def test_a_sweep_without_a_pose_has_no_row():
    sweep = Sweep(1.5, np.zeros((4, 2)), np.arange(4.0), np.ones(4), None)
    with pytest.raises(ValueError, match="The sweep at t=1.5 has no pose"):
        PointsMaker(2)(sweep)


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
        ends = reference_ends(sweep, sectors, 4.0)
        x, y, yaw = sweep.pose
        c, s = math.cos(yaw), math.sin(yaw)
        assert np.array_equal(row[3 + sectors:3 + 2 * sectors], x + c * ends[:, 0] - s * ends[:, 1])
        assert np.array_equal(row[3 + 2 * sectors:], y + s * ends[:, 0] + c * ends[:, 1])


def mixed_sweeps(rng, count):
    """Sweeps of two interleaved geometries, from shared, own, centred and offset origins, with ties, no echo,
    no information, an echo at the centre, and poses in float32 and beyond a half turn."""
    wide, narrow = np.linspace(-math.pi, math.pi, 360, endpoint=False), np.linspace(-2.0, 2.0, 90)
    shared = {id(a): np.zeros((a.size, 2)) for a in (wide, narrow)}
    sweeps = []
    for q in range(count):
        angles = wide if rng.random() < 0.5 else narrow
        ranges = rng.choice([0.0, 0.5, 1.0, 2.0, 3.5, 4.0, 6.0, np.inf, np.nan], size=angles.size)
        origins = (shared[id(angles)] if q % 3 == 0 else np.zeros((angles.size, 2)) if q % 3 == 1
                   else np.tile(rng.uniform(-0.3, 0.3, 2), (angles.size, 1)))
        pose = np.array([*rng.uniform(-50, 50, 2), rng.uniform(-7, 7)], dtype=np.float32 if q % 4 else np.float64)
        sweeps.append(Sweep(float(q), origins, angles, ranges, pose))
    return sweeps


@pytest.mark.parametrize("block", [1, 7, 512])
def test_the_rows_of_many_sweeps_are_the_numpy_references_one_by_one_bit_for_bit(block, monkeypatch):
    monkeypatch.setattr(points, "BLOCK", block)
    sweeps = mixed_sweeps(np.random.default_rng(block), 60)
    for sectors in (1, 16, 90):
        rows = sweep_points(sweeps, sectors, 4.0)
        expected = reference_points(sweeps, sectors, 4.0)
        assert rows.tobytes() == expected.tobytes()   # bit for bit, signed zeros included
        maker = PointsMaker(sectors, 4.0)
        assert np.stack([maker(sweep) for sweep in sweeps]).tobytes() == expected.tobytes()


def test_no_sweeps_make_no_rows():
    assert sweep_points([], 5).shape == (0, 18)


def test_a_sweep_without_a_pose_among_many_is_refused_naming_its_time():
    sweeps = mixed_sweeps(np.random.default_rng(0), 5)
    sweeps[3] = Sweep(7.5, sweeps[3].origins, sweeps[3].angles, sweeps[3].ranges, None)
    with pytest.raises(ValueError, match="The sweep at t=7.5 has no pose"):
        sweep_points(sweeps, 4)


def test_more_sectors_than_beams_is_refused_saying_which_hold_no_beam():
    sweep = random_sweep(np.random.default_rng(0), 4)
    with pytest.raises(ValueError, match="2 of 6 sectors hold no beam"):
        sweep_points([sweep], 6, 4.0)
