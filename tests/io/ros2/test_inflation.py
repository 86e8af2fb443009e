"""ROS 2 bags stored compressed: read as the uncompressed ones, and every part that would inflate beyond its cap
refused before rosbags inflates it, in bounded memory."""

import sqlite3
import struct
import tracemalloc
from contextlib import closing

import pytest

pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                    "'novelty-habituation[ros]'")

from novelty.io.bags.rosbag import Bag, read_bag  # noqa: E402
from novelty.io.ros import caps  # noqa: E402
from novelty.io.ros.caps import MessageError  # noqa: E402
from novelty.io.ros2 import inflation as ros2_inflation  # noqa: E402

from ...io.bag_files import write_bag  # noqa: E402
from ...io.craft import MB, mcap_channel, mcap_chunk, mcap_chunk_index, mcap_file, mcap_offset, mcap_record, \
    rewrite_metadata, zeros_zstd, zstd  # noqa: E402


def _zeros_lz4(n: int) -> bytes:
    import lz4.frame

    compressor = lz4.frame.LZ4FrameCompressor()
    parts = [compressor.begin()] + [compressor.compress(bytes(min(MB, n - i))) for i in range(0, n, MB)]
    return b"".join(parts) + compressor.flush()


def _peak_while(call) -> tuple[Exception, int]:
    """The error ``call`` raises and the peak bytes Python allocated meanwhile."""
    tracemalloc.start()
    try:
        with pytest.raises(MessageError) as caught:
            call()
        return caught.value, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("kind, compression", [("mcap", "storage"), ("mcap", "message"), ("mcap", "file"),
                                               ("sqlite3", "message"), ("sqlite3", "file")])
def test_a_bag_stored_compressed_reads_as_the_uncompressed(tmp_path, kind, compression):
    plain = [repr(m) for m in read_bag(write_bag(tmp_path / "plain", kind), "/scan")]
    packed = [repr(m) for m in read_bag(write_bag(tmp_path / "packed", kind, compression), "/scan")]
    assert len(plain) == 5 and packed == plain


def test_a_chunk_stating_more_than_its_cap_is_refused_before_anything_is_inflated(tmp_path):
    path = tmp_path / "big.mcap"
    path.write_bytes(mcap_file(mcap_chunk(b"\x00" * 16, 2**40)))
    with pytest.raises(MessageError, match=r"big.mcap, MCAP chunk at byte 3\d: states 1,099,511,627,776 bytes "
                                           r"uncompressed; at most 134,217,728 .*MAX_CHUNK_BYTES"):
        Bag(path)


@pytest.mark.parametrize("compress", [zeros_zstd, _zeros_lz4], ids=["zstd", "lz4"])
def test_a_chunk_inflating_past_what_it_states_is_refused_holding_one_cap_at_most(tmp_path, compress):
    compression = "zstd" if compress is zeros_zstd else "lz4"
    path = tmp_path / "bomb.mcap"
    bomb = compress(64 * MB)   # about 2 to 250 KB on disk
    path.write_bytes(mcap_file(mcap_chunk(bomb, 1000, compression)))
    error, peak = _peak_while(lambda: Bag(path))
    assert "states 1,000 bytes uncompressed and inflates to more" in str(error)
    assert peak < 4 * MB + 2 * len(bomb)   # the file's bytes a block at a time, 1,001 inflated


def test_every_frame_of_a_chunk_is_counted(tmp_path):
    # the first frame inflates to the size stated; rosbags inflates the second too
    path = tmp_path / "frames.mcap"
    path.write_bytes(mcap_file(mcap_chunk(zeros_zstd(1000) + zeros_zstd(64 * MB), 1000)))
    error, peak = _peak_while(lambda: Bag(path))
    assert "inflates to more" in str(error) and peak < 4 * MB


def test_a_chunk_inflating_short_of_what_it_states_and_damaged_data_are_refused(tmp_path):
    path = tmp_path / "short.mcap"
    path.write_bytes(mcap_file(mcap_chunk(zeros_zstd(10), 1000)))
    with pytest.raises(MessageError, match="states 1,000 bytes uncompressed and inflates to 10 "):
        Bag(path)
    path.write_bytes(mcap_file(mcap_chunk(b"not zstd at all", 1000)))
    with pytest.raises(MessageError, match=r"MCAP chunk at byte \d+: its zstd data are damaged"):
        Bag(path)
    path.write_bytes(mcap_file(mcap_chunk(b"", 1000, compression="bz2")))
    with pytest.raises(MessageError, match="compression 'bz2'; MCAP's are zstd, lz4 and none"):
        Bag(path)


def test_a_chunk_index_must_point_at_the_chunk_it_describes(tmp_path):
    stored = zeros_zstd(100)
    chunk = mcap_chunk(stored, 100)
    at = mcap_offset()
    path = tmp_path / "index.mcap"
    # rosbags reads a chunk where the summary's index says, with the index's sizes
    for offset, size in ((at + 1, 100), (at, 10**9)):
        path.write_bytes(mcap_file(chunk, mcap_chunk_index(offset, len(stored), size)))
        with pytest.raises(MessageError, match=f"chunk index at byte .*points at byte {offset:,}, where no chunk"):
            Bag(path)
    path.write_bytes(mcap_file(chunk, mcap_chunk_index(at, len(stored), 100)))
    ros2_inflation.check_inflation(path)   # the index that describes its chunk passes


@pytest.mark.parametrize("kind", ["mcap", "sqlite3"])
def test_a_message_stored_compressed_beyond_its_cap_is_refused_when_its_topic_is_read(tmp_path, monkeypatch, kind):
    bag = write_bag(tmp_path, kind, "message")
    monkeypatch.setattr(caps, "MAX_MESSAGE_BYTES", 100)   # a sonar's Range fits; an odometry message does not
    assert len(list(read_bag(bag, "/sonar"))) == 9   # the messages of the topics read only are checked
    with pytest.raises(MessageError, match=r"topic /odom, message (id )?\d+: a message inflates to more than 100 "
                                           "bytes"):
        list(read_bag(bag, "/odom"))


def test_a_file_stored_compressed_inflating_beyond_its_cap_is_refused(tmp_path, monkeypatch):
    bag = write_bag(tmp_path, "sqlite3", "file")
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", 1000)
    monkeypatch.setattr(ros2_inflation, "MAX_INFLATION", 1)
    with pytest.raises(MessageError, match=r"run-sqlite3.db3.zstd: inflates to more than [\d,]+ bytes, 1 times"):
        Bag(bag)


def test_an_mcap_stored_compressed_is_walked_as_it_inflates(tmp_path):
    folder = write_bag(tmp_path, "mcap", "file")
    (folder / "run-mcap.mcap.zstd").write_bytes(zstd.compress(mcap_file(mcap_chunk(zeros_zstd(64 * MB), 1000))))
    error, peak = _peak_while(lambda: Bag(folder))
    assert "run-mcap.mcap.zstd, MCAP chunk at byte" in str(error) and "inflates to more" in str(error)
    assert peak < 8 * MB


# ------------------------------------------------------------------ what rosbags reads, checked as it reads it
def test_a_footer_before_the_files_end_is_refused_not_taken_for_its_end(tmp_path, monkeypatch):
    # rosbags scans past a footer opcode in the data section to the chunk behind it
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", MB)
    path = tmp_path / "early-footer.mcap"
    path.write_bytes(mcap_file(mcap_record(0x02, bytes(20)), mcap_chunk(zeros_zstd(4 * MB), 4 * MB)))
    with pytest.raises(MessageError, match=rf"early-footer.mcap, MCAP footer at byte {mcap_offset()}: before the "
                                           r"file's end \(a footer ends it; a corrupt or hostile file\)"):
        Bag(path)


@pytest.mark.parametrize("length", [2**40, 2**62])
def test_a_record_reaching_past_the_files_end_is_refused_naming_it(tmp_path, length):
    # rosbags would find the chunks after it through the summary
    path = tmp_path / "long.mcap"
    path.write_bytes(mcap_file(mcap_record(0x09, b"", length=length)))
    with pytest.raises(MessageError, match=rf"long.mcap, MCAP record of opcode 0x09 at byte {mcap_offset()}: states "
                                           rf"{length:,} bytes, past the file's end at byte {path.stat().st_size:,}"):
        Bag(path)


def test_the_summary_is_checked_where_the_footer_points_not_where_the_walk_finds_it(tmp_path, monkeypatch):
    # an attachment's payload holds a chunk and a summary indexing it; the footer points into it
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", MB)
    stored = zeros_zstd(4 * MB)
    hidden_at = mcap_offset() + 9 + 4
    chunk = mcap_chunk(stored, 4 * MB)
    summary = b"".join(mcap_channel(1, "/odom", "nav_msgs/msg/Odometry")) + mcap_chunk_index(
        hidden_at, len(stored), 4 * MB, channel=1) + b"\x0e"
    attachment = mcap_record(0x09, b"pad." + chunk + summary)
    data = mcap_file(attachment)
    summary_at = hidden_at + len(chunk)
    footer_at = len(data) - 8 - 29
    path = tmp_path / "hidden.mcap"
    path.write_bytes(data[:footer_at] + mcap_record(0x02, struct.pack("<QQI", summary_at, 0, 0)) + data[-8:])
    with pytest.raises(MessageError, match=rf"hidden.mcap, MCAP footer at byte {footer_at:,}: states the summary "
                                           rf"at byte {summary_at:,}, where no record begins"):
        list(read_bag(path, "/odom"))


@pytest.mark.parametrize("compression, stored, listed, says", [
    ("storage", "run-mcap.mcap", "run-mcap.mcap.part", r"run-mcap.mcap.part, MCAP chunk at byte \d+: states [\d,]+ "
                                                        "bytes uncompressed; at most 1,000"),
    ("file", "run-sqlite3.db3.zstd", "run-sqlite3.db3", r"run-sqlite3/run-sqlite3.db3: inflates to more than "
                                                         r"[\d,]+ bytes, 1 times"),
], ids=["chunks", "file"])
def test_every_file_the_metadata_lists_is_checked_as_stored_whatever_its_name(tmp_path, monkeypatch, compression,
                                                                              stored, listed, says):
    folder = write_bag(tmp_path, "mcap" if compression == "storage" else "sqlite3", compression)
    (folder / stored).rename(folder / listed)
    rewrite_metadata(folder, lambda text: text.replace(f"{stored}\n", f"{listed}\n"))
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", 1000)
    monkeypatch.setattr(ros2_inflation, "MAX_INFLATION", 1)
    with pytest.raises(MessageError, match=says):
        Bag(folder)


@pytest.mark.parametrize("edit", [
    lambda text: text.replace("  custom_data: null\n", "").replace(
        "rosbag2_bagfile_information:\n", "rosbag2_bagfile_information:\n  custom_data:\n    compression_mode: none\n"),
    lambda text: text.replace("compression_mode: message", "compression_mode : message"),
    lambda text: text.replace("compression_mode: message", '"compression_mode": message'),
    lambda text: text.replace("compression_mode: message", "compression_mode: MESSAGE"),
], ids=["nested-first", "space-before-colon", "quoted-key", "upper-case"])
def test_the_compression_mode_is_read_as_yaml_as_rosbags_reads_it(tmp_path, monkeypatch, edit):
    folder = rewrite_metadata(write_bag(tmp_path, "sqlite3", "message"), edit)
    monkeypatch.setattr(caps, "MAX_MESSAGE_BYTES", 100)   # an odometry message has 36 + 36 doubles
    with pytest.raises(MessageError, match="a message inflates to more than 100 bytes"):
        list(read_bag(folder, "/odom"))


def test_the_messages_read_inflate_to_a_bounded_total(tmp_path, monkeypatch):
    folder = write_bag(tmp_path, "sqlite3", "message")
    database = folder / "run-sqlite3.db3"
    with closing(sqlite3.connect(database)) as db, db:
        (odom,) = db.execute("SELECT id FROM topics WHERE name = '/odom'").fetchone()
        db.execute("UPDATE messages SET data = ? WHERE topic_id = ?", (zeros_zstd(MB), odom))
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", 1000)
    monkeypatch.setattr(ros2_inflation, "MAX_INFLATION", 10)   # the file is about 30 KB; each message inflates to 1 MB
    with pytest.raises(MessageError, match=r"run-sqlite3.db3: the messages of /odom inflate to more than [\d,]+ bytes, "
                                           r"10 times the file's size \(novelty.io.ros2.inflation.MAX_INFLATION\)"):
        list(read_bag(folder, "/odom"))
