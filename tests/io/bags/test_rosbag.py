"""ROS bags: ROS 1, ROS 2 SQLite and MCAP written by rosbags' writers, read back message by message."""

import itertools
import math

import numpy as np
import pytest

from novelty.io.ros.messages import LaserScan, Pose, RangeReading

pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                    "'novelty-habituation[ros]'")

from novelty.io.bags.rosbag import BagError, bag_topics, is_bag, read_bag  # noqa: E402

from ...io.bag_files import SCAN_TIMES, SONAR, write_bag  # noqa: E402

KINDS = ("ros1", "sqlite3", "mcap")


@pytest.fixture(scope="module", params=KINDS)
def bag(request, tmp_path_factory):
    return write_bag(tmp_path_factory.mktemp(request.param), request.param)


def test_topics_and_types(bag):
    assert bag_topics(bag) == {"/cloud": "sensor_msgs/msg/PointCloud2", "/odom": "nav_msgs/msg/Odometry",
                               "/scan": "sensor_msgs/msg/LaserScan",
                               "/sonar": "sensor_msgs/msg/Range", "/tf": "tf2_msgs/msg/TFMessage"}


def test_laser_scans_with_header_stamps(bag):
    scans = list(read_bag(bag, "/scan"))
    assert all(isinstance(s, LaserScan) for s in scans)
    np.testing.assert_allclose([s.stamp for s in scans], SCAN_TIMES, atol=1e-9, rtol=0)
    first, second = scans[:2]
    assert first.ranges.tolist() == [1.0, math.inf, 2.0, 3.0]
    assert np.isnan(second.ranges[0]) and second.ranges[2] == -math.inf
    assert (first.range_min, first.range_max) == pytest.approx((0.1, 10.0))
    np.testing.assert_allclose(first.angles, np.deg2rad([-90, -30, 30, 90]), atol=1e-6)


def test_ranges_and_poses(bag):
    messages = list(read_bag(bag, ["/sonar", "/odom"]))
    sonar = [m for m in messages if isinstance(m, RangeReading)]
    poses = [m for m in messages if isinstance(m, Pose)]
    # one Range topic (with another topic): each reading's sensor is its frame
    assert [r.sensor for r in sonar][:3] == ["s2", "s0", "s1"] and len(sonar) == len(SONAR)
    assert [r.range for r in sonar] == [r for _, _, r in SONAR]
    assert [(p.x, p.source) for p in poses] == [(0.95, "/odom"), (1.15, "/odom"), (5.95, "/odom")]
    assert poses[0].theta == pytest.approx(0.5)
    assert [r.sensor for r in read_bag(bag, "/sonar")][:3] == ["s2", "s0", "s1"]


def test_tf_gives_the_robots_frame_only(bag):
    poses = list(read_bag(bag, "/tf"))
    assert [(p.x, p.source) for p in poses] == [(10.95, "/tf"), (11.15, "/tf"), (15.95, "/tf")]
    assert poses[0].theta == pytest.approx(0.5)
    assert [p.x for p in read_bag(bag, "/tf", base_frame="/laser")] == [0.0] * 3   # base_link -> laser alone
    assert list(read_bag(bag, "/tf", base_frame="base_footprint")) == []


def test_a_point_cloud_flattened_into_a_scan_all_round(bag):
    (scan,) = list(read_bag(bag, "/cloud"))
    assert len(scan.ranges) == 360 and scan.angle_min == pytest.approx(-math.pi)
    # (1, 0) at 0 degrees: beam 180; (0, 2) and (0, 1.5) at 90 degrees: beam 270, the nearer; NaN left out
    seen = {int(i): float(r) for i, r in enumerate(scan.ranges) if np.isfinite(r)}
    assert seen == {180: 1.0, 270: 1.5} and scan.stamp == pytest.approx(1.05)


def test_reading_is_lazy(bag):
    first = next(read_bag(bag, "/scan"))
    assert first.stamp == 1.0   # the header's stamp, not the record time (1.000001)
    assert len(list(itertools.islice(read_bag(bag, "/scan"), 2))) == 2


def test_a_missing_topic_lists_what_exists(bag):
    with pytest.raises(BagError, match=r"no topic '/laser'; its topics: /cloud \(sensor_msgs/msg/PointCloud2\), "
                                       r"/odom \(nav_msgs/msg/Odometry\), /scan \(sensor_msgs/msg/LaserScan\)"):
        next(read_bag(bag, "/laser"))


def test_files_that_are_not_bags(tmp_path):
    for name in ("junk.bag", "junk.db3", "junk.mcap"):
        (tmp_path / name).write_text("not a bag at all")
        with pytest.raises(BagError, match="is not a readable bag"):
            bag_topics(tmp_path / name)
    (tmp_path / "scans.csv").write_text("1,2\n")
    assert not is_bag(tmp_path / "scans.csv")
    with pytest.raises(BagError, match="expected a ROS 1 .bag, a ROS 2 .db3 or .mcap"):
        bag_topics(tmp_path / "scans.csv")
    with pytest.raises(FileNotFoundError):
        bag_topics(tmp_path / "absent.bag")


def test_an_unsupported_type_names_the_supported(tmp_path):
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    path = tmp_path / "strings.bag"
    with Writer(path) as writer:
        connection = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=ts)
        writer.write(connection, 1, ts.serialize_ros1(ts.types["std_msgs/msg/String"](data="hi"),
                                                      "std_msgs/msg/String"))
    with pytest.raises(BagError, match="holds std_msgs/msg/String, not read here; supported: "
                                       "sensor_msgs/msg/LaserScan"):
        next(read_bag(path, "/chatter"))
