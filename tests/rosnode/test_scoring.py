"""The node's scoring without ROS: a bag's messages fed as a subscription delivers them, against ``novelty run``.

Each test writes a bag (tests/rosnode/bags.py), runs ``novelty run`` on it
(``--out`` an .npz: the novelty in float64, exactly), then feeds the bag's
messages' bytes, in the bag's order, to the scorer the node runs, with its
clock at each message's record time, and compares the novelty scan for scan,
exactly.
"""

import math

import numpy as np
import pytest

import novelty
from novelty.cli import main
from novelty.rosnode.setup import build

pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")

from ..io.scenes import write_robot_bag  # noqa: E402
from .bags import laser, messages, mounts, odometry_tf, pose_at, robot_bag  # noqa: E402


def offline(bag, tmp_path, detector, *options):
    out = tmp_path / f"offline-{detector}.npz"
    assert main(["run", detector, "--data", str(bag), "--out", str(out), *options]) == 0
    with np.load(out) as rows:
        return {k: rows[k] for k in rows.files}


def live(bag, params, clock=lambda record: record, end=True):
    """The scans the scorer scores from the bag's messages: (times, novelty), and the scorer."""
    scorer, _, _ = build(params, lambda name: name if name.startswith("/") else "/" + name)
    scored = []
    last = 0.0
    for topic, msgtype, record, data in messages(bag):
        last = clock(record)
        scored += scorer.take(topic, msgtype, data, record, last)
    if end:
        scored += scorer.tick(last + 10.0)
    return np.array([s.time for s in scored]), np.array([s.novelty for s in scored]), scorer


@pytest.mark.parametrize("detector", ["hsom", "kmeans-stanley", "map-explore"])
def test_a_bag_fed_to_the_scorer_scores_as_novelty_run(detector, tmp_path):
    bag = robot_bag(tmp_path / "robot.bag", seconds=4.0)
    expected = offline(bag, tmp_path, detector, "--topic", "/scan")
    times, got, scorer = live(bag, {"detector": detector})
    np.testing.assert_array_equal(got, expected["novelty"])
    np.testing.assert_array_equal(times, expected["time"])
    assert scorer.stats.scored == len(expected["novelty"]) == 40
    assert "from tf (base_link -> laser)" in scorer.reading.report.mounts["/scan"]


def test_the_scans_before_the_first_pose_are_the_ones_left_out(tmp_path):
    times = np.round(1.0 + np.arange(0.0, 3.0, 0.1), 6)
    # odometry from 1.55 s: the scans before 1.35 s (0.2 s before it, the tree's hold) have no pose to take
    bag = write_robot_bag(tmp_path / "late.bag", "ros1", laser(times) + odometry_tf(np.round(
        1.55 + np.arange(0, 2.6, 0.02), 6)) + [mounts(0.5, ("laser", (0.1, 0.0, 0.0), False))])
    expected = offline(bag, tmp_path, "map-explore")
    times_live, got, scorer = live(bag, {"detector": "map-explore"})
    np.testing.assert_array_equal(got, expected["novelty"])
    assert times_live[0] == 1.4 and len(got) == 26
    assert scorer.stats.skipped == {"no pose at its time": 4}


def test_an_upside_down_laser_off_the_centre_reads_as_offline(tmp_path):
    bag = robot_bag(tmp_path / "flipped.bag", seconds=3.0, mount=(0.2, -0.1, 0.5), flipped=True)
    expected = offline(bag, tmp_path, "map-explore")
    _, got, scorer = live(bag, {"detector": "map-explore"})
    np.testing.assert_array_equal(got, expected["novelty"])
    assert "upside down" in scorer.reading.report.mounts["/scan"]


def test_fragments_are_assembled_as_offline(tmp_path):
    # 12 revolutions a second of 4 fragments: the pattern is learned from the first 100 messages, as offline
    bag = robot_bag(tmp_path / "fragments.bag", seconds=4.0, rate=12.0, fragments=4, span=math.radians(270),
                    beams=540)
    expected = offline(bag, tmp_path, "hsom")
    _, got, scorer = live(bag, {"detector": "hsom"})
    np.testing.assert_array_equal(got, expected["novelty"])
    assert scorer.reading.assemblers["/scan"].per_revolution == 4


def test_stamps_give_the_detector_the_scans_times(tmp_path):
    bag = robot_bag(tmp_path / "robot.bag", seconds=2.0)
    expected = offline(bag, tmp_path, "hsom", "--stamps")
    _, got, _ = live(bag, {"detector": "hsom", "stamps": True})
    np.testing.assert_array_equal(got, expected["novelty"])
    assert not np.array_equal(got, offline(bag, tmp_path, "hsom")["novelty"])


def test_a_ring_is_scored_as_it_comes_a_row_of_points_when_its_pose_is_known(tmp_path):
    # /tf at 50 Hz, 13 ms after each scan's time and every 20 ms after
    times = np.round(1.0 + np.arange(0.0, 2.0, 0.1), 6)
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", laser(times) + odometry_tf(np.round(
        0.913 + np.arange(0, 2.2, 0.02), 6)) + [mounts(0.5, ("laser", (0.1, 0.0, 0.0), False))])
    scorer, _, _ = build({"detector": "map-explore", "fragments": 1}, lambda n: "/" + n)
    ring, _, _ = build({"detector": "hsom", "fragments": 1}, lambda n: "/" + n)
    waits = {"map-explore": [], "hsom": []}
    for topic, msgtype, record, data in messages(bag):
        for name, s in (("map-explore", scorer), ("hsom", ring)):
            for one in s.take(topic, msgtype, data, record, record):
                waits[name].append(record - one.time)
    # the ring as soon as its scan has come; the points once /tf has passed the scan's time
    assert len(waits["hsom"]) == len(waits["map-explore"]) == 20
    np.testing.assert_allclose(waits["hsom"], 0.0, atol=1e-9)
    np.testing.assert_allclose(waits["map-explore"], 0.013, atol=1e-9)


def test_the_model_saved_and_loaded_goes_on_as_one_that_never_stopped(tmp_path):
    bag = robot_bag(tmp_path / "robot.bag", seconds=3.0)
    _, whole, _ = live(bag, {"detector": "map-explore"})
    first = [m for m in messages(bag) if m[2] < 2.5]
    scorer, _, _ = build({"detector": "map-explore", "fragments": 1}, lambda n: "/" + n)
    for topic, msgtype, record, data in first:
        scorer.take(topic, msgtype, data, record, record)
    done = scorer.stats.scored
    scorer.save(tmp_path / "model.npz")
    again, _, _ = build({"model": str(tmp_path / "model.npz"), "fragments": 1}, lambda n: "/" + n)
    rest = []
    for topic, msgtype, record, data in messages(bag):
        # the latched mounts, and the transforms from just before, as a node started again meets them
        if record >= 2.45 or topic == "/tf_static":
            rest += again.take(topic, msgtype, data, record, record)
    rest += again.tick(1e9)
    assert done == 15 and rest[0].time == 2.5   # the first 15 scans (to 2.4 s) before the restart
    np.testing.assert_array_equal([s.novelty for s in rest], whole[len(whole) - len(rest):])
    assert done + len(rest) == len(whole) == 30


def test_freezing_scores_without_learning_and_reset_returns_to_the_start(tmp_path):
    bag = robot_bag(tmp_path / "robot.bag", seconds=2.0)
    scorer, _, _ = build({"detector": "hsom", "fragments": 1}, lambda n: "/" + n)
    rows = []
    for topic, msgtype, record, data in messages(bag):
        if topic == "/scan" and len(rows) == 10:
            scorer.set_learning(False)
        rows += scorer.take(topic, msgtype, data, record, record)
    det = novelty.make("hsom")
    expected = det.stream(np.array([r.row.x for r in rows[:10]]))
    np.testing.assert_array_equal([r.novelty for r in rows[:10]], expected)
    np.testing.assert_array_equal([r.novelty for r in rows[10:]], det.novelty(np.array([r.row.x for r in rows[10:]])))
    scorer.reset()
    assert not hasattr(scorer.detector, "n_features_in_")


def test_the_poses_are_those_of_the_robot(tmp_path):
    bag = robot_bag(tmp_path / "robot.bag", seconds=1.0)
    scorer, _, _ = build({"detector": "map-explore"}, lambda n: "/" + n)
    rows = []
    for topic, msgtype, record, data in messages(bag):
        rows += scorer.take(topic, msgtype, data, record, record)
    rows += scorer.tick(1e9)
    for one in rows:
        x, y, yaw = pose_at(one.time)
        np.testing.assert_allclose(one.row.pose[:2], (x, y), atol=2e-3)
        assert math.isclose(math.remainder(one.row.pose[2] - yaw, 2 * math.pi), 0.0, abs_tol=1e-3)
