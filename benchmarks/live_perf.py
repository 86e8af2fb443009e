"""The live node's speed: a bag played into it at several rates, per detector; the rate it sustains and its latency.

Run, with ROS 1 installed and in a virtual environment made with ``--system-site-packages``
(docs/guide/live-robot.md)::

    python benchmarks/live_perf.py [--seconds 20] [--rates 1,5,10,max] [--core 0] [--out DIR]

The script writes its own ROS 1 bag (rosbags' writer, in a temporary
folder): a robot driving round a room for ``--seconds`` s with a 360-degree
laser of 360 beams at 40 Hz, ``odom -> base_link`` on ``/tf`` at 100 Hz and
the laser's mount on ``/tf_static``. For each detector (``hsom``,
``kmeans-stanley``, ``map-explore``) and rate, on a ``roscore`` of its own
(a free loopback port), it starts ``novelty node`` pinned to one core
(``taskset``), plays the bag with ``rosbag play --clock -r RATE`` (``max``:
``--immediate``, as fast as it goes) and reads the node's own account at
shutdown: the scan messages that arrived at it (``rosbag play``'s own
queue drops some when it publishes faster than its subscribers read), the
scans scored and those dropped from the node's queue (10 scans), and the
latency from a scan's arrival at the node (its subscription's callback) to
its novelty being published, median and 99th percentile (the scans of the
``points`` input wait for ``/tf`` to pass their time: up to one tf period,
10 ms, of it). The rate achieved is the scan messages' arrival rate at the
node; the rate sustained, the highest achieved with every scan arrived and
scored and none dropped.

The peers, measured in the same run: the same bag's messages fed to the
node's scorer in one process, without ROS (what each scan costs to read and
score, the same code), its time per scan (median and 99th percentile); and
``novelty run`` on the same bag (in this process, the median of
``--repeats`` runs' wall times, the first of which compiles the kernels),
in scans a second.

``--out`` (default ``benchmarks/results/live-perf``) receives ``runs.csv``
(one row a detector and rate), ``summary.md`` (the tables the guide shows)
and ``provenance.json``.

The targets: ``map-explore`` on a 360-beam laser at 40 Hz with no drops and
a 99th-percentile latency under 25 ms; the ring detectors at 200 Hz. Not a
unit test: the numbers depend on the machine and on what else it is doing.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import math
import os
import platform
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))   # this checkout's novelty, not an installed one

from novelty import __version__  # noqa: E402
from novelty.cli import main as cli_main  # noqa: E402
from novelty.io.ros.decoders import largest  # noqa: E402
from novelty.io.ros1.bag1 import Bag1  # noqa: E402
from novelty.rosnode.setup import build, warm_up  # noqa: E402

DETECTORS = ("hsom", "kmeans-stanley", "map-explore")
#: scans a second of the bag's laser, and its beams
RATE, BEAMS = 40.0, 360
#: the targets: (detector kind, input rate (Hz), 99th-percentile latency (ms) or None)
TARGETS = {"map-explore": (40.0, 25.0), "hsom": (200.0, None), "kmeans-stanley": (200.0, None)}
_SUMMARY = re.compile(r"(\d+) scan messages in ([\d.]+) s, (\d+) scans scored, (\d+) skipped, (\d+) dropped from a "
                      r"full queue(?:; latency median ([\d.]+) ms, 99th percentile ([\d.]+) ms)?")


# ------------------------------------------------------------------ the bag
def write_bag(path: Path, seconds: float) -> Path:
    """A robot circling a 6 x 8 m room, its laser at 40 Hz (see the module docstring)."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    angles = -math.pi + 2 * math.pi / BEAMS * np.arange(BEAMS)

    def pose(t):
        a = 2 * math.pi * t / 20.0
        return 1.0 + 2.0 * math.cos(a), 1.0 + 2.0 * math.sin(a), a + math.pi / 2

    def ranges(t):   # the distance to the walls x = -3, 5 and y = -2, 4 from the laser, 0.1 m ahead of the centre
        x, y, yaw = pose(t)
        x, y = x + 0.1 * math.cos(yaw), y + 0.1 * math.sin(yaw)
        c, s = np.cos(yaw + angles), np.sin(yaw + angles)
        with np.errstate(divide="ignore"):
            tx = np.where(c > 0, (5 - x) / c, np.where(c < 0, (-3 - x) / c, np.inf))
            ty = np.where(s > 0, (4 - y) / s, np.where(s < 0, (-2 - y) / s, np.inf))
        return np.minimum(tx, ty).astype(np.float32)

    def header(t, frame):
        return ts.types["std_msgs/msg/Header"](seq=0, stamp=ts.types["builtin_interfaces/msg/Time"](
            sec=int(t), nanosec=int(round((t % 1) * 1e9))), frame_id=frame)

    def transform(t, parent, child, xyz, yaw):
        tf = ts.types["geometry_msgs/msg/TransformStamped"]
        vector, quaternion = ts.types["geometry_msgs/msg/Vector3"], ts.types["geometry_msgs/msg/Quaternion"]
        return tf(header=header(t, parent), child_frame_id=child, transform=ts.types["geometry_msgs/msg/Transform"](
            translation=vector(x=xyz[0], y=xyz[1], z=xyz[2]),
            rotation=quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))))

    scan_type, tf_type = "sensor_msgs/msg/LaserScan", "tf2_msgs/msg/TFMessage"
    messages = []
    for t in np.round(1.0 + np.arange(0.0, seconds, 1 / RATE), 6):
        msg = ts.types[scan_type](header=header(t, "laser"), angle_min=-math.pi, angle_max=math.pi - 2 * math.pi / BEAMS,
                                  angle_increment=2 * math.pi / BEAMS, time_increment=0.0, scan_time=1 / RATE,
                                  range_min=0.05, range_max=30.0, ranges=ranges(t), intensities=np.zeros(0, np.float32))
        messages.append((t, "/scan", scan_type, ts.serialize_ros1(msg, scan_type)))
    for t in np.round(0.95 + np.arange(0.0, seconds + 0.2, 0.01), 6):
        x, y, yaw = pose(t)
        msg = ts.types[tf_type](transforms=[transform(t, "odom", "base_link", (x, y, 0.0), yaw)])
        messages.append((t, "/tf", tf_type, ts.serialize_ros1(msg, tf_type)))
    static = ts.types[tf_type](transforms=[transform(0.5, "base_link", "laser", (0.1, 0.0, 0.2), 0.0)])
    messages.append((0.5, "/tf_static", tf_type, ts.serialize_ros1(static, tf_type)))
    with Writer(path) as writer:
        connections = {}
        for t, topic, kind, data in sorted(messages, key=lambda m: m[0]):
            if topic not in connections:
                latched = {"latching": 1} if topic == "/tf_static" else {}
                connections[topic] = writer.add_connection(topic, kind, typestore=ts, **latched)
            writer.write(connections[topic], int(round(t * 1e9)), data)
    return path


# ------------------------------------------------------------------ the peer: the scorer without ROS
def in_process(bag: Path, detector: str) -> tuple[float, float, int]:
    """Median and 99th percentile (ms) of the time the scorer takes for a scan's message, and the scans scored."""
    scorer, settings, _ = build({"detector": detector, "fragments": 1}, lambda name: "/" + name)
    warm_up(scorer, settings)
    times, scored = [], 0
    with Bag1(bag) as reader:
        limits = {t: (largest(kind), None) for t, kind in reader.topics.items()}
        messages = [(c.topic, c.msgtype, stamp * 1e-9, bytes(data))
                    for c, stamp, _, data in reader.messages(list(reader.topics), limits)]
    spent = 0.0   # the time of the messages since the last scan scored: what scoring it took
    for topic, msgtype, stamp, data in messages:
        start = time.perf_counter()
        done = scorer.take(topic, msgtype, data, stamp, stamp)
        spent += time.perf_counter() - start
        if done:
            times += [spent / len(done)] * len(done)
            scored, spent = scored + len(done), 0.0
    p50, p99 = np.percentile(times, [50, 99]) * 1e3
    return float(p50), float(p99), scored


def offline(bag: Path, detector: str, repeats: int) -> tuple[float, int]:
    """``novelty run``'s scans a second on the bag (the median of ``repeats`` runs), and the scans it scored."""
    walls = []
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "rows.npz"
        for _ in range(repeats):
            start = time.perf_counter()
            with contextlib.redirect_stderr(io.StringIO()):
                if cli_main(["run", detector, "--data", str(bag), "--fragments", "1", "--out", str(out)]) != 0:
                    raise RuntimeError(f"novelty run {detector} failed")
            walls.append(time.perf_counter() - start)
        with np.load(out) as rows:
            scored = len(rows["novelty"])
    return scored / float(np.median(walls)), scored


# ------------------------------------------------------------------ the node on a master
class Session:
    """A roscore of its own on a free loopback port, and the processes started against it."""

    def __init__(self, folder: Path):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.folder = folder
        self.env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{self.port}/", "ROS_IP": "127.0.0.1",
                    "ROS_HOME": str(folder / "ros_home"), "ROS_LOG_DIR": str(folder / "ros_home" / "log")}
        self.core = self._start(["roscore", "-p", str(self.port)], "roscore")
        self._until(lambda: self._ok(["rosparam", "set", "/use_sim_time", "true"]), 30)

    def _start(self, args, name):
        out = open(self.folder / f"{name}.log", "w")
        return subprocess.Popen(args, env=self.env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)

    def _ok(self, args) -> bool:
        return subprocess.run(args, env=self.env, capture_output=True).returncode == 0

    @staticmethod
    def _until(condition, timeout):
        end = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > end:
                raise RuntimeError("timed out")
            time.sleep(0.2)

    def run(self, bag: Path, detector: str, rate: str, core: int | None) -> dict:
        name = f"novelty_{detector.replace('-', '_')}_{rate}"
        pin = ["taskset", "-c", str(core)] if core is not None else []
        node = self._start(pin + [sys.executable, "-m", "novelty.cli", "node", f"_detector:={detector}",
                                  "_fragments:=1", f"__name:={name}"], name)
        self._until(lambda: f"/{name}/save" in subprocess.run(["rosservice", "list"], env=self.env,
                                                               capture_output=True, text=True).stdout, 120)
        play = ["rosbag", "play", "--clock", "-q", "--wait-for-subscribers"]
        play += ["--immediate"] if rate == "max" else ["-r", rate]
        start = time.monotonic()
        subprocess.run(play + [str(bag)], env=self.env, capture_output=True, check=True)
        played = time.monotonic() - start
        time.sleep(2.0)
        os.killpg(node.pid, signal.SIGINT)
        node.wait(60)
        log = (self.folder / f"{name}.log").read_text()
        m = _SUMMARY.search(log)
        if m is None:
            raise RuntimeError(f"{name} said no summary:\n{log[-2000:]}")
        arrived, span = int(m[1]), float(m[2])
        scored, skipped, dropped = int(m[3]), int(m[4]), int(m[5])
        return {"arrived": arrived, "scored": scored, "skipped": skipped, "dropped": dropped, "played_s": played,
                "achieved_hz": (arrived - 1) / span if span > 0 else math.nan,
                "latency_median_ms": float(m[6]), "latency_p99_ms": float(m[7])}

    def close(self):
        os.killpg(self.core.pid, signal.SIGINT)
        try:
            self.core.wait(20)
        except subprocess.TimeoutExpired:
            os.killpg(self.core.pid, signal.SIGKILL)


def sustained(rows: list[dict]) -> float:
    """The highest rate achieved with no scan dropped (0 where every rate dropped some)."""
    return max((r["achieved_hz"] for r in rows if r["dropped"] == 0 and r["scored"] == r["arrived"] == r["scans"]),
               default=0.0)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="the bag's length (s; default 20)")
    parser.add_argument("--rates", default="1,5,10,20,max", help="play rates (default 1,5,10,20,max)")
    parser.add_argument("--detectors", default=",".join(DETECTORS))
    parser.add_argument("--repeats", type=int, default=3, help="novelty run's runs a detector (default 3)")
    parser.add_argument("--core", type=int, default=0, help="the core the node is pinned to (default 0; -1: none)")
    parser.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "live-perf"))
    args = parser.parse_args(argv)
    if shutil.which("roscore") is None:
        print("live_perf.py needs ROS 1 (docs/guide/live-robot.md).", file=sys.stderr)
        return 2
    core = None if args.core < 0 else args.core
    folder = Path(tempfile.mkdtemp(prefix="live-perf-"))
    rows = []
    try:
        bag = write_bag(folder / "robot.bag", args.seconds)
        scans = int(round(args.seconds * RATE))
        session = Session(folder)
        try:
            for detector in args.detectors.split(","):
                p50, p99, scored = in_process(bag, detector)
                rows.append({"detector": detector, "rate": "in-process", "scans": scans, "arrived": scans,
                             "scored": scored,
                             "skipped": 0, "dropped": 0, "played_s": math.nan, "achieved_hz": math.nan,
                             "latency_median_ms": p50, "latency_p99_ms": p99})
                print(f"{detector:16s} in process: {p50:.2f} / {p99:.2f} ms a scan", flush=True)
                rate, scored = offline(bag, detector, args.repeats)
                rows.append({"detector": detector, "rate": "novelty run", "scans": scans, "arrived": scans,
                             "scored": scored, "skipped": 0, "dropped": 0, "played_s": math.nan,
                             "achieved_hz": rate, "latency_median_ms": math.nan, "latency_p99_ms": math.nan})
                print(f"{detector:16s} novelty run: {rate:.0f} scans/s", flush=True)
                for rate in args.rates.split(","):
                    row = {"detector": detector, "rate": rate, "scans": scans, **session.run(bag, detector, rate, core)}
                    rows.append(row)
                    print(f"{detector:16s} {rate:>4s}: {row['scored']}/{scans} scored, {row['dropped']} dropped, "
                          f"{row['achieved_hz']:.0f} Hz, latency {row['latency_median_ms']:.2f} / "
                          f"{row['latency_p99_ms']:.2f} ms", flush=True)
        finally:
            session.close()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    write(Path(args.out), rows, args)
    return 0


def write(out: Path, rows: list[dict], args) -> None:
    out.mkdir(parents=True, exist_ok=True)
    # runs.csv, not results.csv: benchmarks/results/*/results.csv are the suites' rows (benchmarks/tables.py)
    with open(out / "runs.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.3f}" if isinstance(v, float) else v) for k, v in row.items()})
    revision = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True).stdout.strip()
    load = os.getloadavg()
    provenance = {"command": "python benchmarks/live_perf.py " + " ".join(sys.argv[1:]), "revision": revision,
                  "date": time.strftime("%Y-%m-%d"), "novelty": __version__, "python": platform.python_version(),
                  "cpus": os.cpu_count(), "load_average_at_end": [round(v, 2) for v in load],
                  "node_pinned_to_core": args.core}
    (out / "provenance.json").write_text(json.dumps(provenance, indent=2) + "\n")
    def shown(value, form):
        return "" if math.isnan(value) else format(value, form)

    lines = ["| detector | rate | arrived | scored | dropped | achieved (Hz) | latency median (ms) | latency p99 (ms) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| `{r['detector']}` | {r['rate']} | {r['arrived']}/{r['scans']} | {r['scored']} | {r['dropped']} | "
                     f"{shown(r['achieved_hz'], '.0f')} | {shown(r['latency_median_ms'], '.2f')} | "
                     f"{shown(r['latency_p99_ms'], '.2f')} |")
    lines += ["", "| detector | sustained without drops (Hz) | target | met |", "| --- | --- | --- | --- |"]
    for detector in dict.fromkeys(r["detector"] for r in rows):
        mine = [r for r in rows if r["detector"] == detector and r["rate"] not in ("in-process", "novelty run")]
        rate, p99 = TARGETS.get(detector, (math.nan, None))
        at = [r for r in mine if r["achieved_hz"] >= rate * 0.95 and r["dropped"] == 0 and r["scored"] == r["scans"]]
        met = bool(at) and (p99 is None or min(r["latency_p99_ms"] for r in at) < p99)
        target = f"{rate:.0f} Hz" + ("" if p99 is None else f", p99 < {p99:.0f} ms")
        lines.append(f"| `{detector}` | {sustained(mine):.0f} | {target} | {'yes' if met else 'no'} |")
    (out / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
