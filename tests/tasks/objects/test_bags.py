"""Objects in a bag shaped like a real robot's: a laser mounted upside down, its mount given when the bag lacks it.

A robot drives through the simulated room of :mod:`tests.io.scenes` with its
laser upside down at its centre (its angles run clockwise seen from above),
and the bag holds no transform for the laser's frame, as happens when a
robot's description is not running while it records. Read with the mount
given (``mounts="0,0,0,flipped"``), the task is the upright laser's (whose
bag places it through ``/tf_static``), ray for ray; read as if upright, with
a warning, the object stands on the other side of the robot. The
``recording`` task, which reads the same bags, takes the mount too.
"""

import math
import warnings

import numpy as np
import pytest

from novelty import datasets
from novelty.tasks.objects.casting import cast_all, sightings
from novelty.tasks.objects.shapes import Cylinder
from novelty.tasks.objects.object_tasks import inspection_task, read_drive

pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")

from ...io.scenes import (laser_ranges, odometry, scan_message, tf_message, transform,  # noqa: E402
                      write_robot_bag)

SCAN = "sensor_msgs/msg/LaserScan"
ODOM = "nav_msgs/msg/Odometry"
TF = "tf2_msgs/msg/TFMessage"
#: a 270-degree laser of 271 beams, one a degree
ANGLES = np.deg2rad(np.arange(-135.0, 135.5, 1.0))
#: a scan every 0.2 s for 8 s
TIMES = np.round(np.arange(0.1, 8.0, 0.2), 3)
#: a bin to the robot's right as it passes x = 0 (the robot drives along y = 0.5), from t = 4 s on
BIN = Cylinder("bin", 0.2, -0.6, 0.2, start=4.0)


def pose_at(t):
    """Along x at 0.25 m/s, from x = -2, facing +x."""
    return (-2.0 + 0.25 * t, 0.5, 0.0)


def robot_bag(path, flipped):
    """Scans in frame ``laser`` and odometry of ``base_link``; upright, the laser placed by ``/tf_static``,
    upside down, no transform for it."""
    scans = [(t, "/scan", SCAN, lambda ts, t=t: scan_message(
        ts, t, "laser", float(ANGLES[0]), math.radians(1.0),
        laser_ranges(pose_at(t), (0.0, 0.0, 0.0), ANGLES, flipped=flipped))) for t in TIMES]
    odom = [(t, "/odom", ODOM, lambda ts, t=t: odometry(ts, t, pose_at(t)))
            for t in np.round(np.arange(0.0, 8.2, 0.05), 3)]
    static = [] if flipped else [(0.0, "/tf_static", TF, lambda ts: tf_message(
        ts, [transform(ts, 0.0, "base_link", "laser")]))]
    return write_robot_bag(path, "ros1", scans + odom + static)


def quietly(read, *args, **kwargs):
    """``read(*args, **kwargs)``, any warning an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return read(*args, **kwargs)


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    folder = tmp_path_factory.mktemp("objects-bags")
    return robot_bag(folder / "upright", False), robot_bag(folder / "flipped", True)


def test_the_mount_given_reads_an_upside_down_laser_as_the_robot_saw(bags):
    upright, flipped = bags
    truth = quietly(read_drive, upright, "/scan", pose_topic="/odom")
    given = quietly(read_drive, flipped, "/scan", pose_topic="/odom", mounts="0,0,0,flipped")
    assert len(given) == len(truth) == len(TIMES)
    for a, b in zip(given, truth):   # the same beams, listed in the opposite order
        np.testing.assert_allclose(a.angles[::-1], b.angles, atol=1e-6)
        np.testing.assert_allclose(a.ranges[::-1], b.ranges, rtol=1e-6)
    # the bin is seen by the same scans, on the robot's right (negative bearings), read either way
    seen_truth = sightings(cast_all(truth, [BIN], within=4.0).shortened)[:, 0]
    cast = cast_all(given, [BIN], within=4.0)
    assert seen_truth.any() and np.array_equal(sightings(cast.shortened)[:, 0], seen_truth)
    k = int(np.flatnonzero(seen_truth)[0])
    shortened = cast.sweeps[k].ranges < cast.recorded[k].ranges - 0.1
    assert np.all(cast.sweeps[k].angles[shortened] < 0)


def test_read_as_upright_the_object_is_cast_on_the_wrong_side_with_a_warning(bags):
    upright, flipped = bags
    with pytest.warns(UserWarning, match=r"/scan at the robot's centre, facing forward \(assumed.*mounts="):
        as_upright = read_drive(flipped, "/scan", pose_topic="/odom")
    truth = quietly(read_drive, upright, "/scan", pose_topic="/odom")
    # the wrong reading mirrors the room: its beams at the truth's angles read what the truth reads at minus them
    np.testing.assert_allclose(as_upright[5].ranges, truth[5].ranges[::-1], rtol=1e-6)
    assert not np.allclose(as_upright[5].ranges, truth[5].ranges, rtol=1e-3)


def test_a_task_of_the_upside_down_laser_is_the_upright_lasers_with_its_mount_recorded(bags):
    upright, flipped = bags
    truth = quietly(inspection_task, upright, [BIN], topic="/scan", pose_topic="/odom", learn=0.45)
    given = quietly(datasets.load, "inspection-objects", path=str(flipped), objects=[BIN], topic="/scan",
                          pose_topic="/odom", learn=0.45, mounts="0,0,0,flipped")
    assert truth.y.sum() > 0 and np.array_equal(given.y, truth.y) and np.array_equal(given.split, truth.split)
    np.testing.assert_allclose(given.X, truth.X, atol=1e-6)
    assert given.metadata["reading"] == {
        "mounts": {"every scan topic": "x=0 m, y=0 m, yaw=0 deg, upside down, from option"}} and "reading" not in truth.metadata
    # what the reading found and chose, as novelty run says it
    assert given.metadata["read"] == ["/scan: x=0 m, y=0 m, yaw=0 deg, upside down, from option",
                                      "poses from /odom, interpolated at each scan's time"]
    assert truth.metadata["read"] == ["base frame base_link (REP 105's default)",
                                      "/scan: x=0 m, y=0 m, yaw=0 deg, from tf (base_link -> laser)",
                                      "poses from /odom, interpolated at each scan's time"]


def test_a_bad_mount_is_refused_with_what_was_expected(bags):
    with pytest.raises(ValueError, match="X,Y,YAW"):
        read_drive(bags[1], "/scan", pose_topic="/odom", mounts="upside down")


def test_a_recording_task_takes_the_mount_too(bags):
    upright, flipped = bags
    options = dict(topic="/scan", pose_topic="/odom", places=1.0, warmup=1, gap=None, intervals=[(0, 4), (4, 8)])
    truth = quietly(datasets.load, "recording", paths=str(upright), **options)
    given = quietly(datasets.load, "recording", paths=str(flipped), mounts="0,0,0,flipped", **options)
    np.testing.assert_allclose(given.X, truth.X, atol=1e-6)
    assert given.metadata["reading"] == {
        "mounts": {"every scan topic": "x=0 m, y=0 m, yaw=0 deg, upside down, from option"}}
    assert "reading" not in truth.metadata
    mirrored = datasets.load("recording", paths=str(flipped), mounts="0,0,0", **options)
    assert not np.allclose(mirrored.X, truth.X, atol=1e-3)


def test_a_recording_task_gives_a_map_the_points_input(bags):
    from novelty import bench
    from novelty.io.scans.points import sweep_points

    upright, _ = bags
    options = dict(topic="/scan", pose_topic="/odom", places=1.0, intervals=[(0, 4), (4, 8)], sectors=90)
    task = quietly(datasets.load, "recording", paths=str(upright), inputs="points", **options)
    expected = sweep_points(read_drive(upright, "/scan", pose_topic="/odom"), sectors=90)
    np.testing.assert_array_equal(task.X, expected)
    assert task.metadata["inputs"] == "points" and task.metadata["columns"][:4] == ["x", "y", "heading", "near_0"]
    with pytest.raises(ValueError, match="points input of Reading .*; reduce apply to the ring only"):
        datasets.load("recording", paths=str(upright), inputs="points", reduce="mean", **options)
    # in a benchmark a map gets the points input of the same task on its own, a ring detector the ring
    text = f"recording paths={upright} topic=/scan pose_topic=/odom places=1.0 intervals=[[0,4],[4,8]] sectors=90"
    results = bench.run(["map-explore", "hsom"], text, protocol="exploration", seeds=1)
    assert {r["detector"]: r["status"] for r in results.rows} == {"map-explore": "ok", "hsom": "ok"}
