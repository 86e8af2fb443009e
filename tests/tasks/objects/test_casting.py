"""Casting into a whole recording: sightings and passes, on a corridor drive and a ROS bag."""

import math

import numpy as np
import pytest

from novelty.tasks.objects.casting import cast_all, passes, sightings
from novelty.tasks.objects.shapes import Cylinder
from novelty.io.recording.readers import read_sweeps
from novelty.io import Reading


def test_every_sweep_is_cast_and_counted(drive):
    bin_ = Cylinder("bin", 5.0, 0.6, 0.25, start=42.0)
    cast = cast_all(drive, [bin_], within=4.0)
    assert len(cast.sweeps) == len(cast.recorded) == len(drive) and cast.shortened.shape == (len(drive), 1)
    assert cast.times.tolist() == list(range(84)) and cast.poses.shape == (84, 3)
    assert not cast.shortened[:42].any()                      # before it stands there
    # the third leg (scans 42-62) drives back from x = 10 facing -x: the bin at x = 5 is ahead on its right
    # until the robot passes it; it is seen from within 4 m of it
    seen = sightings(cast.shortened)[:, 0]
    xs = cast.poses[seen, 0]
    assert seen[42:63].any() and np.all(np.abs(xs - 5.0) < 4.0)
    k = passes(seen, cast.poses, bin_, 4.0)
    assert sorted(set(k.tolist()) - {-1}) == [0, 1] and np.all(k[42:63][seen[42:63]] == 0)


def test_passes_need_one_pose_a_scan_and_a_positive_leave():
    with pytest.raises(ValueError, match="one entry a pose"):
        passes([True], np.zeros((2, 3)), Cylinder("c", 0, 0, 1), 1.0)
    with pytest.raises(ValueError, match="leave must be a positive length"):
        passes([True], np.zeros((1, 3)), Cylinder("c", 0, 0, 1), 0.0)


def test_a_bag_with_odometry_is_cast_from_its_poses(tmp_path):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra")
    from ...io.bag_files import write_bag

    sweeps = [s for s in read_sweeps(write_bag(tmp_path, "ros1"), Reading(topic="/scan", pose_topic="/odom"))
              if s.time >= 6.0]
    # the scans at 6.0 and 6.1 s: four beams at -90, -30, 30 and 90 degrees, all 2 m; the robot at x = 5.95
    # (odometry at 5.95 s) facing 0.5 rad. A pole 1.2 m along the third beam's world direction, radius 0.2:
    # that beam now ends 1.0 m out, the others miss it
    bearing = 0.5 + math.pi / 6
    pole = Cylinder("pole", 5.95 + 1.2 * math.cos(bearing), 1.2 * math.sin(bearing), 0.2)
    cast = cast_all(sweeps, [pole])
    assert [s.ranges.tolist() for s in cast.sweeps] == [pytest.approx([2.0, 2.0, 1.0, 2.0])] * 2
    assert cast.shortened.tolist() == [[1], [1]]
