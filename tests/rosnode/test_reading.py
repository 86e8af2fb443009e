"""Live messages read as a bag's: a bag's messages pushed one at a time give the bag reader's inputs, exactly."""

import math

import numpy as np
import pytest

from novelty.io import Reading, read_rings, read_sweeps
from novelty.io.scans.points import sweep_points
from novelty.rosnode.reading import LiveReading
from novelty.sonar import preprocess

pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")

from ..io.scenes import odometry, quaternion, tf_message, transform, write_robot_bag  # noqa: E402
from .bags import laser, messages, mounts, odometry_tf, pose_at  # noqa: E402

TIMES = np.round(1.0 + np.arange(0.0, 3.0, 0.1), 6)
#: one laser on /scan read as the points input, as novelty run reads it for a map
POINTS = Reading(topic="/scan", sectors=180, inputs="points")
TF_TIMES = np.round(0.95 + np.arange(0.0, 3.2, 0.02), 6)


def pushed(reading: LiveReading, bag) -> list:
    """The rows of the bag's messages pushed into ``reading`` in the bag's order, the clock at their times."""
    rows = []
    for topic, msgtype, record, data in messages(bag):
        if topic in reading.topics:
            rows += reading.push(topic, reading.decode(topic, msgtype, data, record), record)
    return rows + reading.flush()


def test_two_lasers_merged_as_novelty_run_merges_them(tmp_path):
    front, rear = ("front", (0.25, 0.0, 0.0), False), ("rear", (-0.25, 0.05, math.pi), True)
    bag = write_robot_bag(tmp_path / "two.bag", "ros1", laser(TIMES, "/front", "front", span=math.radians(200),
                                                              mount=front[1]) +
                          laser(np.round(TIMES + 0.013, 6), "/rear", "rear", span=math.radians(200), mount=rear[1],
                                flipped=True) + odometry_tf(TF_TIMES) + [mounts(0.5, front, rear)])
    expected = list(read_rings(bag, Reading(topic=["/front", "/rear"])))
    reading = LiveReading(Reading(topic=["/front", "/rear"]))
    rows = pushed(reading, bag)
    assert len(rows) == len(expected) == 30
    np.testing.assert_array_equal([r.x for r in rows], preprocess(np.array([e.ranges for e in expected]), 4.0))
    np.testing.assert_array_equal([r.time for r in rows], [e.time for e in expected])
    assert reading.stream.merger.merged == 30 and "upside down" in reading.report.mounts["/rear"]


def test_poses_from_an_odometry_topic(tmp_path):
    odom = [(t, "/odom", "nav_msgs/msg/Odometry", lambda ts, t=t: odometry(ts, t, pose_at(t))) for t in TF_TIMES]
    bag = write_robot_bag(tmp_path / "odom.bag", "ros1", laser(TIMES, mount=(0.0, 0.0, 0.0)) + odom)
    expected = list(read_sweeps(bag, Reading(topic="/scan", pose_topic="/odom")))
    reading = LiveReading(Reading(topic="/scan", pose_topic="/odom", sectors=180, inputs="points"))
    rows = pushed(reading, bag)
    np.testing.assert_array_equal([r.x for r in rows], sweep_points(expected, 180, 4.0))
    assert reading.report.poses == "from /odom, interpolated at each scan's time"


def test_the_base_footprint_where_the_tree_has_no_base_link_and_a_fixed_frame_given(tmp_path):
    # map -> odom (moving: a localiser's corrections) -> base_footprint -> laser
    def tree(ts, t):
        x, y, yaw = pose_at(t)
        return tf_message(ts, [transform(ts, t, "map", "odom", (1.0, 0.5 * t, 0.0), quaternion(yaw=0.1)),
                               transform(ts, t, "odom", "base_footprint", (x, y, 0.0), quaternion(yaw=yaw))])

    bag = write_robot_bag(tmp_path / "footprint.bag", "ros1", laser(TIMES, frame="laser") + [
        (t, "/tf", "tf2_msgs/msg/TFMessage", lambda ts, t=t: tree(ts, t)) for t in TF_TIMES] + [
        (0.5, "/tf_static", "tf2_msgs/msg/TFMessage", lambda ts: tf_message(ts, [
            transform(ts, 0.5, "base_footprint", "laser", (0.1, 0.0, 0.2))]))])
    in_map = LiveReading(POINTS)
    rows = pushed(in_map, bag)
    assert in_map.report.base_frame == "base_footprint" and "fallback" in in_map.report.base_reason
    np.testing.assert_array_equal([r.x for r in rows], sweep_points(list(read_sweeps(bag, Reading(topic="/scan"))), 180, 4.0))
    in_odom = LiveReading(POINTS, fixed_frame="odom")
    poses = np.array([r.pose for r in pushed(in_odom, bag)])
    # the poses in odom are the robot's on its circle (interpolated linearly between samples 20 ms apart)
    np.testing.assert_allclose(poses[:, :2], [pose_at(r.time)[:2] for r in rows], atol=1e-4)


def test_time_jumping_back_forgets_the_moving_transforms_and_keeps_the_static(tmp_path):
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", laser(TIMES) + odometry_tf(TF_TIMES) + [
        mounts(0.5, ("laser", (0.1, 0.0, 0.0), False))])
    reading = LiveReading(POINTS)
    first = pushed(reading, bag)
    assert reading.jumped_back("/tf", 3.0) is False and reading.jumped_back("/tf", 0.9) is True
    reading.restart()
    assert not reading.posing.tree.has("odom") and reading.posing.tree.has("laser")
    again = pushed(reading, bag)
    np.testing.assert_array_equal([r.x for r in again], [r.x for r in first])


def test_a_point_cloud_and_a_multi_echo_laser_read_as_novelty_run_reads_them(tmp_path):
    from ..io.bag_files import _header, _make, write_bag

    cloud_bag = write_bag(tmp_path, "ros1")   # one PointCloud2 on /cloud, flattened all round
    reading = LiveReading(Reading(topic="/cloud", sectors=8))
    rows = pushed(reading, cloud_bag)
    expected = list(read_rings(cloud_bag, Reading(topic="/cloud", sectors=8)))
    assert len(rows) == len(expected) == 1
    np.testing.assert_array_equal(rows[0].x, preprocess(expected[0].ranges, 4.0))

    def echoes(ts, t):
        near = [_make(ts, "sensor_msgs/msg/LaserEcho", echoes=np.array([1.0 + k % 3, 2.5 + t], np.float32))
                for k in range(8)]
        return _make(ts, "sensor_msgs/msg/MultiEchoLaserScan", header=_header(ts, t, "laser"), angle_min=-1.0,
                     angle_max=0.75, angle_increment=0.25, range_min=0.1, range_max=30.0, ranges=near,
                     intensities=[_make(ts, "sensor_msgs/msg/LaserEcho", echoes=np.array([5.0, 50.0], np.float32))] * 8)

    echo_bag = write_robot_bag(tmp_path / "echoes.bag", "ros1", [
        (t, "/echoes", "sensor_msgs/msg/MultiEchoLaserScan", lambda ts, t=t: echoes(ts, t)) for t in TIMES[:3]])
    for echo in ("first", "last", "strongest"):
        options = Reading(topic="/echoes", sectors=2, echo=echo)
        reading = LiveReading(options)
        expected = [r.ranges for r in read_rings(echo_bag, options)]
        np.testing.assert_array_equal([r.x for r in pushed(reading, echo_bag)], preprocess(np.array(expected), 4.0))
    assert expected[0].tolist() != [r.ranges for r in read_rings(echo_bag, Reading(topic="/echoes", sectors=2))][0].tolist()


def test_sonars_gathered_into_rings_in_the_order_of_their_mounts_as_novelty_run_gathers_them(tmp_path):
    from ..io.bag_files import _header, _make, write_sonar_topics

    # three sonars on one topic whose frame names say nothing of where they point: left, front, right
    angles = {"sonar_a": math.pi / 2, "sonar_b": 0.0, "sonar_c": -math.pi / 2}
    messages = [mounts(0.5, *[(f, (0.1 * math.cos(a), 0.1 * math.sin(a), a), False) for f, a in angles.items()])]
    for t in TIMES[:6]:
        for j, frame in enumerate(angles):
            messages.append((t + 0.01 * j, "/sonar", "sensor_msgs/msg/Range", lambda ts, t=t, j=j, frame=frame: _make(
                ts, "sensor_msgs/msg/Range", header=_header(ts, t + 0.01 * j, frame), field_of_view=0.5,
                min_range=0.05, max_range=10.0, range=1.0 + j + t)))
    bag = write_robot_bag(tmp_path / "sonars.bag", "ros1", messages)
    reading = LiveReading(Reading(topic="/sonar"))
    rows = pushed(reading, bag)
    expected = list(read_rings(bag, Reading(topic="/sonar")))
    assert len(rows) == len(expected) == 6
    np.testing.assert_array_equal([r.x for r in rows], preprocess(np.array([e.ranges for e in expected]), 4.0))
    assert rows[0].ranges.tolist() == [2.0 + 1.0, 1.0 + 1.0, 3.0 + 1.0]   # c (right), b (front), a (left)
    assert "sonar_c -90 deg" not in reading.report.notes[0] and "sonar_c 270 deg" in reading.report.notes[0]
    # one topic a sonar, without frames: named by their topics, in that order
    two = write_sonar_topics(tmp_path / "two.bag")
    options = Reading(topic=["/front", "/back"])
    np.testing.assert_array_equal([r.ranges for r in pushed(LiveReading(options), two)],
                                  [r.ranges for r in read_rings(two, options)])
