"""The ROS 1 bag reader: the same messages as rosbags' reader, and crafted bags refused in bounded time and memory."""

import struct
import subprocess
import sys
from pathlib import Path

import pytest

import novelty
from novelty.io.ros import caps
from novelty.io.ros1.bag1 import Bag1, BagFormatError
from novelty.io.ros.caps import MessageError

from novelty.io.ros1 import chunks

from ...io.craft import Zeros, laser_prefix, ros1_bag, ros1_chunked_bag, u32

pytest.importorskip("rosbags", reason="the reader is checked against rosbags (the ros extra)")

from rosbags.rosbag1 import Reader, Writer  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

from ...io.bag_files import _messages  # noqa: E402

ENV = {"PYTHONPATH": str(Path(novelty.__file__).parents[1])}
SCAN = [laser_prefix(4) + struct.pack("<4f", 1, 2, 3, 4) + u32(0)]


@pytest.mark.parametrize("compression", [None, "BZ2", "LZ4"])
def test_every_message_as_rosbags_reads_it(tmp_path, compression):
    ts = get_typestore(Stores.ROS1_NOETIC)
    ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    path = tmp_path / "run.bag"
    writer = Writer(path)
    if compression:
        writer.set_compression(getattr(Writer.CompressionFormat, compression))
    writer.chunk_threshold = 600   # several chunks, their messages interleaved by time (a public attribute)
    with writer:
        connections = {}
        for t, topic, msgtype, msg in _messages(ts):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=ts)
            writer.write(connections[topic], int(round(t * 1e9)) + 1000, ts.serialize_ros1(msg, msgtype))
    with Bag1(path) as ours, Reader(path) as theirs:
        topics = list(ours.topics)
        assert ours.topics == {t: info.msgtype for t, info in theirs.topics.items()}
        assert [ours.count(t) for t in topics] == [theirs.topics[t].msgcount for t in topics]
        assert len(ours.chunk_infos) > 1
        read = [(c.topic, t, d) for c, t, _, d in ours.messages(topics, dict.fromkeys(topics, (10**6, None)))]
        assert read == [(c.topic, t, bytes(d)) for c, t, d in theirs.messages()]
        numbers = [n for c, _, n, _ in ours.messages(["/scan"], {"/scan": (10**6, None)})]
        assert numbers == [1, 2, 3, 4, 5]


HOSTILE = """
import resource, sys, time
from pathlib import Path
from novelty.io.recording import read_rings
start = time.process_time()
try:
    list(read_rings(sys.argv[1], "/scan"))
except ValueError as exc:
    print(exc)
status = Path("/proc/self/status")
# the process's peak resident memory: VmHWM where Linux tells it (ru_maxrss counts the forking parent's too)
peak = next((int(line.split()[1]) for line in status.read_text().splitlines() if line.startswith("VmHWM")), None) \
    if status.exists() else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(time.process_time() - start, peak / 1024)
"""


def test_a_5_kb_bag_stating_50_million_beams_is_refused_in_bounded_time_and_memory(tmp_path):
    # one bz2 chunk whose LaserScan states 50 million beams, its 200 MB of zeros there to inflate
    n = 50_000_000
    path = ros1_bag(tmp_path / "hostile.bag", [(10**9, [laser_prefix(n), Zeros(4 * n + 4)])], compression="bz2")
    assert path.stat().st_size < 10_000
    done = subprocess.run([sys.executable, "-c", HOSTILE, str(path)], capture_output=True, text=True, env=ENV,
                          timeout=120)
    error, measured = done.stdout.strip().splitlines()
    assert error == (f"{path}, topic /scan, message 1 (ranges): states 50,000,000 beams; at most 100,000 are read "
                     "(novelty.io.ros.caps.MAX_BEAMS).")
    cpu_seconds, peak_mb = (float(v) for v in measured.split())
    assert cpu_seconds < 1.0 and peak_mb < 200, measured


def test_crafted_chunks_and_records_are_refused_naming_what(tmp_path, monkeypatch):
    two = [(10**9, SCAN), (2 * 10**9, SCAN)]
    # a chunk that states fewer bytes than its records need: its last message runs past it
    short = ros1_bag(tmp_path / "short.bag", two, compression="bz2", size=150)
    with pytest.raises(MessageError, match=r"short.bag, topic /scan, message \d \((record|length)\)"):
        list(_read(short))
    # a message the index places where the chunk ends before it
    beyond = ros1_bag(tmp_path / "beyond.bag", two, offsets=[0, 10**6])
    with pytest.raises(MessageError, match=r"message 2 \(record\)"):
        list(_read(beyond))
    # an index pointing into the middle of a record
    askew = ros1_bag(tmp_path / "askew.bag", two, offsets=[0, 5])
    with pytest.raises(MessageError, match=r"beyond|record|length"):
        list(_read(askew))
    # a message beyond what a chunk may be inflated to reach
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", 650)   # the first message ends at byte 604 of 723
    with pytest.raises(MessageError, match=r"message 2 \(chunk\): lies \d+ bytes into its chunk's"):
        list(_read(ros1_bag(tmp_path / "ok.bag", two, compression="bz2")))


def test_files_that_are_not_ros1_bags(tmp_path):
    for name, content, says in [
        ("text.bag", b"hello", "it does not start with #ROSBAG V2.0"),
        ("cut.bag", b"#ROSBAG V2.0\n\x10\x00\x00\x00", "a record at byte 13 states a 16-byte header"),
    ]:
        (tmp_path / name).write_bytes(content)
        with pytest.raises(BagFormatError, match=f"{name} is not a readable bag \\(ROS 1, format 2.0\\): {says}"):
            Bag1(tmp_path / name)
    whole = ros1_bag(tmp_path / "whole.bag", [(10**9, SCAN)]).read_bytes()
    (tmp_path / "truncated.bag").write_bytes(whole[:-40])
    with pytest.raises(BagFormatError, match="truncated.bag is not a readable bag"):
        Bag1(tmp_path / "truncated.bag")


def _read(path):
    with Bag1(path) as bag:
        yield from bag.messages(["/scan"], {"/scan": (10**6, None)})


def test_chunks_whose_messages_interleave_in_time_are_each_inflated_once(tmp_path, monkeypatch):
    # two chunks of 40 scans each, their times alternating, a megabyte of other topics' room before each scan
    n, gap = 40, 2**20
    first = [(2 * k * 10**9 + 10**9, SCAN) for k in range(n)]
    second = [(2 * k * 10**9 + 2 * 10**9, SCAN) for k in range(n)]
    path = ros1_chunked_bag(tmp_path / "interleaved.bag", [first, second], compression="bz2", gap=gap)
    assert path.stat().st_size < 30_000
    inflated = []
    make = chunks._decompressor

    def counted(compression):
        decompressor = make(compression)

        class Counting:
            def __getattr__(self, name):
                return getattr(decompressor, name)

            def decompress(self, data, max_length=-1):
                out = decompressor.decompress(data, max_length=max_length)
                inflated.append(len(out))
                return out

        return Counting()

    monkeypatch.setattr(chunks, "_decompressor", counted)
    read = [(time, number) for _, time, number, _ in _read(path)]
    assert read == [(k * 10**9, k) for k in range(1, 2 * n + 1)]   # in time order, numbered so
    chunk_bytes = n * (gap + 200)
    assert sum(inflated) <= 2 * chunk_bytes   # each chunk inflated once (before: from its start at each switch)
    # the messages taken out before their turn are held within a bound
    monkeypatch.setattr(caps, "MAX_HELD_BYTES", 1000)
    with pytest.raises(MessageError, match=r"interleaved.bag, topic /scan, message \d+ \(chunk\): more than 1,000 "
                                           r"bytes of messages would wait for their turn"):
        list(_read(path))
