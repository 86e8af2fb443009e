"""The node against a real ROS master: bags played with ``rosbag play``, what it publishes recorded with ``rosbag record``.

Each test starts ``novelty node`` (a process of its own) on a master of the
module's own (a free loopback port: tests/rosnode/ros.py), with
``/use_sim_time`` set, plays bags written here (tests/rosnode/bags.py) with
``rosbag play --clock``, records what the node publishes and compares it
with ``novelty run`` on the same bags, exactly.
"""

import time

import numpy as np
import pytest

import novelty
from novelty.cli import main
from novelty.rosnode.setup import build

from .ros import Master, recorded, skip_without_ros

skip_without_ros()
pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")

from ..io.scenes import write_robot_bag  # noqa: E402
from .bags import laser, messages, mounts, odometry_tf  # noqa: E402

pytestmark = pytest.mark.slow

#: seconds the node may take, after a bag has played, to score the scans it holds (its transform timeout is 1 s)
SETTLE = 3.0


@pytest.fixture(scope="module")
def master(tmp_path_factory):
    master = Master(tmp_path_factory.mktemp("ros")).start()
    master.run(["rosparam", "set", "/use_sim_time", "true"])
    yield master
    master.stop()


def drive(times, tf_times, *, mount=(0.2, -0.1, 0.5), flipped=True, **options):
    """An upside-down laser off the robot's centre, /tf at ``tf_times``, its mount on /tf_static."""
    return laser(times, mount=mount, flipped=flipped, **options) + odometry_tf(tf_times) + [
        mounts(0.6, ("laser", mount, flipped))]


def offline(bag, folder, detector, *options):
    """``novelty run``'s rows of the bag (.npz: the novelty exactly), and what it said on standard error."""
    out = folder / f"offline-{detector}.npz"
    assert main(["run", detector, "--data", str(bag), "--out", str(out), *options]) == 0
    with np.load(out) as rows:
        return {k: rows[k] for k in rows.files}


def run_node(master, folder, name, bags, *params, play=(), between=None):
    """Start the node, record what it publishes while ``bags`` play one after another, stop it (SIGINT).

    ``between(i)`` runs after the i-th bag has played and settled. Returns ``(recorded messages by
    topic, the node's exit status, its standard error)``.
    """
    # a queue as long as a bag: the scans held while the reading learns the scanner's pattern of fragments (the
    # first 100) are scored in one burst, during which no scan must be dropped
    node = master.node("_queue_size:=500", *params, name=name)
    master.wait_for_node(node, f"/{name}")
    topics = [f"/{name}/novelty_stamped", f"/{name}/novelty", f"/{name}/alarm", f"/{name}/novel_cells", "/diagnostics"]
    recorder = master.record(folder / f"{name}.bag", *topics)
    for i, bag in enumerate(bags):
        master.play(bag, "--wait-for-subscribers", *play)
        time.sleep(SETTLE)
        if between is not None:
            between(i)
    time.sleep(1.5)   # one more second of diagnostics
    code = node.stop()
    recorder.stop()
    return recorded(folder / f"{name}.bag"), code, node.errors()


def diagnostics(messages, name) -> dict:
    """The node's last diagnostics as a dict of its values (and its message)."""
    mine = [s for m in messages["/diagnostics"] for s in m.status if s.name == f"novelty: /{name}"]
    return {**{kv.key: kv.value for kv in mine[-1].values}, "message": mine[-1].message}


def stamps(messages) -> np.ndarray:
    """The messages' header stamps (ns)."""
    return np.array([m.header.stamp.to_nsec() for m in messages])


@pytest.mark.parametrize("detector", ["map-explore", "hsom"])
def test_the_novelty_published_while_a_bag_plays_is_what_novelty_run_writes(master, tmp_path, detector):
    # an upside-down laser off the centre at 20 Hz for 8 s (the first 100 scans held while the reading learns
    # whether they come in fragments, as novelty run holds them); /tf from 1.45 s (the first scans have no pose)
    # with a gap from 4.0 to 6.0 s (longer than a scan waits for its pose: some scans in it have none)
    # (/tf at 20 Hz half-way between the scans: messages of two topics a few milliseconds apart may reach the
    # node in either order, the bag's order is one of them)
    times = np.round(1.0 + np.arange(0.0, 8.0, 0.05), 6)
    tf_times = np.round(1.475 + np.arange(0.0, 7.8, 0.05), 6)
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", drive(times, tf_times[(tf_times < 4.0) | (tf_times > 6.0)]))
    expected = offline(bag, tmp_path, detector, "--topic", "/scan")
    name = f"novelty_{detector.replace('-', '_')}"
    got, code, err = run_node(master, tmp_path, name, [bag], f"_detector:={detector}")
    assert code == 0, err
    stamped = got[f"/{name}/novelty_stamped"]
    np.testing.assert_array_equal([m.vector.x for m in stamped], expected["novelty"])
    np.testing.assert_array_equal(stamps(stamped), np.round(expected["time"] * 1e9).astype(np.int64))
    np.testing.assert_array_equal([m.data for m in got[f"/{name}/novelty"]], expected["novelty"].astype(np.float32))
    np.testing.assert_array_equal([m.data for m in got[f"/{name}/alarm"]], expected["alarm"] == 1)
    status = diagnostics(got, name)
    assert status["scans scored"] == str(len(expected["novelty"]))
    if detector == "map-explore":
        # the scans it could not score are the ones novelty run left out: before /tf began and in its gap
        left_out = 160 - len(expected["novelty"])
        assert left_out > 3 and status["scans skipped: no pose at its time"] == str(left_out)
        check_the_cells(got[f"/{name}/novel_cells"], stamped, bag)
    else:
        assert len(expected["novelty"]) == 160 and not any(k.startswith("scans skipped") for k in status)
    assert status["scans dropped from a full queue"] == "0" and float(status["latency median (ms)"]) > 0


def check_the_cells(markers, stamped, bag):
    """Each scan's marker: the cells it hit above the threshold, as the map scored them before learning the scan."""
    scorer, _, _ = build({"detector": "map-explore"}, lambda name: "/" + name.lstrip("/"))
    scored = []
    for topic, msgtype, record, data in messages(bag):
        scored += scorer.take(topic, msgtype, data, record, record, cells=True)
    scored += scorer.tick(1e9, cells=True)
    # the first scan is scored by an empty map: no cells to show
    assert scored[0].cells is None and len(markers) == len(scored) - 1 == len(stamped) - 1
    for marker_array, one, published in zip(markers, scored[1:], stamped[1:]):
        (marker,) = marker_array.markers
        centres, novelty = one.cells
        novel = novelty > 0.5
        assert marker.header.frame_id == "odom" and marker.header.stamp == published.header.stamp
        assert marker.type == marker.CUBE_LIST and marker.scale.x == 0.2   # map-explore's cells
        assert [(p.x, p.y) for p in marker.points] == [tuple(c) for c in centres[novel].tolist()]
        np.testing.assert_array_equal([c.g for c in marker.colors], (1.0 - novelty[novel]).astype(np.float32))
    assert sum(len(m.markers[0].points) for m in markers) > 0


def test_a_node_started_again_with_its_saved_model_goes_on_where_it_stopped(master, tmp_path):
    times = np.round(1.0 + np.arange(0.0, 6.0, 0.1), 6)
    tf_times = np.round(0.9 + np.arange(0.0, 6.3, 0.02), 6)
    split = 4.0
    messages = drive(times, tf_times)
    whole = write_robot_bag(tmp_path / "whole.bag", "ros1", messages)
    scans = [m for m in messages if m[1] == "/scan"]
    others = [m for m in messages if m[1] != "/scan"]
    # the scans before the split, and /tf a little past it (the last scan's pose is interpolated)
    first = write_robot_bag(tmp_path / "first.bag", "ros1", [m for m in scans if m[0] < split] + [
        m for m in others if m[0] < split + 0.1])
    # the rest: the robot's own publishers latch its mounts again for the node started again; its /tf goes on
    second = write_robot_bag(tmp_path / "second.bag", "ros1", [m for m in scans if m[0] >= split] + [
        m for m in others if m[0] >= split - 0.1 or m[1] == "/tf_static"])
    expected = offline(whole, tmp_path, "map-explore")
    model = tmp_path / "model.npz"
    before, code, err = run_node(master, tmp_path, "novelty_before", [first], "_detector:=map-explore",
                                 f"_save:={model}")
    assert code == 0 and model.is_file() and "model saved to" in err, err
    n = len(before["/novelty_before/novelty_stamped"])
    after, code, err = run_node(master, tmp_path, "novelty_after", [second], f"_model:={model}",
                                f"_save:={model}")
    assert code == 0, err
    published = [m.vector.x for m in before["/novelty_before/novelty_stamped"] + after["/novelty_after/novelty_stamped"]]
    assert n == 30 and len(published) == len(expected["novelty"]) == 60
    np.testing.assert_array_equal(published, expected["novelty"])


def call(master, service, *args) -> str:
    return master.run(["rosservice", "call", service, *args]).stdout


def test_learning_frozen_and_resumed_the_model_saved_and_reset_by_services(master, tmp_path):
    times = np.round(1.0 + np.arange(0.0, 3.0, 0.1), 6)
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", drive(times, np.round(0.9 + np.arange(0.0, 3.3, 0.02), 6)))
    model = tmp_path / "model.npz"
    saved = {}

    def between(i):
        if i == 0:
            assert "success: True" in call(master, "/novelty_services/save")
            saved["learned"] = novelty.load(model)
            assert "success: True" in call(master, "/novelty_services/set_learning", "data: false")
        elif i == 2:
            assert "success: True" in call(master, "/novelty_services/save")
            saved["frozen"] = novelty.load(model)
            assert "success: True" in call(master, "/novelty_services/reset")
            assert "success: True" in call(master, "/novelty_services/set_learning", "data: true")

    got, code, err = run_node(master, tmp_path, "novelty_services", [bag] * 4, "_detector:=map-explore",
                              f"_save:={model}", between=between)
    assert code == 0, err
    runs = np.array([m.vector.x for m in got["/novelty_services/novelty_stamped"]]).reshape(4, 30)
    # frozen, the bag scores the same twice; reset, the fresh detector scores it as at first
    np.testing.assert_array_equal(runs[1], runs[2])
    np.testing.assert_array_equal(runs[3], runs[0])
    assert not np.array_equal(runs[0], runs[1])
    np.testing.assert_array_equal(saved["frozen"].synapse_.efficacy_, saved["learned"].synapse_.efficacy_)
    status = diagnostics(got, "novelty_services")
    assert status["time jumps back"] == "3" and status["scans scored"] == "120"


def test_faults_are_counted_said_once_and_survived(master, tmp_path):
    # NaN and -inf beams at 1.5 s, 90 beams (another geometry) at 2.0 s, no scans 3.0-5.0 s (a stop),
    # no /tf 5.5-7.5 s (a gap); played twice (time jumps back)
    def ranges(t, r):
        if abs(t - 1.5) < 1e-6:
            r = r.copy()
            r[::7], r[3::7] = np.nan, -np.inf
        return r

    times = np.round(1.0 + np.arange(0.0, 8.0, 0.1), 6)
    times = times[(times < 3.0) | (times >= 5.0)]
    tf_times = np.round(0.95 + np.arange(0.0, 8.3, 0.1), 6)   # half-way between the scans
    messages = [m for m in drive(times, tf_times[(tf_times < 5.5) | (tf_times > 7.5)], ranges=ranges)
                if abs(m[0] - 2.0) > 1e-6 or m[1] != "/scan"]
    messages += laser([2.0], beams=90, mount=(0.2, -0.1, 0.5), flipped=True)
    bag = write_robot_bag(tmp_path / "faults.bag", "ros1", messages)
    got, code, err = run_node(master, tmp_path, "novelty_faults", [bag, bag], "_detector:=map-explore",
                              "_stopped_after:=1.5")
    assert code == 0, err
    status = diagnostics(got, "novelty_faults")
    assert status["scans with beams without information (NaN)"] == "2"
    assert status["scans skipped: its beams cannot make the input"] == "2"   # 90 beams for 180 sectors
    # a scan waits for /tf to pass its time until a scan 1 s younger comes: those from 5.7 s (0.2 s after the
    # last transform, the tree's hold) to 6.4 s have no pose; from 6.5 s their poses are interpolated over the gap
    assert status["scans skipped: no pose at its time"] == str(2 * 8)
    assert status["time jumps back"] == "1" and int(status["scans stopped"]) >= 2
    assert status["scans scored"] == str(2 * (len(times) - 1 - 8))
    said = [line for line in err.splitlines() if "novelty:" in line]
    for words in ("without information (NaN)", "cannot be read and is left out", "Time jumped back",
                  "the scans stopped", "Scans resumed"):
        assert sum(words in line for line in said) >= 1, (words, said)
    # each kind of fault said once, however often it happened; a stop and its end each time
    assert sum("(NaN)" in line for line in said) == 1 and sum("cannot be read" in line for line in said) == 1


def test_the_master_going_away_and_coming_back(master, tmp_path):
    times = np.round(1.0 + np.arange(0.0, 2.0, 0.1), 6)
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", drive(times, np.round(0.9 + np.arange(0.0, 2.3, 0.02), 6)))
    node = master.node("_detector:=hsom", name="novelty_master")
    master.wait_for_node(node, "/novelty_master")
    master.core.stop()
    master.wait_until(lambda: not master.online(), 20, "the master to stop")
    time.sleep(2.5)
    master.core = master.spawn(["roscore", "-p", master.port], "roscore-again")
    master.wait_until(master.online, 30, "the master to answer again")
    master.run(["rosparam", "set", "/use_sim_time", "true"])
    master.wait_until(lambda: master.serves("/novelty_master/save"), 20, "the node to register again")
    recorder = master.record(tmp_path / "again.bag", "/novelty_master/novelty_stamped")
    master.play(bag, "--wait-for-subscribers")
    time.sleep(SETTLE)
    recorder.stop()
    assert node.stop() == 0
    assert len(recorded(tmp_path / "again.bag")["/novelty_master/novelty_stamped"]) == 20
    err = node.errors()
    assert "is away" in err and "registered again" in err and "internal error" not in err


@pytest.mark.parametrize("params, says", [
    (["_detector:=no-such-detector"], "no-such-detector"),
    (["_detector:=hsom", "_sectors:=0"], "The '~sectors' parameter of the novelty node must be an int in [1, inf). "
                                         "Got 0 instead."),
    (["_model:=/no/such/model.npz"], "~model: no such file: /no/such/model.npz"),
    ([], "Give the novelty node ~detector"),
])
def test_a_node_that_cannot_start_says_why_in_one_line(master, tmp_path, params, says):
    name = f"novelty_refused_{len(list(master.folder.glob('novelty_refused*.err')))}"   # its own parameters
    node = master.node(*params, name=name)
    assert node.wait(60) == 2
    err = node.err.read_text().strip().splitlines()
    assert len(err) == 1 and err[0].startswith("novelty node: error: ") and says in err[0], err


def test_a_model_file_that_does_not_load_is_refused_at_start(master, tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a model")
    node = master.node(f"_model:={bad}", name="novelty_bad_model")
    assert node.wait(60) == 2
    err = node.err.read_text().strip().splitlines()
    assert len(err) == 1 and "could not be loaded" in err[0], err


def test_without_a_master_the_node_says_so(tmp_path):
    lonely = Master(tmp_path)   # not started: nothing answers on its port
    node = lonely.node("_detector:=hsom")
    assert node.wait(60) == 2
    assert node.err.read_text().strip() == f"novelty node: error: no ROS master at {lonely.uri}: start roscore " \
                                           "(or set ROS_MASTER_URI)."


def test_rosnode_kill_saves_the_model(master, tmp_path):
    times = np.round(1.0 + np.arange(0.0, 1.0, 0.1), 6)
    bag = write_robot_bag(tmp_path / "robot.bag", "ros1", drive(times, np.round(0.9 + np.arange(0.0, 1.3, 0.02), 6)))
    model = tmp_path / "killed.npz"
    node = master.node("_detector:=hsom", f"_save:={model}", name="novelty_killed")
    master.wait_for_node(node, "/novelty_killed")
    master.play(bag, "--wait-for-subscribers")
    time.sleep(SETTLE)
    master.run(["rosnode", "kill", "/novelty_killed"])
    assert node.wait(30) == 0
    assert novelty.load(model).n_features_in_ == 16
    assert "model saved to" in node.errors()
