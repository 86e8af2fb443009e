"""Sweeps: whole scans in the robot's base frame, and their rings seen from the robot's centre."""

import gzip
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from novelty.io import Reading, read_sweeps
from novelty.io.frames.mounts import Mount
from novelty.io.ros.messages import LaserScan, Sweep
from novelty.io.scans.sweep_rings import RingMaker, laser_ring, sweep_ring
from novelty.io.scans.sweeps import SweepMaker, scan_sweep

from ..carmen.test_log import LOG

INF, NAN = math.inf, math.nan


def sweep(angles_deg, ranges, origin=(0.0, 0.0)):
    angles = np.deg2rad(np.asarray(angles_deg, dtype=float))
    return Sweep(0.0, np.tile(origin, (len(angles), 1)).astype(float), angles, np.asarray(ranges, float), None)


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 200), st.floats(0.05, 2 * math.pi), st.floats(-4.0, 4.0), st.integers(1, 16),
       st.sampled_from(["min", "mean", "median", 25.0]), st.booleans(), st.integers(0, 2**32 - 1))
def test_centred_sweeps_give_todays_laser_rings_bit_for_bit(n, span, start, sectors, reduce, limited, seed):
    assume(sectors <= n)
    rng = np.random.default_rng(seed)
    ranges = rng.choice([0.05, 1.0, 2.5, 7.0, 12.0, INF, -INF, NAN], n) * rng.uniform(0.5, 1.5, n)
    scan = LaserScan(0.0, ranges, angle_min=start, angle_increment=span / n, range_min=0.1, range_max=10.0)
    limits = (-math.pi / 2, math.pi / 2) if limited else None
    try:
        expected = laser_ring(scan, sectors, reduce, limits, front=0.3)
    except ValueError:   # sectors the beams cannot fill are refused alike
        with pytest.raises(ValueError, match="hold no beam"):
            sweep_ring(scan_sweep(scan), sectors, reduce, limits, front=0.3)
        return
    got = sweep_ring(scan_sweep(scan), sectors, reduce, limits, front=0.3)
    assert got.tobytes() == expected.tobytes()


def test_an_offset_sensor_is_seen_from_the_centre_by_hand():
    # a laser 1 m behind the centre looking forward: beams at -45, 0, 45 degrees, 2 m, 3 m, sqrt(2) m
    s = sweep([-45, 0, 45], [2 * math.sqrt(2), 3.0, math.sqrt(2)], origin=(-1.0, 0.0))
    # end points (1, -2), (2, 0), (0, 1) from the centre: bearings -63.4, 0, 90 degrees
    # the scan's span -67.5..67.5 in 3 sectors of 45 degrees; the point at 90 degrees is beyond it
    ring = sweep_ring(s, 3)
    assert ring.tolist() == [pytest.approx(math.sqrt(5)), 2.0, INF]
    # the front half in two sectors: the point at 90 degrees is on the high limit, in the last sector
    assert sweep_ring(s, 2, limits=(-math.pi / 2, math.pi / 2)).tolist() == [pytest.approx(math.sqrt(5)), 1.0]
    # sectors that no beam's direction reaches are refused as for a centred laser
    with pytest.raises(ValueError, match="2 of 4 sectors hold no beam"):
        sweep_ring(s, 4, limits=(-math.pi, math.pi))


def test_beams_without_an_echo_keep_their_direction_and_nan_stays_out():
    s = sweep([-45, 45], [INF, NAN], origin=(5.0, 0.0))
    # +inf is nothing seen along the beam's own direction; NaN is no information (+inf once reduced)
    assert sweep_ring(s, 2).tolist() == [INF, INF]
    s = sweep([-45, 45], [INF, 1.0], origin=(0.0, -1.0))
    # the second beam's end point is (0.707, -0.293): seen at -22.5 degrees, in the right-hand sector
    assert sweep_ring(s, 2).tolist() == [pytest.approx(math.hypot(math.sqrt(0.5), 1 - math.sqrt(0.5))), INF]


def test_a_ring_maker_reuses_a_geometry_and_tells_geometries_apart():
    make = RingMaker(2)
    a = sweep([-90, -30, 30, 90], [1.0, 2.0, 3.0, 4.0])
    b = sweep([0, 60, 120, 180], [1.0, 2.0, 3.0, 4.0])
    assert make(a).tolist() == [1.0, 3.0] and make(b).tolist() == [1.0, 3.0] and make(a).tolist() == [1.0, 3.0]
    assert len(make._known) == 2
    with pytest.raises(ValueError, match="reduce must be"):
        RingMaker(2, "max")


@pytest.fixture
def carmen(tmp_path):
    path = tmp_path / "run.log.gz"
    path.write_bytes(gzip.compress(LOG.encode()))
    return path


def test_carmen_sweeps(carmen, tmp_path):
    (front,) = list(read_sweeps(carmen))
    np.testing.assert_allclose(np.rad2deg(front.angles), [-90, -45, 0, 45, 90])
    assert front.origins.tolist() == [[0.0, 0.0]] * 5 and front.pose.tolist() == [0.5, 0.25, 0.125]
    assert (front.time, front.source, front.frame) == (10.5, "FLASER", "")
    (narrow,) = list(read_sweeps(carmen, Reading(fov=math.pi / 2)))
    np.testing.assert_allclose(np.rad2deg(narrow.angles), [-45, -22.5, 0, 22.5, 45])
    # ROBOTLASER1 states the laser's pose and the robot's in the world: the laser 0.3 m ahead, 0.1 m left
    yaw = 0.25
    lx, ly = 4.0 + 0.3 * math.cos(yaw) - 0.1 * math.sin(yaw), 5.0 + 0.3 * math.sin(yaw) + 0.1 * math.cos(yaw)
    line = (f"ROBOTLASER1 0 -1.0 2.0 1.0 30.0 0.01 0 3 1.5 2.5 3.5 0 {lx} {ly} 0.75 4.0 5.0 {yaw} "
            "0 0 0 0 0 12.0 host 12.01\n")
    (tmp_path / "robot.log").write_text(line)
    (robot,) = list(read_sweeps(tmp_path / "robot.log", Reading(topic="ROBOTLASER1")))
    np.testing.assert_allclose(robot.origins, [[0.3, 0.1]] * 3, atol=1e-12)
    np.testing.assert_allclose(robot.angles, [-0.5, 0.5, 1.5])


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra")
    from ..bag_files import write_bag

    return write_bag(tmp_path_factory.mktemp("ros1"), "ros1")


def test_bag_sweeps_are_cleaned_and_share_their_geometry(bag):
    sweeps = list(read_sweeps(bag, Reading(topic="/scan", pose_topic="/odom")))
    assert len(sweeps) == 5 and sweeps[0].source == "/scan"
    # range 0.1..10: +inf kept, -inf -> range_min, 12 m -> NaN
    assert sweeps[0].ranges.tolist() == [1.0, INF, 2.0, 3.0]
    assert sweeps[1].ranges[2] == pytest.approx(0.1) and np.isnan(sweeps[1].ranges[3])
    assert all(s.angles is sweeps[0].angles for s in sweeps) and not sweeps[0].angles.flags.writeable
    assert [round(s.pose[0], 2) for s in sweeps] == [1.0, 1.1, 1.2, 5.95, 5.95]
    with pytest.raises(ValueError, match="Sweeps are read from LaserScan, MultiEchoLaserScan or PointCloud2 "
                                         "topics; /sonar holds sensor_msgs/msg/Range"):
        next(read_sweeps(bag, Reading(topic="/sonar")))


def test_one_message_at_a_time_gives_the_sweeps_a_file_reader_gives(bag):
    # what a live node does with each message: its mount, then SweepMaker; the bag's reader does the same
    from novelty.io import read_bag
    from novelty.io.frames.mounts import parse_mount

    reading = Reading(topic="/scan", mounts="0.3,0.1,90,flipped", fragments=1)
    offline = list(read_sweeps(bag, reading))
    _, mount = parse_mount("0.3,0.1,90,flipped")
    maker = SweepMaker(offline[0].frame)   # the base frame and the poses: a node's own tf lookups
    live = [maker(scan, mount, sweep.pose, "/scan") for scan, sweep in zip(read_bag(bag, "/scan"), offline)]
    assert len(live) == len(offline) == 5
    for a, b in zip(live, offline):
        assert (a.time, a.frame, a.source, a.pose is b.pose) == (b.time, b.frame, b.source, True)
        for field in ("origins", "angles", "ranges"):
            np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    assert RingMaker(4)(live[0]).tolist() == RingMaker(4)(offline[0]).tolist()


def test_scan_sweep_with_a_mount_is_one_message_of_a_sweep_maker():
    scan = LaserScan(2.0, np.array([1.0, np.inf, -np.inf]), angle_min=-1.0, angle_increment=1.0, range_min=0.2,
                     source="/scan")
    mount = Mount.planar(0.5, -0.25, math.pi / 2)
    one = scan_sweep(scan, None, "base_link", mount=mount)
    many = SweepMaker("base_link")(scan, mount, None, "/scan")
    for field in ("origins", "angles", "ranges"):
        np.testing.assert_array_equal(getattr(one, field), getattr(many, field))
    assert one.origins.tolist() == [[0.5, -0.25]] * 3 and one.ranges.tolist() == [1.0, INF, 0.2]
    np.testing.assert_allclose(one.angles, [-1.0 + math.pi / 2, math.pi / 2, 1.0 + math.pi / 2])
