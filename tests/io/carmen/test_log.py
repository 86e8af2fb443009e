"""CARMEN logs: every message read field by field, errors with their line, lazy reading, the Radish logs."""

import gzip
import itertools
import math

import numpy as np
import pytest

from novelty.io.carmen.log import CarmenError, CarmenLog, read_carmen
from novelty.io.ros.messages import LaserScan, Pose

LOG = """\
# CARMEN Laser Message Log
# message formats defined: PARAM SYNC ODOM FLASER RLASER ROBOTLASER1
PARAM robot_front_laser_max 50 nohost 0
ODOM 1.0 2.0 0.5 0.3 0.0 0.0 10.25 host 10.26
FLASER 5 1.0 2.0 3.0 4.0 5.0 0.5 0.25 0.125 0.5 0.25 0.1 10.5 host 10.51
NEFF 15
RLASER 3 7.0 8.0 9.0 -1.0 -2.0 3.0 -1.0 -2.0 3.0 11.0 host 11.01
ROBOTLASER1 0 -1.0 2.0 1.0 30.0 0.01 0 3 1.5 2.5 3.5 2 9 9 4.0 5.0 0.75 4.0 5.0 0.25 0 0 0 0 0 12.0 host 12.01
SYNC tag
"""


@pytest.fixture
def log(tmp_path):
    path = tmp_path / "tiny.log"
    path.write_text(LOG)
    return path


def test_every_message_read_field_by_field(log):
    reader = CarmenLog(log)
    odom, front, rear, robot = list(reader)
    assert isinstance(odom, Pose) and (odom.stamp, odom.x, odom.y, odom.theta) == (10.25, 1.0, 2.0, 0.5)
    assert isinstance(front, LaserScan) and front.stamp == 10.5 and front.source == "FLASER"
    assert front.ranges.tolist() == [1.0, 2.0, 3.0, 4.0, 5.0]
    assert front.pose.tolist() == [0.5, 0.25, 0.125]
    # a 180-degree scan, first beam at the robot's right: 5 beams 45 degrees apart
    np.testing.assert_allclose(np.rad2deg(front.angles), [-90, -45, 0, 45, 90])
    # the rear laser looks backwards: its first beam at 180 - 90 = 90 degrees (the robot's left)
    np.testing.assert_allclose(np.rad2deg(rear.angles), [90, 180, 270])
    # ROBOTLASER1: start -1 rad, 1 rad apart, the laser turned 0.75 - 0.25 = 0.5 rad from the robot
    assert robot.ranges.tolist() == [1.5, 2.5, 3.5] and robot.range_max == 30.0
    np.testing.assert_allclose(robot.angles, [-0.5, 0.5, 1.5])
    assert robot.pose.tolist() == [4.0, 5.0, 0.25] and robot.stamp == 12.0
    assert dict(reader.skipped) == {"PARAM": 1, "NEFF": 1, "SYNC": 1}


def test_gzip_is_read_alike_whatever_its_name(tmp_path, log):
    packed = tmp_path / "tiny.dat"
    packed.write_bytes(gzip.compress(log.read_bytes()))
    plain = [m.stamp for m in read_carmen(log)]
    assert [m.stamp for m in read_carmen(packed)] == plain == [10.25, 10.5, 11.0, 12.0]


def test_only_the_messages_asked_for(log):
    reader = CarmenLog(log, messages=["FLASER"])
    assert [m.source for m in reader] == ["FLASER"]
    assert reader.skipped["ODOM"] == 1 and reader.skipped["ROBOTLASER1"] == 1


def test_fov_spreads_old_lasers(log):
    front = next(m for m in CarmenLog(log, messages=["FLASER"], fov=math.pi / 2))
    np.testing.assert_allclose(np.rad2deg(front.angles), [-45, -22.5, 0, 22.5, 45])


def test_reading_stops_where_the_caller_stops(tmp_path):
    path = tmp_path / "bad-later.log"
    path.write_text(LOG.replace("SYNC tag", "FLASER 3 1 2"))   # a truncated last line
    first_two = list(itertools.islice(read_carmen(path), 2))
    assert [type(m) for m in first_two] == [Pose, LaserScan]
    with pytest.raises(CarmenError, match=r"line 9 \(FLASER\).*truncated"):
        list(read_carmen(path))


@pytest.mark.parametrize("text, match", [
    ("x,y,z\n1,2,3\n", "line 1: not a CARMEN log"),
    ("ODOM 1 2 3 0 0 0 5.0 h 5.0\nodom 1 2\n", "line 2: a corrupt line"),
    ("ODOM 1 2 three 0 0 0 5.0 h 5.0\n", r"line 1 \(ODOM\).*'three' is not a number"),
    ("FLASER 2.5 1 2 0 0 0 0 0 0 1.0 h 1.0\n", "expected a count of readings"),
    ("FLASER 4 1 2 3 4 0 0 0\n", r"line 1 \(FLASER\).*truncated"),
    ("FLASER inf 1 2 0 0 0 0 0 0 1.0 h 1.0\n", r"line 1 \(FLASER\): the number of readings is 'inf'; expected a count"),
    ("ODOM 1 2 3 0 0 0 5.0 h 5.0\nFLASER nan 1 2 0 0 0 0 0 0 1.0 h 1.0\n",
     r"line 2 \(FLASER\): the number of readings is 'nan'; expected a count"),
    ("ODOM nan 2 3 0 0 0 5.0 h 5.0\n", r"line 1 \(ODOM\): x is nan; a pose must be finite"),
    ("FLASER 2 1 2 0 inf 0 0 0 0 1.0 h 1.0\n", r"line 1 \(FLASER\): y is inf; a pose must be finite"),
])
def test_bad_lines_name_their_line(tmp_path, text, match):
    path = tmp_path / "bad.log"
    path.write_text(text)
    with pytest.raises(CarmenError, match=match):
        list(read_carmen(path))


def test_binary_and_truncated_gzip_files(tmp_path, log):
    binary = tmp_path / "image.log"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\xff\xfe" * 10)
    with pytest.raises(CarmenError, match="not a CARMEN log"):
        list(read_carmen(binary))
    cut = tmp_path / "cut.log.gz"
    cut.write_bytes(gzip.compress(log.read_bytes() * 50)[:-30])
    with pytest.raises(CarmenError, match="truncated or corrupt"):
        list(read_carmen(cut))


def test_a_line_longer_than_any_log_line_is_refused(tmp_path, monkeypatch):
    from novelty.io.carmen import log as carmen

    monkeypatch.setattr(carmen, "MAX_LINE", 40)   # memory holds one line, of at most MAX_LINE characters
    path = tmp_path / "long.log"
    path.write_text("ODOM 1 2 3 0 0 0 5.0 h 5.0\nFLASER 9 " + "1.0 " * 30 + "\n")
    with pytest.raises(CarmenError, match="line 2: longer than 40 characters"):
        list(read_carmen(path))


def test_an_unknown_message_choice_or_field_of_view_is_refused(log):
    with pytest.raises(ValueError, match="choose among FLASER, RLASER, ROBOTLASER1, ODOM"):
        CarmenLog(log, messages=["LASER5"])
    with pytest.raises(ValueError, match="fov"):
        CarmenLog(log, fov=0.0)


def test_the_radish_logs_first_scans(radish):
    # the README's counts: 180 beams in intel and aces, 361 in csail
    for name, beams in [("intel", 180), ("aces", 180), ("csail", 361)]:
        scans = list(itertools.islice(read_carmen(radish / f"{name}-corrected.log.gz", ["FLASER"]), 5))
        assert [len(s.ranges) for s in scans] == [beams] * 5
        assert all(s.pose is not None and np.all(s.ranges > 0) for s in scans)
    first = next(read_carmen(radish / "intel-corrected.log.gz", ["FLASER"]))
    # the log's first FLASER line: ranges 1.09 1.08 ..., pose 0.600266 -0.0320327 -0.354665, time 32.9068
    assert first.ranges[:3].tolist() == [1.09, 1.08, 1.08] and first.stamp == 32.9068
    assert first.pose.tolist() == [0.600266, -0.0320327, -0.354665]
