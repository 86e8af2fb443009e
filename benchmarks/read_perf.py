"""Reading rings from bags against rosbags' own deserialization of the same messages, measured in one run.

Run::

    pip install ".[ros]"
    python benchmarks/read_perf.py [--quick] [--repeats N] [--out DIR]

The script writes its own bags (with rosbags' writers, into a temporary
folder), in the shapes real robots record:

- ``fixed``: one 270-degree laser of 1,081 beams sending whole scans (ROS 1);
- ``fragments``: a scanner that sends each 270-degree revolution as 6
  messages of 180 beams (ROS 1), assembled into one scan a revolution;
- ``tf tree``: a 360-degree lidar of 720 beams at 10 Hz in ``base_scan``
  with ``odom -> base_footprint`` on ``/tf`` at 50 Hz and the static
  ``base_footprint -> base_link -> base_scan`` (ROS 1): mounts and poses
  looked up at each scan's time;
- ``two lasers``: front and rear lasers of 541 beams, their mounts on
  ``/tf_static``, merged into one ring (ROS 1);
- ``fixed (bz2)``: the ``fixed`` bag with bz2 chunks;
- ``fixed (ROS 2)``: the ``fixed`` scans in a ROS 2 SQLite bag;
- ``fixed (MCAP, zstd chunks)`` and ``fixed (ROS 2, zstd messages)``: the
  same stored compressed, every compressed part checked before rosbags
  inflates it (:mod:`novelty.io.ros2.inflation`), a second inflation.

For each, the time of :func:`novelty.io.read_rings` (opening the
bag, decoding, assembling, placing, posing, merging, reducing each sweep to
16 sectors) is set against rosbags' ``AnyReader`` opening the same bag and
deserializing every message the reader reads (the scans, and ``/tf`` where
it is read), as a user of rosbags would. Times are CPU seconds
(``time.process_time``) of one process, the two readers interleaved within
each repetition, in alternating order; the table gives the medians and
their ratio (the target: at most 1.5). Not a unit test: the numbers depend on the machine and on what
else it is doing.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # this checkout's novelty, not an installed one

from novelty.io import Reading, read_rings  # noqa: E402

TARGET = 1.5


def _typestore(ros1: bool):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    if not ros1:
        return get_typestore(Stores.ROS2_HUMBLE)
    ts = get_typestore(Stores.ROS1_NOETIC)
    ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    return ts


def _make(ts, msgtype, **values):
    import dataclasses

    cls = ts.types[msgtype]
    for field in dataclasses.fields(cls):
        if field.name not in values:
            values[field.name] = 0 if field.name == "seq" else 0.0
    return cls(**values)


def _header(ts, t, frame):
    stamp = ts.types["builtin_interfaces/msg/Time"](sec=int(t), nanosec=int(round((t % 1) * 1e9)))
    return _make(ts, "std_msgs/msg/Header", stamp=stamp, frame_id=frame)


def _scan(ts, t, frame, angle_min, increment, ranges):
    return _make(ts, "sensor_msgs/msg/LaserScan", header=_header(ts, t, frame), angle_min=angle_min,
                 angle_max=angle_min + increment * (len(ranges) - 1), angle_increment=increment, range_min=0.05,
                 range_max=30.0, ranges=np.asarray(ranges, np.float32), intensities=np.zeros(0, np.float32))


def _transform(ts, t, parent, child, xyz=(0.0, 0.0, 0.0), yaw=0.0):
    q = _make(ts, "geometry_msgs/msg/Quaternion", z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    v = _make(ts, "geometry_msgs/msg/Vector3", x=xyz[0], y=xyz[1], z=xyz[2])
    return _make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, t, parent), child_frame_id=child,
                 transform=_make(ts, "geometry_msgs/msg/Transform", translation=v, rotation=q))


def _tf(ts, transforms):
    return _make(ts, "tf2_msgs/msg/TFMessage", transforms=transforms)


def _ranges(rng, n):
    """A room's walls at 1-8 m with some beams without an echo."""
    r = 1.0 + 7.0 * np.abs(np.sin(np.linspace(0, 3, n) + rng.uniform(0, 0.1)))
    r[rng.random(n) < 0.02] = np.inf
    return r


def write_bags(folder: Path, scans: int) -> dict:
    """The benchmark's bags: name -> (path, topics rosbags deserializes, options of read_rings)."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    rng = np.random.default_rng(0)

    def write(name, messages, ros1=True, compression=None, storage="sqlite3"):
        ts = _typestore(ros1)
        if ros1:
            path = folder / f"{name}.bag"
            writer, serialize = Writer1(path), ts.serialize_ros1
            if compression:
                writer.set_compression(Writer1.CompressionFormat.BZ2)
        else:
            root = folder / name
            plugin = StoragePlugin.SQLITE3 if storage == "sqlite3" else StoragePlugin.MCAP
            writer, serialize = Writer2(root, version=9, storage_plugin=plugin), ts.serialize_cdr
            path = root / f"{name}.{'db3' if storage == 'sqlite3' else 'mcap'}"
            if compression:   # a ROS 2 bag stored compressed is read from its folder (metadata.yaml says how)
                writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
                path = root
        with writer:
            connections = {}
            for t, topic, msgtype, build in sorted(messages, key=lambda m: m[0]):
                if topic not in connections:
                    connections[topic] = writer.add_connection(topic, msgtype, typestore=ts)
                writer.write(connections[topic], int(round(t * 1e9)), serialize(build(ts), msgtype))
        return path

    scan_type, tf_type = "sensor_msgs/msg/LaserScan", "tf2_msgs/msg/TFMessage"
    span, n = math.radians(270), 1081
    walls = {size: [_ranges(rng, size) for _ in range(scans)] for size in (1081, 180, 720, 541)}
    fixed = [(0.1 * k, "/scan", scan_type, lambda ts, k=k: _scan(
        ts, 0.1 * k, "laser", -span / 2, span / (n - 1), walls[n][k])) for k in range(scans)]
    per, beams = 6, 180
    fragments = [(0.1 * k + 0.01 * f, "/scan", scan_type, lambda ts, k=k, f=f: _scan(
        ts, 0.1 * k + 0.01 * f, "laser", -span / 2 + f * span / per, span / (per * beams), walls[beams][k]))
        for k in range(scans // per) for f in range(per)]
    lidar = [(0.1 * k, "/scan", scan_type, lambda ts, k=k: _scan(
        ts, 0.1 * k, "base_scan", 0.0, 2 * math.pi / 720, walls[720][k])) for k in range(scans)]
    lidar += [(0.02 * k, "/tf", tf_type, lambda ts, k=k: _tf(ts, [_transform(
        ts, 0.02 * k, "odom", "base_footprint", (0.01 * k, 0.0, 0.0), 0.001 * k)])) for k in range(5 * scans + 10)]
    lidar.append((0.0, "/tf_static", tf_type, lambda ts: _tf(ts, [
        _transform(ts, 0.0, "base_footprint", "base_link", (0.0, 0.0, 0.01)),
        _transform(ts, 0.0, "base_link", "base_scan", (-0.032, 0.0, 0.172))])))
    two = [(0.1 * k + 0.02 * j, topic, scan_type, lambda ts, k=k, j=j, frame=frame: _scan(
        ts, 0.1 * k + 0.02 * j, frame, -span / 2, span / 540, walls[541][2 * k + j]))
        for k in range(scans // 2) for j, (topic, frame) in enumerate((("/front", "front"), ("/rear", "rear")))]
    two.append((0.0, "/tf_static", tf_type, lambda ts: _tf(ts, [
        _transform(ts, 0.0, "base_link", "front", (0.3, 0.0, 0.2)),
        _transform(ts, 0.0, "base_link", "rear", (-0.3, 0.0, 0.2), math.pi)])))
    return {
        "fixed": (write("fixed", fixed), ["/scan"], {}),
        "fragments": (write("fragments", fragments), ["/scan"], {}),
        "tf tree": (write("tf-tree", lidar), ["/scan", "/tf", "/tf_static"], {}),
        "two lasers": (write("two", two), ["/front", "/rear", "/tf_static"], {"topic": ["/front", "/rear"]}),
        "fixed (bz2)": (write("fixed-bz2", fixed, compression="bz2"), ["/scan"], {}),
        "fixed (ROS 2)": (write("fixed-ros2", fixed, ros1=False), ["/scan"], {}),
        "fixed (MCAP, zstd chunks)": (write("fixed-mcap-zstd", fixed, ros1=False, compression="storage",
                                            storage="mcap"), ["/scan"], {}),
        "fixed (ROS 2, zstd messages)": (write("fixed-ros2-zstd", fixed, ros1=False, compression="message"),
                                         ["/scan"], {}),
    }


def rosbags_deserializes(path: Path, topics) -> int:
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    with AnyReader([path], default_typestore=get_typestore(Stores.LATEST)) as reader:
        connections = [c for c in reader.connections if c.topic in topics]
        return sum(1 for c, _, raw in reader.messages(connections=connections) if reader.deserialize(raw, c.msgtype))


def ours_reads(path: Path, options) -> int:
    return sum(1 for _ in read_rings(path, Reading(topic=options.get("topic"), sectors=16)))


def _cpu(fn, *args) -> tuple[float, int]:
    start = time.process_time()
    n = fn(*args)
    return time.process_time() - start, n


def measure(bags: dict, repeats: int) -> dict:
    times = {name: {"rosbags": [], "ours": []} for name in bags}
    counts = {}
    for path, topics, options in bags.values():   # a first pass each, untimed: rosbags' generated code
        rosbags_deserializes(path, topics)
        ours_reads(path, options)
    for k in range(repeats):
        for name, (path, topics, options) in bags.items():
            # the two in alternating order (ABBA), so that a drift of the machine's load touches both alike
            for who in (("rosbags", "ours") if k % 2 == 0 else ("ours", "rosbags")):
                if who == "rosbags":
                    t, messages = _cpu(rosbags_deserializes, path, topics)
                else:
                    t, rings = _cpu(ours_reads, path, options)
                times[name][who].append(t)
            counts[name] = (messages, rings)
    return {name: dict(rosbags=statistics.median(v["rosbags"]), ours=statistics.median(v["ours"]),
                       messages=counts[name][0], rings=counts[name][1], raw=v) for name, v in times.items()}


def table(results: dict) -> str:
    lines = ["| shape | messages deserialized | rings | rosbags (s) | read_rings (s) | ratio | target |",
             "| --- | ---: | ---: | ---: | ---: | ---: | --- |"]
    for name, r in results.items():
        ratio = r["ours"] / r["rosbags"]
        lines.append(f"| {name} | {r['messages']:,} | {r['rings']:,} | {r['rosbags']:.3f} | {r['ours']:.3f} | "
                     f"{ratio:.2f} | {'PASS' if ratio <= TARGET else 'FAIL'} (<= {TARGET}) |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="600 scans a bag instead of 2,000")
    parser.add_argument("--repeats", type=int, default=9, help="repetitions (medians reported; default 9)")
    parser.add_argument("--out", help="a folder to write read_perf.json and read_perf.md to")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        bags = write_bags(Path(folder), 600 if args.quick else 2000)
        results = measure(bags, args.repeats)
    text = table(results)
    print(text)
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "read_perf.json").write_text(json.dumps(results, indent=1))
        (out / "read_perf.md").write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
