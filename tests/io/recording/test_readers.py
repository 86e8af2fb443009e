"""Recordings as rings and datasets: CARMEN logs and bags, lasers and sonars, with poses."""

import gzip
import itertools
import math

import numpy as np
import pytest

from novelty.io.recording.readers import is_recording, read_recording, read_rings
from novelty.io import Reading

from ...io.carmen.test_log import LOG


@pytest.fixture
def carmen(tmp_path):
    path = tmp_path / "run.log.gz"
    path.write_bytes(gzip.compress(LOG.encode()))
    return path


def test_carmen_rings_with_the_scans_own_poses(carmen):
    # FLASER 1..5 m at -90, -45, 0, 45, 90 degrees: two sectors, right (-112.5..0) and left (0..112.5)
    (ring,) = list(read_rings(carmen, Reading(sectors=2)))
    assert ring.ranges.tolist() == [1.0, 3.0] and ring.time == 10.5
    assert ring.pose.tolist() == [0.5, 0.25, 0.125]
    (odom,) = list(read_rings(carmen, Reading(sectors=2, pose_topic="ODOM")))
    assert odom.pose.tolist() == [1.0, 2.0, 0.5]          # the odometry before the scan
    (robot,) = list(read_rings(carmen, Reading(topic="ROBOTLASER1", sectors=3)))
    assert robot.ranges.tolist() == [1.5, 2.5, 3.5]
    # the rear laser's beams at 90, 180, 270 degrees (through the back): one ring in one piece
    (rear,) = list(read_rings(carmen, Reading(topic="RLASER", sectors=3)))
    assert rear.ranges.tolist() == [7.0, 8.0, 9.0]


def test_carmen_without_the_laser_asked_for(tmp_path):
    path = tmp_path / "odom.log"
    path.write_text("ODOM 1 2 3 0 0 0 5.0 h 5.0\nPARAM a b h 0\n")
    with pytest.raises(ValueError, match=r"holds no FLASER messages; it holds: ODOM \(1\), PARAM \(1\)"):
        list(read_rings(path))
    with pytest.raises(ValueError, match="one of FLASER, RLASER, ROBOTLASER1"):
        list(read_rings(path, Reading(topic="ODOM")))


def test_dataset_preprocessed_with_time_pose_and_distance(carmen, tmp_path):
    data = read_recording(carmen, Reading(sectors=2))
    assert data.X.tolist() == [[0.75, 0.25]]              # 1 - r / 4
    assert data.columns["time"].tolist() == [10.5] and data.distance.tolist() == [0.0]
    raw = read_recording(carmen, Reading(sectors=2, threshold=None))
    assert raw.X.tolist() == [[1.0, 3.0]]
    assert is_recording(carmen) and is_recording(tmp_path / "a.bag") and not is_recording(tmp_path / "a.csv")
    with pytest.raises(ValueError, match="neither a CARMEN log"):
        list(read_rings(tmp_path / "a.csv"))


@pytest.fixture(scope="module", params=("ros1", "sqlite3", "mcap"))
def bag(request, tmp_path_factory):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                        "'novelty-habituation[ros]'")
    from ...io.bag_files import write_bag

    return write_bag(tmp_path_factory.mktemp(request.param), request.param)


def test_laser_rings_from_a_bag(bag):
    rings = list(read_rings(bag, Reading(topic="/scan", sectors=2, pose_topic="/odom")))
    # 4 beams at -90, -30, 30, 90 degrees; range 0.1..10: [1, inf | 2, 3] and [NaN, 1.5 | -inf -> 0.1, 12 -> NaN]
    assert [r.ranges.tolist() for r in rings[:2]] == [[1.0, 2.0], [1.5, pytest.approx(0.1)]]
    # odometry at 0.95, 1.15, 5.95 s (its x is its time), interpolated at each scan's time; the scans at
    # 6.0 and 6.1 s, after the last, hold it (within 0.2 s)
    assert [round(r.pose[0], 2) for r in rings] == [1.0, 1.1, 1.2, 5.95, 5.95]
    data = read_recording(bag, Reading(topic="/scan", sectors=2, pose_topic="/odom"))
    np.testing.assert_allclose(data.distance, [0, 0.1, 0.2, 4.95, 4.95])


def test_sonar_rings_from_a_bag(bag):
    rings = list(read_rings(bag, Reading(topic="/sonar")))
    # frames s2, s0, s1 in turn; the ring in name order s0, s1, s2; range 0.2..5 (9 m: no information)
    assert [r.ranges.tolist() for r in rings] == [[1.0, math.inf, 3.0], [2.0, 0.5, 4.0], [math.inf, 1.0, 1.0]]
    assert [round(r.time, 2) for r in rings] == [1.02, 1.12, 6.02]
    mounted = list(read_rings(bag, Reading(topic="/sonar", sensors={"s1": -1.0, "s2": 0.0, "s0": 1.0})))
    assert mounted[0].ranges.tolist() == [math.inf, 3.0, 1.0]
    # with a pose topic the sonars are still told apart by their frames; tf gives base_link's pose
    placed = list(read_rings(bag, Reading(topic="/sonar", pose_topic="/tf")))
    assert [r.ranges.tolist() for r in placed] == [r.ranges.tolist() for r in rings]
    assert [r.pose[0] for r in placed] == pytest.approx([10.95, 10.95, 15.95])   # rings at 1.02, 1.12, 6.02 s


def test_one_topic_a_sonar(tmp_path):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra")
    from ...io.bag_files import write_sonar_topics

    path = write_sonar_topics(tmp_path / "sonars.bag")
    # the ring in the order the topics are given: front, back
    rings = list(read_rings(path, Reading(topic=["/front", "/back"])))
    assert [(round(r.time, 1), r.ranges.tolist()) for r in rings] == [(1.1, [1.0, 2.0]), (1.3, [3.0, 4.0])]


def test_point_cloud_rings_from_a_bag(bag):
    # the cloud's beams: 1 m at 0 degrees, 1.5 m at 90; four sectors all round from the robot's front:
    # front-left (0..90, holding the 0-degree beam), back-left (90.., the 90-degree beam), back-right, front-right
    (ring,) = list(read_rings(bag, Reading(topic="/cloud", sectors=4)))
    assert ring.ranges.tolist() == [1.0, 1.5, math.inf, math.inf]


def test_a_bag_needs_its_topic_named(bag):
    with pytest.raises(ValueError, match=r"Name the scans' topic.*/odom \(nav_msgs/msg/Odometry\)"):
        list(read_rings(bag))


def test_the_radish_logs_as_datasets(radish):
    data = read_recording(radish / "aces-corrected.log.gz", limit=50)
    assert data.X.shape == (50, 16) and data.poses.shape == (50, 3)
    assert np.all((data.X >= 0) & (data.X <= 1)) and np.all(np.diff(data.distance) >= 0)
    csail = next(itertools.islice(read_rings(radish / "csail-corrected.log.gz", Reading(sectors=8)), 3, None))
    assert csail.ranges.shape == (8,) and np.all(csail.ranges > 0)
