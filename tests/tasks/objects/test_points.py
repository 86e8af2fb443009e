"""A recording's sweeps as the points input, on the corridor drive (walls whose faces stand 1 m either side, beams -90 to 90 degrees)."""

import numpy as np
import pytest

from novelty.io.scans.points import sweep_points
from novelty.tasks.objects.object_tasks import object_inputs, object_rings
from novelty.io.ros.messages import Sweep


def test_each_sectors_end_point_is_its_nearest_echo_in_the_world_frame(drive):
    # two sectors: the right half's nearest echo is the beam at -90 degrees, the left half's at +90
    out, back = drive[4], drive[-5]                  # at x = 2 facing +x, and at x = 2 facing -x
    assert out.pose.tolist() == [2.0, 0.0, 0.0] and back.pose[:2].tolist() == [2.0, 0.0]
    rows = sweep_points([out, back], sectors=2, threshold=4.0)
    near = 1.0 - 1.0 / 4.0
    assert rows[0].tolist() == pytest.approx([2.0, 0.0, 0.0, near, near, 2.0, 2.0, -1.0, 1.0])
    # facing back (a heading of pi, written -pi), its right is the world's left
    assert rows[1].tolist() == pytest.approx([2.0, 0.0, -np.pi, near, near, 2.0, 2.0, 1.0, -1.0])


def test_a_sector_with_no_echo_within_the_threshold_ends_the_threshold_along_its_nearest_beam(drive):
    rows = sweep_points([drive[4]], sectors=2, threshold=0.9)
    assert rows[0].tolist() == pytest.approx([2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0, -0.9, 0.9])


def test_the_points_inputs_ring_is_the_ring_input(drive):
    points = object_inputs(drive, "points", sectors=16)
    assert np.array_equal(points[:, 3:3 + 16], object_rings(drive, 16))
    assert np.array_equal(points[:, :2], np.array([s.pose[:2] for s in drive]))


def test_a_sweep_without_a_pose_or_a_ring_of_no_sectors_is_refused(drive):
    bare = Sweep(0.0, np.zeros((2, 2)), np.array([-0.1, 0.1]), np.ones(2), None)
    with pytest.raises(ValueError, match="has no pose: the points input places each echo in the world frame"):
        sweep_points([bare])
    with pytest.raises(ValueError, match="one number of sectors \\(an int >= 1\\); got 0"):
        sweep_points(drive[:1], sectors=0)
    with pytest.raises(ValueError, match="nearest echo \\(reduce='min'\\); got reduce='mean'"):
        object_inputs(drive[:1], "points", reduce="mean")
