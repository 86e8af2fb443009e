"""Crafted recordings and tables that once cost gigabytes or minutes, read under limits: time and peak memory.

Run::

    pip install ".[ros]"
    python benchmarks/hostile_inputs.py [--cases NAME,NAME] [--library DIR] [--limit-gb 4] [--timeout 300]

Each case writes a small crafted file (with the tests' writers: ``tests/io/craft.py``,
``tests/io/bag_files.py``, ``tests/io/tables/craft.py``) and reads it through the public API in a
child process limited to ``--limit-gb`` of address space and ``--timeout`` seconds; the table gives
each case's file size, what the reading said, its wall time and its peak resident memory (the
child's ``VmHWM``; of a child stopped at the time limit, its peak so far). ``--library DIR`` reads with
the ``novelty`` of another checkout (``git archive <commit> novelty | tar -x -C /tmp/before``), to set a
revision's figures beside this one's. Not a unit test: the
tests hold each case to its bound (a few seconds, 200 MB); here are the figures.

The cases:

- ``mcap-footer``: a footer opcode after an MCAP's header, then a chunk of 1 GiB of zeros;
- ``mcap-long-record``: a record stating 2^40 bytes covers such a chunk, which the summary indexes;
  ``mcap-huge-record`` the same with 2^62 bytes;
- ``mcap-hidden-summary``: the footer points at a summary hidden in an attachment, indexing a chunk
  hidden there too;
- ``meta-part``: a bag folder's metadata lists ``run-mcap.mcap.part``, an MCAP of such a chunk;
- ``meta-file-named-mcap``: a file stored compressed (``compression_mode: file``) named ``.mcap``,
  inflating to 1.9 GiB;
- ``mode-nested``, ``mode-space``, ``mode-quoted``: ``compression_mode: message`` written as YAML
  allows (a nested key first, a space before the colon, a quoted key), one message inflating to 600 MiB;
- ``unread-topic``: 100 messages of a topic not read, each inflating to 60 MiB;
- ``ros1-interleaved``: two bz2 chunks of 40 scans each whose times alternate, 3 MB of other topics'
  room before each scan;
- ``merge-held``: two lasers merged, one sending 50 scans at the start, the other 1,200 of 10,000 beams;
- ``tf-dense``: 800,000 transforms a microsecond apart;
- ``tf-deep``: a tf chain of 2,000 frames;
- ``mat-cell``: a ``.mat`` whose 1 x 1 cell array holds 1.46 GB of zeros.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import sqlite3
import struct
import subprocess
import sys
import tempfile
from contextlib import closing
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MB = 2**20
GIB = 2**30


def _craft():
    sys.path.insert(0, str(ROOT))   # the tests' writers of crafted files
    from tests.io import craft

    return craft


# ------------------------------------------------------------------ the files
def _mcap_cases(case: str, folder: Path) -> Path:
    craft = _craft()
    path = folder / "x.mcap"
    stored = craft.zeros_zstd(GIB)
    chunk = craft.mcap_chunk(stored, GIB)
    if case == "mcap-footer":
        path.write_bytes(craft.mcap_file(craft.mcap_record(0x02, bytes(20)), chunk))
    elif case in ("mcap-long-record", "mcap-huge-record"):
        head = craft.mcap_record(0x09, b"", length=2**40 if case == "mcap-long-record" else 2**62)
        at = craft.mcap_offset(head)
        summary = craft.mcap_channel(1, "/odom", "nav_msgs/msg/Odometry") + [
            craft.mcap_chunk_index(at, len(stored), GIB, channel=1)]
        path.write_bytes(craft.mcap_file(head + chunk, summary=summary))
    else:
        at = craft.mcap_offset() + 9 + 4
        summary = b"".join(craft.mcap_channel(1, "/odom", "nav_msgs/msg/Odometry")) + craft.mcap_chunk_index(
            at, len(stored), GIB, channel=1) + b"\x0e"
        data = craft.mcap_file(craft.mcap_record(0x09, b"pad." + chunk + summary))
        footer = len(data) - 8 - 29
        path.write_bytes(data[:footer] + craft.mcap_record(0x02, struct.pack("<QQI", at + len(chunk), 0, 0))
                         + data[-8:])
    return path


def _folder_cases(case: str, folder: Path) -> Path:
    craft = _craft()
    from tests.io.bag_files import write_bag

    if case == "meta-part":
        bag = write_bag(folder, "mcap", "storage")
        (bag / "run-mcap.mcap").unlink()
        (bag / "run-mcap.mcap.part").write_bytes(craft.mcap_file(craft.mcap_chunk(craft.zeros_zstd(GIB), GIB)))
        return craft.rewrite_metadata(bag, lambda t: t.replace("run-mcap.mcap\n", "run-mcap.mcap.part\n"))
    if case == "meta-file-named-mcap":
        bag = write_bag(folder, "mcap", "file")
        (bag / "run-mcap.mcap.zstd").unlink()
        compressor, block = craft.zstd.ZstdCompressor(), bytes(MB)
        with open(bag / "run-mcap.mcap", "wb") as fh:
            for _ in range(1900):
                fh.write(compressor.compress(block))
            fh.write(compressor.flush())
        return craft.rewrite_metadata(bag, lambda t: t.replace("run-mcap.mcap.zstd\n", "run-mcap.mcap\n"))
    bag = write_bag(folder, "sqlite3", "message")
    edits = {"mode-nested": lambda t: t.replace("  custom_data: null\n", "").replace(
                 "rosbag2_bagfile_information:\n", "rosbag2_bagfile_information:\n  custom_data:\n"
                 "    compression_mode: none\n"),
             "mode-space": lambda t: t.replace("compression_mode: message", "compression_mode : message"),
             "mode-quoted": lambda t: t.replace("compression_mode: message", '"compression_mode": message')}
    craft.rewrite_metadata(bag, edits.get(case, lambda t: t))
    with closing(sqlite3.connect(bag / "run-sqlite3.db3")) as db, db:
        topic = "/cloud" if case == "unread-topic" else "/odom"
        (tid,) = db.execute("SELECT id FROM topics WHERE name = ?", (topic,)).fetchone()
        if case == "unread-topic":
            (stamp,) = db.execute("SELECT timestamp FROM messages WHERE topic_id = ?", (tid,)).fetchone()
            bomb = craft.zeros_zstd(60 * MB)
            db.execute("DELETE FROM messages WHERE topic_id = ?", (tid,))
            db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                           [(tid, stamp + k, bomb) for k in range(100)])
        else:
            db.execute("UPDATE messages SET data = ? WHERE id = (SELECT MIN(id) FROM messages WHERE topic_id = ?)",
                       (craft.zeros_zstd(600 * MB), tid))
    return bag


def _interleaved(case: str, folder: Path) -> Path:
    craft = _craft()
    scan = [craft.laser_prefix(4) + struct.pack("<4f", 1, 2, 3, 4) + craft.u32(0)]
    first = [(2 * k * 10**9 + 10**9, scan) for k in range(40)]
    second = [(2 * k * 10**9 + 2 * 10**9, scan) for k in range(40)]
    return craft.ros1_chunked_bag(folder / "x.bag", [first, second], compression="bz2", gap=3 * MB)


def _robot_bags(case: str, folder: Path) -> Path:
    _craft()
    from rosbags.rosbag1 import Writer

    from tests.io.bag_files import store
    from tests.io.scenes import scan_message, tf_message, transform, write_robot_bag

    if case == "tf-deep":
        chain = [(f"f{k}", f"f{k + 1}") for k in range(2000)] + [("f2000", "base_link")]
        scans = [(t, "/scan", "sensor_msgs/msg/LaserScan", lambda ts, t=t: scan_message(
            ts, t, "laser", -1.0, 0.1, np.ones(8, np.float32))) for t in (0.1, 0.2, 0.3)]
        statics = (0.0, "/tf_static", "tf2_msgs/msg/TFMessage", lambda ts: tf_message(
            ts, [transform(ts, 0.0, parent, child, (0.001, 0, 0)) for parent, child in chain]))
        return write_robot_bag(folder / "x.bag", "ros1", scans + [statics])
    ts, path = store("ros1"), folder / "x.bag"
    writer = Writer(path)
    if case == "tf-dense":
        writer.set_compression(Writer.CompressionFormat.BZ2)
    with writer:
        if case == "tf-dense":
            scan = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=ts)
            tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=ts)
            for k in range(800_000):
                t = 1.0 + k * 1e-6
                writer.write(tf, int(round(t * 1e9)), ts.serialize_ros1(tf_message(ts, [transform(
                    ts, t, "odom", "base_link", (1.0, 0.0, 0.0))]), "tf2_msgs/msg/TFMessage"))
            writer.write(scan, int(1.8e9), ts.serialize_ros1(scan_message(ts, 1.8, "base_link", -1.0, 0.1, np.ones(
                8, np.float32)), "sensor_msgs/msg/LaserScan"))
            return path
        lasers = {name: writer.add_connection(f"/scan_{name}", "sensor_msgs/msg/LaserScan", typestore=ts)
                  for name in "ab"}
        ranges, n = np.full(10_000, 2.0, np.float32), 10_000
        times = [(round(0.1 * k, 3), "a") for k in range(1200)] + [(round(0.05 + 0.1 * k, 3), "b") for k in range(50)]
        for t, name in sorted(times):
            writer.write(lasers[name], int(t * 1e9), ts.serialize_ros1(scan_message(
                ts, t, name, -math.pi, 2 * math.pi / n, ranges), "sensor_msgs/msg/LaserScan"))
    return path


def _mat_cell(case: str, folder: Path) -> Path:
    _craft()
    from tests.io.tables.craft import mat_cell_of_zeros

    mat_cell_of_zeros(folder / "x.mat", "X", 182 * MB + MB // 2)
    return folder / "x.mat"


#: each case: (what writes its file, what reads it: a statement with ``path``)
CASES = {
    "mcap-footer": (_mcap_cases, "list(read_bag(path, '/odom'))"),
    "mcap-long-record": (_mcap_cases, "list(read_bag(path, '/odom'))"),
    "mcap-huge-record": (_mcap_cases, "list(read_bag(path, '/odom'))"),
    "mcap-hidden-summary": (_mcap_cases, "list(read_bag(path, '/odom'))"),
    "meta-part": (_folder_cases, "Bag(path).close()"),
    "meta-file-named-mcap": (_folder_cases, "Bag(path).close()"),
    "mode-nested": (_folder_cases, "list(read_bag(path, '/odom'))"),
    "mode-space": (_folder_cases, "list(read_bag(path, '/odom'))"),
    "mode-quoted": (_folder_cases, "list(read_bag(path, '/odom'))"),
    "unread-topic": (_folder_cases, "list(read_bag(path, '/scan'))"),
    "ros1-interleaved": (_interleaved, "list(read_bag(path, '/scan'))"),
    "merge-held": (_robot_bags, "list(read_sweeps(path, topic=['/scan_a', '/scan_b']))"),
    "tf-dense": (_robot_bags, "list(read_sweeps(path))"),
    "tf-deep": (_robot_bags, "list(read_sweeps(path))"),
    "mat-cell": (_mat_cell, "read_scans(path)"),
}

#: what the child runs: the reading, what it said, its wall time and its peak resident memory
CHILD = """
import sys, time, warnings
from pathlib import Path
warnings.simplefilter("ignore")
from novelty.io import read_bag, read_sweeps
from novelty.datasets.files import read_scans
try:
    from novelty.io.bags.rosbag import Bag
except ImportError:
    from novelty.io.rosbag import Bag
path = Path(sys.argv[1])
start = time.perf_counter()
try:
    exec(sys.argv[2])
    said = "read"
except Exception as exc:
    said = f"{type(exc).__name__}: {exc}"
seconds = time.perf_counter() - start
peak = next(int(line.split()[1]) for line in Path("/proc/self/status").read_text().splitlines()
            if line.startswith("VmHWM"))
print(f"{seconds:.2f}\\t{peak / 1024:.0f}\\t{' '.join(said.split())[:160]}")
"""


def _environment(library: Path | None) -> dict:
    return {**os.environ, "PYTHONPATH": str(library or ROOT)}


def _library_read(library: Path | None) -> str:
    """Where the children import ``novelty`` from (to be sure it is the checkout asked for)."""
    with tempfile.TemporaryDirectory() as folder:
        done = subprocess.run([sys.executable, "-c", "import novelty; print(novelty.__file__)"], capture_output=True,
                              text=True, env=_environment(library), cwd=folder, check=True)
    return str(Path(done.stdout.strip()).parent)


def _peak_mb(pid: int) -> str:
    """A running process's peak resident memory so far, in MB (its ``VmHWM``)."""
    status = Path(f"/proc/{pid}/status").read_text().splitlines()
    return next(f"{int(line.split()[1]) / 1024:.0f}" for line in status if line.startswith("VmHWM"))


def run_case(case: str, folder: Path, library: Path | None, limit: int, timeout: float) -> tuple:
    """``(file bytes, seconds, peak MB, what it said)`` of one case, read in a limited child process."""
    write, statement = CASES[case]
    path = write(case, folder)
    size = sum(f.stat().st_size for f in ([path] if path.is_file() else path.rglob("*")) if f.is_file())
    env = _environment(library)

    def limited():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    # run in the case's folder: ``python -c`` puts its working directory first on the path
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path), statement], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=env, cwd=folder, preexec_fn=limited)
    try:
        out, err = child.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        peak = _peak_mb(child.pid)   # read before the kill: the peak so far
        child.kill()
        child.communicate()
        return size, f">{timeout:.0f}", peak, "stopped at the time limit"
    if child.returncode != 0:
        return size, "", "", f"exit {child.returncode}: {' '.join(err.split())[-160:]}"
    seconds, peak, said = out.strip().splitlines()[-1].split("\t")
    return size, seconds, peak, said


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default=",".join(CASES), help="comma-separated cases (default: all)")
    parser.add_argument("--library", type=Path, help="read with the novelty of this checkout")
    parser.add_argument("--limit-gb", type=float, default=4.0, help="address space of a child (GB)")
    parser.add_argument("--timeout", type=float, default=300.0, help="seconds a child may take")
    args = parser.parse_args(argv)
    print(f"novelty read from {_library_read(args.library)}\n")
    print("| case | file bytes | seconds | peak MB | the reading said |\n| --- | --- | --- | --- | --- |")
    for case in args.cases.split(","):
        with tempfile.TemporaryDirectory() as folder:
            size, seconds, peak, said = run_case(case, Path(folder), args.library, int(args.limit_gb * 1e9),
                                                 args.timeout)
        print(f"| {case} | {size:,} | {seconds} | {peak} | {said.replace('|', '/')} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
