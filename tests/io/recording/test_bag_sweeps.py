"""Bags shaped like real robots' recordings, from one simulated room: the rings they give against a centred laser's.

Each test writes with rosbags' writers what a robot records (scans in their
frames, /tf and /tf_static, odometry) and compares the rings read with those
of a centred, upright, whole-scan laser of the same room at the same poses.
"""

import math
import time

import numpy as np
import pytest

from novelty.io import Reading
from novelty.io.bags.report import ReadReport
from novelty.io.bags.rosbag import Bag
from novelty.io.frames.tf import TfError
from novelty.io.recording.readers import read_rings, read_sweeps
from novelty.io.ros import caps
from novelty.io.scans.assembly import LEARN

pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")

from ...io.bag_files import _header, _make  # noqa: E402
from ...io.scenes import (CONVEX, laser_ranges, odometry, quaternion, scan_message, tf_message,  # noqa: E402
                     transform, write_robot_bag)

KINDS = pytest.mark.parametrize("kind", ["ros1", "sqlite3"])
SCAN = "sensor_msgs/msg/LaserScan"
TF = "tf2_msgs/msg/TFMessage"


def path_of(t):
    """The robot's pose at t s: along x at 0.5 m/s, turning slowly."""
    return (-1.0 + 0.5 * t, 0.5 + 0.1 * t, 0.2 + 0.3 * t)


SPAN = math.radians(270)


def whole_scans(times, frame="laser", n=1080, span=SPAN, start=None, mount=(0.0, 0.0, 0.0),
                flipped=False, walls=None, topic="/scan"):
    """A scanner's whole scans at ``times`` as bag messages."""
    start = -span / 2 + span / n / 2 if start is None else start
    inc = span / n
    angles = start + inc * np.arange(n)
    kw = {} if walls is None else {"walls": walls}
    return [(t, topic, SCAN, lambda ts, t=t: scan_message(
        ts, t, frame, start, inc, laser_ranges(path_of(t), mount, angles, flipped=flipped, **kw))) for t in times]


def statics(t, *edges):
    return (t, "/tf_static", TF, lambda ts: tf_message(ts, [transform(ts, t, *e) for e in edges]))


def odom_tf(times, child="base_link"):
    return [(t, "/tf", TF, lambda ts, t=t: tf_message(ts, [transform(
        ts, t, "odom", child, (*path_of(t)[:2], 0.0), quaternion(yaw=path_of(t)[2]))])) for t in times]


def rings(path, report=None, **options):
    return [r.ranges for r in read_rings(path, Reading(sectors=16, **options), report=report)]


TIMES = np.round(np.arange(0.05, 2.0, 0.2), 3)
TF_TIMES = np.round(np.arange(0.0, 2.2, 0.02), 3)


@KINDS
def test_an_upside_down_laser_gives_the_upright_centred_lasers_ring(kind, tmp_path):
    upright = write_robot_bag(tmp_path / f"upright-{kind}", kind, whole_scans(TIMES) + [
        statics(0.0, ("base_link", "laser"))])
    flipped = write_robot_bag(tmp_path / f"flipped-{kind}", kind, whole_scans(TIMES, flipped=True) + [
        statics(0.0, ("base_link", "laser", (0.0, 0.0, 0.3), quaternion(roll=math.pi)))])
    expected = rings(upright)
    report = ReadReport()
    got = rings(flipped, report=report)
    np.testing.assert_allclose(got, expected, rtol=1e-6)
    assert "upside down" in report.mounts["/scan"] and "from tf (base_link -> laser)" in report.mounts["/scan"]
    # read as if upright (its mount overridden), its ring is the mirror image
    mirrored = rings(flipped, mounts="0,0,0")
    assert not np.allclose(mirrored, expected, rtol=1e-3)


#: what both the centred laser (-135..135 degrees) and the turned one (-105..165) see: -86..115 degrees
LIMITS = (-1.5, 2.0)


@KINDS
def test_an_offset_turned_laser_is_seen_from_the_robots_centre(kind, tmp_path):
    # a laser 0.4 m ahead, 0.2 m to the right, turned 30 degrees left, in a convex room: dense beams sample the
    # same walls, so its ring from the centre is the centred laser's within the beams' spacing
    mount = (0.4, -0.2, math.radians(30))
    centred = write_robot_bag(tmp_path / f"centred-{kind}", kind, whole_scans(TIMES, walls=CONVEX, n=2160))
    offset = write_robot_bag(tmp_path / f"offset-{kind}", kind, whole_scans(
        TIMES, walls=CONVEX, n=2160, mount=mount) + [statics(0.0, ("base_link", "laser", (0.4, -0.2, 0.2),
                                                                     quaternion(yaw=mount[2])))])
    expected = np.array(rings(centred, limits=LIMITS))
    got = np.array(rings(offset, limits=LIMITS))
    np.testing.assert_allclose(got, expected, atol=0.02)
    assert np.abs(np.array(rings(offset, limits=LIMITS, mounts="0,0,0")) - expected).max() > 0.2
    # without a transform in the bag, the mount option stands in for it
    bare = write_robot_bag(tmp_path / f"bare-{kind}", kind, whole_scans(TIMES, walls=CONVEX, n=2160, mount=mount))
    np.testing.assert_allclose(rings(bare, limits=LIMITS, mounts="0.4,-0.2,30"), expected, atol=0.02)


@KINDS
def test_a_turtlebot3_tree_gives_poses_with_the_default_options(kind, tmp_path):
    # odom -> base_footprint on /tf at 50 Hz; base_footprint -> base_link -> base_scan static; a 360-degree
    # lidar at 5 Hz starting at 0 rad, as the TurtleBot3's driver does
    n = 360
    scans = whole_scans(TIMES, frame="base_scan", n=n, span=2 * math.pi, start=0.0, mount=(-0.032, 0.0, 0.0))
    bag = write_robot_bag(tmp_path / f"tb3-{kind}", kind, scans + odom_tf(TF_TIMES, "base_footprint") + [
        statics(0.0, ("base_footprint", "base_link", (0.0, 0.0, 0.01)),
                ("base_link", "base_scan", (-0.032, 0.0, 0.172)))])
    report = ReadReport()
    read = list(read_rings(bag, report=report))
    poses = np.array([r.pose for r in read])
    np.testing.assert_allclose(poses, [path_of(t) for t in TIMES], atol=1e-6)
    assert report.base_frame == "base_link" and report.base_reason == "REP 105's default"
    assert report.poses.startswith("from /tf: odom -> base_footprint -> base_link")
    assert [r.pose.tolist() for r in read_rings(bag, Reading(pose_topic="/tf"))] == poses.tolist()
    # base_footprint without base_link: REP 105's fallback
    footprint = write_robot_bag(tmp_path / f"footprint-{kind}", kind, scans + odom_tf(TF_TIMES, "base_footprint") + [
        statics(0.0, ("base_footprint", "base_scan", (-0.032, 0.0, 0.18)))])
    report = ReadReport()
    np.testing.assert_allclose([r.pose for r in read_rings(footprint, report=report)], poses, atol=1e-6)
    assert report.base_reason == "REP 105's fallback: the tf tree has no base_link"
    with pytest.raises(TfError, match=r"pose_topic /tf holds no pose for the base frame 'chassis': it has no parent "
                                      r"there; the frames: base_footprint, base_link, base_scan, odom; the tree: "
                                      r"odom -> base_footprint -> base_link -> base_scan"):
        next(read_rings(bag, Reading(pose_topic="/tf", base_frame="chassis")))
    with pytest.raises(ValueError, match="pose_topic /tf_static holds static transforms"):
        next(read_rings(bag, Reading(pose_topic="/tf_static")))


@KINDS
def test_scans_before_the_first_pose_have_none(kind, tmp_path):
    bag = write_robot_bag(tmp_path / f"late-{kind}", kind, whole_scans(TIMES) + [
        (t, "/odom", "nav_msgs/msg/Odometry", lambda ts, t=t: odometry(ts, t, path_of(t))) for t in TF_TIMES[30:]])
    read = list(read_rings(bag, Reading(pose_topic="/odom")))
    first = TF_TIMES[30]
    assert [r.pose is None for r in read] == [t < first - 0.2 for t in TIMES]   # held within 0.2 s of the first
    np.testing.assert_allclose([r.pose for r in read if r.time >= first], [path_of(t) for t in TIMES if t >= first],
                               atol=1e-9)


@pytest.mark.parametrize("per, start_at", [(6, 0), (6, 4), (4, 1)])
def test_fragments_of_revolutions_make_one_scan_each(tmp_path, per, start_at):
    # a scanner whose revolution (270 degrees in the first two cases, all round in the third) comes as `per`
    # messages, the bag starting at fragment `start_at`: one ring a revolution, the centred whole scan's
    span = 2 * math.pi if per == 4 else math.radians(270)
    n = 1080
    inc = span / n
    start = -span / 2 + inc / 2 if per != 4 else -math.pi + inc / 2
    messages = []
    for k, t in enumerate(TIMES):
        ranges = laser_ranges(path_of(t), (0, 0, 0), start + inc * np.arange(n))
        for f in range(per):
            if k == 0 and f < start_at:
                continue
            piece = slice(f * n // per, (f + 1) * n // per)
            messages.append((t + 0.01 * f, "/scan", SCAN, lambda ts, t=t, f=f, piece=piece, ranges=ranges: scan_message(
                ts, t + 0.01 * f, "laser", start + inc * piece.start, inc, ranges[piece])))
    bag = write_robot_bag(tmp_path / "fragments.bag", "ros1", messages)
    whole = write_robot_bag(tmp_path / "whole.bag", "ros1", whole_scans(TIMES, span=span, start=start))
    report = ReadReport()
    got = rings(bag, report=report)
    expected = rings(whole)[1 if start_at else 0:]
    np.testing.assert_array_equal(got, expected)
    incomplete = 1 if start_at else 0
    assert report.assembly["/scan"] == (len(messages), len(TIMES) - incomplete, incomplete, per)
    assert len(rings(bag, fragments=1)) == len(messages)   # assembly off: every message a ring
    with pytest.raises(ValueError, match=f"3 fragments a revolution were stated, but its first messages tile a "
                                         f"revolution in {per}"):
        rings(bag, fragments=3)


def test_a_revolution_missing_a_fragment_is_left_out(tmp_path):
    n, per, inc = 1080, 6, math.radians(270) / 1080
    start = -math.radians(135) + inc / 2
    messages = []
    for k, t in enumerate(TIMES):
        ranges = laser_ranges(path_of(t), (0, 0, 0), start + inc * np.arange(n))
        for f in range(per):
            if (k, f) == (3, 2):
                continue   # a dropped message
            piece = slice(f * n // per, (f + 1) * n // per)
            messages.append((t + 0.01 * f, "/scan", SCAN, lambda ts, t=t, f=f, piece=piece, ranges=ranges: scan_message(
                ts, t + 0.01 * f, "laser", start + inc * piece.start, inc, ranges[piece])))
    report = ReadReport()
    read = list(read_rings(write_robot_bag(tmp_path / "dropped.bag", "ros1", messages), report=report))
    assert [round(r.time, 2) for r in read] == [t for k, t in enumerate(TIMES) if k != 3]
    assert report.assembly["/scan"][1:] == (len(TIMES) - 1, 1, per)
    assert report.lines()[0] == f"/scan: {len(TIMES) - 1} scans assembled from {len(messages)} messages (6 a revolution; 1 incomplete revolution left out)"


@KINDS
def test_two_lasers_make_one_ring_all_round(kind, tmp_path):
    # a front laser 0.3 m ahead and a rear one 0.3 m behind facing back, each 270 degrees, 0.02 s apart:
    # merged, the centred all-round laser's ring of a convex room
    front = whole_scans(TIMES, frame="front", walls=CONVEX, n=2160, mount=(0.3, 0.0, 0.0), topic="/scan_front")
    rear = whole_scans(TIMES + 0.02, frame="rear", walls=CONVEX, n=2160, mount=(-0.3, 0.0, math.pi),
                       topic="/scan_rear")
    bag = write_robot_bag(tmp_path / f"two-{kind}", kind, front + rear + [statics(
        0.0, ("base_link", "front", (0.3, 0.0, 0.2)), ("base_link", "rear", (-0.3, 0.0, 0.2), quaternion(yaw=math.pi)))])
    centred = write_robot_bag(tmp_path / f"all-round-{kind}", kind, whole_scans(TIMES, walls=CONVEX, n=4320,
                                                                               span=2 * math.pi))
    report = ReadReport()
    got = [r for r in read_rings(bag, Reading(topic=["/scan_front", "/scan_rear"]), report=report)]
    assert [r.time for r in got] == pytest.approx(list(TIMES))
    # within the beams' spacing and the robot's motion in the 0.02 s between the parts (1 cm, 0.34 degrees)
    np.testing.assert_allclose([r.ranges for r in got], rings(centred), atol=0.04)
    assert report.merged == (len(TIMES), 0)
    # beyond the tolerance, no pairs
    assert list(read_rings(bag, Reading(topic=["/scan_front", "/scan_rear"], tolerance=0.01))) == []


@pytest.mark.parametrize("start", [0.0, -math.pi, math.pi])
def test_a_360_lidars_ring_starts_at_the_front_whatever_its_first_angle(tmp_path, start):
    bag = write_robot_bag(tmp_path / "lidar.bag", "ros1", whole_scans(TIMES, n=720, span=2 * math.pi, start=start))
    reference = write_robot_bag(tmp_path / "reference.bag", "ros1", whole_scans(TIMES, n=720, span=2 * math.pi,
                                                                                start=0.0))
    got = rings(bag)
    np.testing.assert_array_equal(got, rings(reference))
    # sector 0 starts at the front: the nearest wall straight ahead at the first pose, (5 - x) / cos(yaw)
    x, _, yaw = path_of(TIMES[0])
    ahead = laser_ranges(path_of(TIMES[0]), (0, 0, 0), np.linspace(0, 2 * math.pi / 16, 46)[:-1])
    assert got[0][0] == pytest.approx(ahead.min(), abs=1e-5)


def test_read_sweeps_carries_the_mounts_to_the_sweep(tmp_path):
    bag = write_robot_bag(tmp_path / "offset.bag", "ros1", whole_scans(TIMES[:2], n=8, mount=(0.4, -0.2, 0.5)) + [
        statics(0.0, ("base_link", "laser", (0.4, -0.2, 0.2), quaternion(yaw=0.5)))])
    sweep = next(read_sweeps(bag))
    assert sweep.origins.tolist() == [[0.4, -0.2]] * 8 and sweep.frame == "base_link"
    inc = math.radians(270) / 8
    # (the message's float32 angles, exact to 1e-7)
    np.testing.assert_allclose(sweep.angles, 0.5 - math.radians(135) + inc / 2 + inc * np.arange(8), atol=1e-6)


@KINDS
def test_multi_echo_scans_read_the_echo_asked_for(kind, tmp_path):
    # every beam sees glass at 1 m (weak) and the wall behind it (strong): first, last, strongest
    def message(ts, t):
        n = 8
        walls = laser_ranges(path_of(t), (0, 0, 0), -1.0 + 0.25 * np.arange(n))

        def echoes(rows):
            return [_make(ts, "sensor_msgs/msg/LaserEcho", echoes=np.asarray(r, np.float32)) for r in rows]

        return _make(ts, "sensor_msgs/msg/MultiEchoLaserScan", header=_header(ts, t, "laser"), angle_min=-1.0,
                     angle_max=0.75, angle_increment=0.25, range_min=0.1, range_max=30.0,
                     ranges=echoes([[1.0, w] for w in walls]), intensities=echoes([[5.0, 50.0]] * n))

    bag = write_robot_bag(tmp_path / f"echoes-{kind}", kind, [
        (t, "/echoes", "sensor_msgs/msg/MultiEchoLaserScan", lambda ts, t=t: message(ts, t)) for t in TIMES[:3]])
    walls = laser_ranges(path_of(TIMES[0]), (0, 0, 0), -1.0 + 0.25 * np.arange(8))
    first = next(read_rings(bag, Reading(sectors=2))).ranges
    last = next(read_rings(bag, Reading(sectors=2, echo="last"))).ranges
    strongest = next(read_rings(bag, Reading(sectors=2, echo="strongest"))).ranges
    assert first.tolist() == [1.0, 1.0]
    np.testing.assert_allclose(last, [walls[:4].min(), walls[4:].min()], rtol=1e-6)
    assert strongest.tolist() == last.tolist()
    with pytest.raises(ValueError, match="The 'echo' parameter of Reading must be one of 'first', 'last', "
                                         "'strongest'. Got 'loudest'"):
        next(read_rings(bag, Reading(echo="loudest")))


@KINDS
def test_sonars_are_ordered_by_their_mounting_angles_from_tf(kind, tmp_path):
    # three sonars whose frame names say nothing of where they point: left, front, right
    mounts = {"sonar_a": math.pi / 2, "sonar_b": 0.0, "sonar_c": -math.pi / 2}
    messages = [statics(0.0, *[("base_link", f, (0.1 * math.cos(a), 0.1 * math.sin(a), 0.2), quaternion(yaw=a))
                               for f, a in mounts.items()])]
    for t in TIMES[:4]:
        for j, (frame, a) in enumerate(mounts.items()):
            r = float(laser_ranges(path_of(t), (0.1 * math.cos(a), 0.1 * math.sin(a), a), [0.0])[0])
            messages.append((t + 0.01 * j, "/sonar", "sensor_msgs/msg/Range", lambda ts, t=t, j=j, frame=frame, r=r: _make(
                ts, "sensor_msgs/msg/Range", header=_header(ts, t + 0.01 * j, frame), field_of_view=0.5,
                min_range=0.05, max_range=10.0, range=r)))
    bag = write_robot_bag(tmp_path / f"sonars-{kind}", kind, messages)
    report = ReadReport()
    ring = next(read_rings(bag, report=report))
    # counter-clockwise from the front: front (b), left (a), right (c, at 270 degrees)
    expected = [laser_ranges(path_of(TIMES[0]), (0.1 * math.cos(a), 0.1 * math.sin(a), a), [0.0])[0]
                for a in (0.0, math.pi / 2, -math.pi / 2)]
    np.testing.assert_allclose(ring.ranges, expected, rtol=1e-6)
    assert report.notes == ["sonars in the order of their mounting angles from tf: sonar_b 0 deg, sonar_a 90 deg, "
                            "sonar_c 270 deg"]


def test_a_mount_naming_no_topic_read_is_refused(tmp_path):
    bag = write_robot_bag(tmp_path / "one.bag", "ros1", whole_scans(TIMES[:2], n=8))
    with pytest.raises(ValueError, match=r"A mount is given for /scna, which is not a scan topic read \(/scan\)"):
        next(read_sweeps(bag, Reading(mounts=["/scna=0.1,0,0"])))
    assert next(read_sweeps(bag, Reading(mounts=["/scan=0.1,0,0"]))).origins[0].tolist() == [0.1, 0.0]


def test_poses_that_interpolate_to_no_number_are_refused_with_their_topic_and_time(tmp_path):
    # finite odometry at +-1e308: between two samples, x = p + f (q - p) overflows
    far = [(0.0, (1e308, 0.0, 0.0)), (1.0, (-1e308, 0.0, 0.0))]
    bag = write_robot_bag(tmp_path / "far.bag", "ros1", whole_scans([0.5], n=8) + [
        (t, "/odom", "nav_msgs/msg/Odometry", lambda ts, t=t, p=p: odometry(ts, t, p)) for t, p in far])
    with pytest.raises(ValueError, match=r"far.bag: the robot's pose at 0.500 s, interpolated from /odom, is not "
                                         r"finite \(x nan"):
        list(read_sweeps(bag, Reading(pose_topic="/odom")))


def test_a_transform_tf2_would_skip_is_skipped_and_counted_with_where_it_is(tmp_path):
    def bad(t, parent, child, q):
        return (t, "/tf", TF, lambda ts: tf_message(ts, [transform(ts, t, parent, child, (0.0, 0.0, 0.0), q)]))

    bag = write_robot_bag(tmp_path / "bad-tf.bag", "ros1", whole_scans(TIMES, n=8) + odom_tf(TF_TIMES) + [
        bad(0.51, "odom", "base_link", (0.0, 0.0, 0.0, 0.0)), bad(0.53, "odom", "odom", (0.0, 0.0, 0.0, 1.0))])
    report = ReadReport()
    read = list(read_sweeps(bag, report=report))
    assert len(read) == len(TIMES) and all(s.pose is not None for s in read)
    assert f"2 transforms skipped, as tf2 skips them (the first: {bag}, topic /tf, message 27: odom -> base_link at " \
           "0.510 s: a zero quaternion (0.0, 0.0, 0.0, 0.0), which is no rotation.)" in report.lines()


def test_a_deep_tf_chain_costs_a_bounded_time_and_is_said(tmp_path):
    # 2,000 frames in one chain down to the laser: each transform beyond the depth bound is skipped
    chain = [(f"f{k}", f"f{k + 1}", (0.001, 0.0, 0.0)) for k in range(2000)] + [("f2000", "base_link")]
    bag = write_robot_bag(tmp_path / "deep.bag", "ros1", whole_scans(TIMES[:3], n=8) + [statics(0.0, *chain)])
    report = ReadReport()
    started = time.process_time()
    read = list(read_sweeps(bag, report=report))
    assert time.process_time() - started < 10 and len(read) == 3
    assert any(line.endswith(f"transforms skipped, as tf2 skips them (the first: {bag}, topic /tf_static, message 1: "
                             "f99 -> f100 at 0.000 s: makes a chain of 101 frames; at most 100 are read "
                             "(novelty.io.ros.caps.MAX_TF_DEPTH).)") for line in report.lines()), report.lines()


@pytest.fixture
def read(monkeypatch) -> list:
    """The topic of each message a bag gives, as it is read."""
    topics = []
    messages = Bag.messages

    def counted(self, *args, **kwargs):
        for message in messages(self, *args, **kwargs):
            topics.append(message[0])
            yield message

    monkeypatch.setattr(Bag, "messages", counted)
    return topics


def test_a_topic_that_stops_before_its_fragments_are_learned_holds_the_others_scans_a_bounded_time(tmp_path, read):
    # /scan_b's 50 messages come in its first 5 s, then no more; /scan_a's scans go on for 100 s
    a = whole_scans(np.round(np.arange(0.0, 100.0, 0.1), 3), frame="a", n=8, topic="/scan_a")
    b = whole_scans(np.round(np.arange(0.05, 5.0, 0.1), 3), frame="b", n=8, topic="/scan_b")
    bag = write_robot_bag(tmp_path / "stops.bag", "ros1", a + b)
    sweeps = read_sweeps(bag, Reading(topic=["/scan_a", "/scan_b"]))
    next(sweeps)
    assert len(read) < 300   # before, the first sweep came after all 1,050 messages were read and held
    assert sum(1 for _ in sweeps) == 49   # the other 49 of /scan_b's 50, merged


def test_scans_waiting_for_poses_that_never_come_hold_a_bounded_number_of_beams(tmp_path, monkeypatch, read):
    # 400 scans stamped alike (a driver's clock stuck at 5 s) and odometry that ends at 1 s: each scan waits
    # for poses past its time, which never come, while the recording's time stands still
    angles = np.linspace(-1.0, 1.0, 8)
    stuck = [(1.0 + k * 0.01, "/scan", SCAN, lambda ts: scan_message(ts, 5.0, "laser", -1.0, angles[1] - angles[0],
                                                                       np.ones(8))) for k in range(400)]
    odom = [(t, "/odom", "nav_msgs/msg/Odometry", lambda ts, t=t: odometry(ts, t, path_of(t))) for t in TF_TIMES[:50]]
    bag = write_robot_bag(tmp_path / "stuck.bag", "ros1", stuck + odom)
    monkeypatch.setattr(caps, "MAX_WAITING_BEAMS", 80)   # ten scans of 8 beams
    sweeps = read_sweeps(bag, Reading(topic="/scan", pose_topic="/odom"))
    first = next(sweeps)
    # the odometry, the messages its fragments are learned from, then ten scans waiting: before, all 450 messages
    assert len(read) <= 50 + LEARN + 11 and first.pose is None   # its pose never came
    assert 1 + sum(1 for _ in sweeps) == 400


def test_a_mount_where_no_laser_is_placed_is_refused(tmp_path):
    log = tmp_path / "tiny.log"
    log.write_text("FLASER 4 1.0 2.0 3.0 8.0 0.0 0.0 0.0 0.0 0.0 0.0 10.0 robot 10.0\n")
    with pytest.raises(ValueError, match=r"tiny.log is a CARMEN log, whose lasers are read as it records them, and "
                                         r"no mount would be read: give none"):
        next(read_rings(log, Reading(mounts="0.2,0,0")))
    sonar = write_robot_bag(tmp_path / "sonar.bag", "ros1", [(t, "/sonar", "sensor_msgs/msg/Range", lambda ts, t=t: _make(
        ts, "sensor_msgs/msg/Range", header=_header(ts, t, "s0"), min_range=0.1, max_range=5.0, range=1.0))
        for t in (1.0, 2.0)])
    with pytest.raises(ValueError, match="/sonar holds sonars' Range readings, and no mount would be read"):
        next(read_rings(sonar, Reading(mounts="/sonar=0.2,0,0")))
