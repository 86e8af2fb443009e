"""``novelty run`` on robot recordings: CARMEN logs and ROS bags streamed ring by ring; ``novelty plot`` of the path."""

import argparse
import csv
import io
import math

import numpy as np
import pytest

from novelty.cli import main
from novelty.cli.recording import recording_rings
from novelty.io import Reading

from ..io.carmen.test_log import LOG


def table(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


def test_a_carmen_log_streams_with_its_poses(tmp_path, capsys):
    path = tmp_path / "run.log"
    path.write_text(LOG)
    assert main(["run", "hsom", "--data", str(path), "--sectors", "2", "--param", "n_rows=2",
                 "--param", "n_columns=2"]) == 0
    (row,) = table(capsys.readouterr().out)
    assert list(row) == ["scan", "novelty", "alarm", "time", "x", "y", "theta"]
    assert (row["novelty"], row["time"], row["x"], row["theta"]) == ("1", "10.5", "0.5", "0.125")


def test_wrong_options_for_a_recording(tmp_path, capsys):
    path = tmp_path / "run.log"
    path.write_text(LOG)
    for extra, message in [(["--topic", "ODOM"], "one of FLASER, RLASER, ROBOTLASER1"),
                           (["--reduce", "most"], "--reduce must be min, mean, median or a percentile"),
                           (["--limits", "90"], "--limits must be LOW,HIGH in degrees"),
                           (["--passes", "2"], "no --passes")]:
        assert main(["run", "hsom", "--data", str(path), *extra]) == 2
        assert message in capsys.readouterr().err


@pytest.fixture(scope="module", params=("ros1", "sqlite3", "mcap"))
def bag(request, tmp_path_factory):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                        "'novelty-habituation[ros]'")
    from ..io.bag_files import write_bag

    return write_bag(tmp_path_factory.mktemp(request.param), request.param)


def test_a_bag_streams_its_laser_with_odometry(bag, tmp_path, capsys):
    out = tmp_path / "novelty.csv"
    assert main(["run", "hsom", "--data", str(bag), "--topic", "/scan", "--sectors", "2", "--pose-topic",
                 "/odom", "--out", str(out), "--param", "n_rows=2", "--param", "n_columns=2"]) == 0
    rows = table(out.read_text())
    assert [r["x"] for r in rows] == ["1", "1.1", "1.2", "5.95", "5.95"]   # interpolated at each scan's time
    assert rows[0]["novelty"] == "1" and float(rows[2]["novelty"]) < 1
    npz = tmp_path / "novelty.npz"
    assert main(["run", "hsom", "--data", str(bag), "--topic", "/sonar", "--out", str(npz)]) == 0
    with np.load(npz) as saved:
        assert saved["novelty"].shape == (3,) and saved["time"][0] == pytest.approx(1.02)


def test_a_map_reads_the_points_input_of_a_bag_with_its_poses(bag, tmp_path, capsys):
    # map-explore reads the robot's pose with each scan: novelty run gives it the points input, here one
    # sector a beam (the bag's laser has four), each row scored then learned as a script would
    import novelty
    from novelty.io.scans.points import sweep_points
    from novelty.io.recording.readers import read_sweeps

    out = tmp_path / "map.csv"
    assert main(["run", "map-explore", "--data", str(bag), "--topic", "/scan", "--pose-topic", "/odom",
                 "--out", str(out)]) == 0
    rows = table(out.read_text())
    sweeps = list(read_sweeps(bag, Reading(topic="/scan", pose_topic="/odom")))
    det = novelty.make("map-explore")
    expected = [det.score_learn_one(r) for r in sweep_points(sweeps, sectors=4)]
    assert [float(r["novelty"]) for r in rows] == pytest.approx(expected, abs=1e-9)
    assert [r["x"] for r in rows] == ["1", "1.1", "1.2", "5.95", "5.95"]
    capsys.readouterr()
    assert main(["run", "map-explore", "--data", str(bag), "--topic", "/scan", "--pose-topic", "/odom",
                 "--sectors", "5"]) == 2
    assert "sectors hold no beam" in capsys.readouterr().err
    assert main(["run", "map-explore", "--data", str(bag), "--topic", "/scan", "--pose-topic", "/odom",
                 "--reduce", "mean"]) == 2
    assert "no --reduce, --limits or --front" in capsys.readouterr().err


def test_a_map_on_a_recording_without_poses_says_where_poses_come_from(tmp_path, capsys):
    pytest.importorskip("rosbags", reason="the bag is written with rosbags' writers (the ros extra)")
    from ..tasks.objects.test_bags import robot_bag

    bag = robot_bag(tmp_path / "no-poses", False)   # no /tf: its poses are on /odom, read only when named
    assert main(["run", "map-explore", "--data", str(bag)]) == 2
    err = capsys.readouterr().err
    assert "map-explore reads the robot's pose with each scan; none of the 40 scans" in err
    assert "give --pose-topic" in err


def test_a_bag_refuses_a_wrong_topic_naming_what_exists(bag, capsys):
    assert main(["run", "hsom", "--data", str(bag), "--topic", "/laser"]) == 2
    err = capsys.readouterr().err
    assert "no topic '/laser'; its topics: /cloud (sensor_msgs/msg/PointCloud2), /odom (nav_msgs" in err
    assert main(["run", "hsom", "--data", str(bag), "--topic", "/odom"]) == 2
    assert ("must be LaserScan, MultiEchoLaserScan, PointCloud2 or Range topics, lasers or sonars; /odom holds "
            "nav_msgs/msg/Odometry") in capsys.readouterr().err


def test_a_file_that_is_not_a_bag(tmp_path, capsys):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra")
    path = tmp_path / "run.mcap"
    path.write_bytes(b"\x00" * 64)
    assert main(["run", "hsom", "--data", str(path), "--topic", "/scan"]) == 2
    assert "is not a readable bag" in capsys.readouterr().err


def test_without_rosbags_the_message_names_the_extra(tmp_path, capsys, monkeypatch):
    from novelty.io.bags import rosbag

    def missing():
        raise ImportError("Reading ROS bags needs the optional package rosbags: pip install "
                          "'novelty-habituation[ros]' (or pip install rosbags).")

    monkeypatch.setattr(rosbag, "_rosbags", missing)
    (tmp_path / "run.bag").write_bytes(b"#ROSBAG V2.0\n")
    assert main(["run", "hsom", "--data", str(tmp_path / "run.bag"), "--topic", "/scan"]) == 2
    assert "novelty-habituation[ros]" in capsys.readouterr().err


def test_plot_draws_the_path_coloured_by_novelty(tmp_path, monkeypatch):
    figure = pytest.importorskip("matplotlib.figure", reason="plots need matplotlib (novelty-habituation[plot])")
    out = tmp_path / "run.csv"
    out.write_text("scan,novelty,alarm,time,x,y,theta\n0,1,1,0.0,0.0,0.0,0\n1,0.5,1,1.0,1.0,2.0,0\n")
    drawn = []
    monkeypatch.setattr(figure.Figure, "savefig", lambda fig, *a, **k: drawn.append(fig))
    assert main(["plot", str(out), "--out", str(tmp_path / "path.png")]) == 0
    path_axes = drawn[0].axes[0]
    dots = path_axes.collections[0]
    assert dots.get_offsets().tolist() == [[0.0, 0.0], [1.0, 2.0]]
    assert dots.get_array().tolist() == [1.0, 0.5]
    assert path_axes.get_xlabel() == "x (m)"


def test_the_rings_are_the_papers_inputs(tmp_path):
    # one FLASER of five beams at -90..90 degrees, 1..5 m; two sectors: min 1 m and 3 m -> 1 - r / 2 with T = 2
    path = tmp_path / "run.log"
    path.write_text(LOG)
    args = argparse.Namespace(data=str(path), topic=None, pose_topic=None, base_frame="base_link", sectors=2,
                              reduce="min", front=0.0, limits=None, range_threshold=2.0)
    ((time, x, pose),) = list(recording_rings(args))
    assert x.tolist() == [0.5, 0.0] and time == 10.5 and pose.tolist() == [0.5, 0.25, 0.125]
    # the front turned to the laser's left (+90 degrees): the beams at -180, -135, -90, -45, 0 degrees from
    # it; the front half (-90..90) in two sectors holds 3 m and 4 m (right), 5 m (left); means with T = 10
    args.front, args.limits, args.reduce, args.range_threshold = 90.0, "-90,90", "mean", 10.0
    ((_, x, _),) = list(recording_rings(args))
    assert x.tolist() == pytest.approx([1 - 3.5 / 10, 1 - 5 / 10])


def test_bench_runs_an_exploration_task_from_recordings(tmp_path, monkeypatch):
    # three drives a day apart along a corridor; a box 1 m ahead 10-14 s into the second and third
    monkeypatch.chdir(tmp_path)
    for k in range(3):
        with open(f"drive{k}.log", "w") as fh:
            for t in 86400.0 * k + np.arange(0.0, 30.0, 0.5):
                near = k >= 1 and 86400 * k + 10 <= t <= 86400 * k + 14
                r = " ".join(["1.0" if near else "3.0"] * 4)
                fh.write(f"FLASER 4 {r} {t % 86400} 0 0 {t % 86400} 0 0 {t} robot {t}\n")
    (tmp_path / "marks.csv").write_text("feature,start,end\nbox,86410,86414\nbox,172810,172814\n")
    assert main(["bench", "--protocol", "exploration", "--detector", "hsom", "--task",
                 "recording paths=drive0.log,drive1.log,drive2.log marks=marks.csv sectors=4",
                 "--out", "out"]) == 0
    (row,) = table((tmp_path / "out" / "results.csv").read_text())
    # the box's 9 scans of the second drive are its first encounter (the first drive is the warm-up)
    assert (row["status"], row["n_runs"], row["warmup_runs"], row["n_first"]) == ("ok", "3", "1", "9")
    # the box's scans are the only novel ones to a map that learned the empty corridor
    assert float(row["first_encounter_auc"]) == 1.0


def _empty_topic_bag(path):
    """A ROS 1 bag whose /scan holds no message (its odometry does)."""
    from rosbags.rosbag1 import Writer

    from ..io.bag_files import _messages, store

    ts = store("ros1")
    with Writer(path) as writer:
        writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=ts)
        odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=ts)
        for t, topic, msgtype, msg in _messages(ts):
            if topic == "/odom":
                writer.write(odom, int(t * 1e9), ts.serialize_ros1(msg, msgtype))
    return path


def test_a_failed_run_leaves_an_existing_out_byte_identical(bag, tmp_path, capsys):
    from ..io.craft import Zeros, laser_prefix, ros1_bag

    out = tmp_path / "good.csv"
    out.write_bytes(b"scan,novelty\n0,0.5\n")
    (tmp_path / "notes.log").write_text("x,y\n1,2\n")
    hostile = ros1_bag(tmp_path / "hostile.bag", [(10**9, [laser_prefix(50_000_000), Zeros(200_000_004)])],
                       compression="bz2")
    for argv, says in [
        (["--data", str(bag), "--topic", "/sacn"], "no topic '/sacn'"),
        (["--data", str(bag), "--topic", "/scan", "--pose-topic", "/sonar"],
         "pose_topic /sonar must hold poses (one of nav_msgs/msg/Odometry"),
        (["--data", str(tmp_path / "notes.log")], "line 1: not a CARMEN log"),
        (["--data", str(_empty_topic_bag(tmp_path / "empty.bag")), "--topic", "/scan"], "topic /scan holds no messages"),
        (["--data", str(hostile)], "topic /scan, message 1 (ranges): states 50,000,000 beams"),
    ]:
        for target in (out, out.with_suffix(".npz")):
            if target.suffix == ".npz":
                target.write_bytes(b"PK an earlier result")
            before = target.read_bytes()
            assert main(["run", "hsom", *argv, "--out", str(target)]) == 2
            assert says in capsys.readouterr().err
            assert target.read_bytes() == before


def test_a_run_failing_midway_keeps_its_rows_and_says_how_many(tmp_path, capsys):
    path = tmp_path / "run.log"
    scan = "FLASER 4 1.0 2.0 3.0 4.0 0.5 0.25 0.125 0.5 0.25 0.1 {t} host {t}\n"
    path.write_text(scan.format(t=1.0) + scan.format(t=2.0) + "FLASER 4 1.0 oops 3.0 4.0 0 0 0 0 0 0 3.0 h 3.0\n")
    for out in (tmp_path / "novelty.csv", tmp_path / "novelty.npz"):
        assert main(["run", "hsom", "--data", str(path), "--sectors", "2", "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "line 3 (FLASER): the ranges: 'oops' is not a number" in err
        assert f"(the first 2 scans' rows were written to {out} before it)" in err
        if out.suffix == ".csv":
            assert [r["time"] for r in table(out.read_text())] == ["1.0", "2.0"]
        else:
            with np.load(out) as saved:
                assert saved["time"].tolist() == [1.0, 2.0]


def test_a_scanner_that_splits_revolutions_reads_as_one_ring_a_revolution(tmp_path, capsys):
    # a safety laser: each 275-degree revolution as 6 messages, 87 revolutions
    from ..io.scenes import laser_ranges, scan_message, write_robot_bag

    n, per = 1100, 6
    inc = math.radians(275) / n
    start = -math.radians(137.5)
    messages = []
    for k in range(87):
        t = 1.0 + 0.04 * k
        ranges = laser_ranges((0.5 * math.cos(0.1 * k), 0.0, 0.05 * k), (0, 0, 0), start + inc * np.arange(n))
        for f in range(per):
            piece = slice(f * n // per, (f + 1) * n // per)
            messages.append((t + 0.005 * f, "/scan", "sensor_msgs/msg/LaserScan",
                             lambda ts, t=t, f=f, piece=piece, ranges=ranges: scan_message(
                                 ts, t + 0.005 * f, "laser", start + inc * piece.start, inc, ranges[piece])))
    bag = write_robot_bag(tmp_path / "safety.bag", "ros1", messages)
    out = tmp_path / "novelty.csv"
    assert main(["run", "hsom", "--data", str(bag), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "novelty run: /scan: 87 scans assembled from 522 messages (6 a revolution)" in err
    assert len(table(out.read_text())) == 87
    assert main(["run", "hsom", "--data", str(bag), "--out", str(out), "--fragments", "1"]) == 0
    assert len(table(out.read_text())) == 522 and "assembled" not in capsys.readouterr().err
    assert main(["run", "hsom", "--data", str(bag), "--fragments", "none"]) == 2
    assert "--fragments must be auto or a count >= 1; got 'none'" in capsys.readouterr().err


def test_the_console_says_which_frame_mount_and_poses_were_used(tmp_path, capsys):
    from ..io.scenes import laser_ranges, quaternion, scan_message, tf_message, transform, write_robot_bag

    angles = -1.5 + 0.01 * np.arange(300)
    messages = [(0.5 + 0.1 * k, "/scan", "sensor_msgs/msg/LaserScan", lambda ts, k=k: scan_message(
        ts, 0.5 + 0.1 * k, "base_scan", -1.5, 0.01, laser_ranges((0.1 * k, 0.0, 0.0), (0, 0, 0), angles)))
        for k in range(5)]
    messages += [(0.05 * k, "/tf", "tf2_msgs/msg/TFMessage", lambda ts, k=k: tf_message(ts, [transform(
        ts, 0.05 * k, "odom", "base_footprint", (0.005 * k, 0.0, 0.0))])) for k in range(30)]
    messages.append((0.0, "/tf_static", "tf2_msgs/msg/TFMessage", lambda ts: tf_message(ts, [transform(
        ts, 0.0, "base_footprint", "base_scan", (-0.03, 0.0, 0.17), quaternion())])))
    bag = write_robot_bag(tmp_path / "tb3.bag", "ros1", messages)
    out = tmp_path / "novelty.csv"
    assert main(["run", "hsom", "--data", str(bag), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "novelty run: base frame base_footprint (REP 105's fallback: the tf tree has no base_link)" in err
    assert "novelty run: /scan: x=-0.03 m, y=0 m, yaw=0 deg, from tf (base_footprint -> base_scan)" in err
    assert "novelty run: poses from /tf: odom -> base_footprint, interpolated at each scan's time" in err
    assert [r["x"] for r in table(out.read_text())] == ["0.05", "0.06", "0.07", "0.08", "0.09"]
    assert main(["run", "hsom", "--data", str(bag), "--out", str(out), "--mount", "0.2,0,180,flipped"]) == 0
    assert ("/scan: x=0.2 m, y=0 m, yaw=180 deg, upside down, from option (the bag's own transform "
            "base_footprint -> base_scan is not used)") in capsys.readouterr().err
