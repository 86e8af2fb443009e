"""ROS 2 bags stored compressed: read as the uncompressed ones, and every part that would inflate beyond its cap
refused before rosbags inflates it, in bounded memory."""

import struct
import tracemalloc

import pytest

pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                    "'novelty-habituation[ros]'")

from novelty.io.ros import caps
from novelty.io.ros2 import inflation as ros2_inflation  # noqa: E402
from novelty.io.ros.caps import MessageError  # noqa: E402
from novelty.io.bags.rosbag import Bag, read_bag  # noqa: E402
from novelty.io.ros2.inflation import MCAP_MAGIC, _zstd  # noqa: E402

from ...io.bag_files import write_bag  # noqa: E402

MB = 2**20


def _record(opcode: int, content: bytes) -> bytes:
    return struct.pack("<BQ", opcode, len(content)) + content


def _string(text: str) -> bytes:
    return struct.pack("<I", len(text)) + text.encode()


def _chunk(stored: bytes, size: int, compression: str = "zstd") -> bytes:
    """A chunk record (0x06): times, the uncompressed size it states, no crc, its compression, its records."""
    return _record(0x06, struct.pack("<QQQI", 0, 0, size, 0) + _string(compression)
                   + struct.pack("<Q", len(stored)) + stored)


def _chunk_index(offset: int, stored: int, size: int, compression: str = "zstd") -> bytes:
    return _record(0x08, struct.pack("<QQQQ", 0, 0, offset, 0) + struct.pack("<I", 0) + struct.pack("<Q", 0)
                   + _string(compression) + struct.pack("<QQ", stored, size))


def _mcap(*records: bytes) -> bytes:
    header = _record(0x01, _string("ros2") + _string("a test"))
    return MCAP_MAGIC + header + b"".join(records) + _record(0x02, bytes(20)) + MCAP_MAGIC


def _zeros_zstd(n: int) -> bytes:
    """A zstd frame of ``n`` zero bytes, compressed a megabyte at a time (never holding ``n`` bytes)."""
    compressor = _zstd().ZstdCompressor()
    block = bytes(min(n, MB))
    parts = [compressor.compress(block[:min(MB, n - i)]) for i in range(0, n, MB)]
    return b"".join(parts) + compressor.flush()


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
    path.write_bytes(_mcap(_chunk(b"\x00" * 16, 2**40)))
    with pytest.raises(MessageError, match=r"big.mcap, MCAP chunk at byte 3\d: states 1,099,511,627,776 bytes "
                                           r"uncompressed; at most 134,217,728 .*MAX_CHUNK_BYTES"):
        Bag(path)


@pytest.mark.parametrize("compress", [_zeros_zstd, _zeros_lz4], ids=["zstd", "lz4"])
def test_a_chunk_inflating_past_what_it_states_is_refused_holding_one_cap_at_most(tmp_path, compress):
    compression = "zstd" if compress is _zeros_zstd else "lz4"
    path = tmp_path / "bomb.mcap"
    bomb = compress(64 * MB)   # about 2 to 250 KB on disk
    path.write_bytes(_mcap(_chunk(bomb, 1000, compression)))
    error, peak = _peak_while(lambda: Bag(path))
    assert "states 1,000 bytes uncompressed and inflates to more" in str(error)
    assert peak < 4 * MB + 2 * len(bomb)   # the file's bytes a block at a time, 1,001 inflated


def test_every_frame_of_a_chunk_is_counted(tmp_path):
    # the first frame inflates to the size stated; rosbags inflates the second too
    path = tmp_path / "frames.mcap"
    path.write_bytes(_mcap(_chunk(_zeros_zstd(1000) + _zeros_zstd(64 * MB), 1000)))
    error, peak = _peak_while(lambda: Bag(path))
    assert "inflates to more" in str(error) and peak < 4 * MB


def test_a_chunk_inflating_short_of_what_it_states_and_damaged_data_are_refused(tmp_path):
    path = tmp_path / "short.mcap"
    path.write_bytes(_mcap(_chunk(_zeros_zstd(10), 1000)))
    with pytest.raises(MessageError, match="states 1,000 bytes uncompressed and inflates to 10 "):
        Bag(path)
    path.write_bytes(_mcap(_chunk(b"not zstd at all", 1000)))
    with pytest.raises(MessageError, match=r"MCAP chunk at byte \d+: its zstd data are damaged"):
        Bag(path)
    path.write_bytes(_mcap(_chunk(b"", 1000, compression="bz2")))
    with pytest.raises(MessageError, match="compression 'bz2'; MCAP's are zstd, lz4 and none"):
        Bag(path)


def test_a_chunk_index_must_point_at_the_chunk_it_describes(tmp_path):
    stored = _zeros_zstd(100)
    chunk = _chunk(stored, 100)
    at = len(MCAP_MAGIC) + len(_record(0x01, _string("ros2") + _string("a test")))
    path = tmp_path / "index.mcap"
    # rosbags reads a chunk where the summary's index says, with the index's sizes
    for offset, size in ((at + 1, 100), (at, 10**9)):
        path.write_bytes(_mcap(chunk, _chunk_index(offset, len(stored), size)))
        with pytest.raises(MessageError, match=f"chunk index at byte .*points at byte {offset:,}, where no chunk"):
            Bag(path)
    path.write_bytes(_mcap(chunk, _chunk_index(at, len(stored), 100)))
    ros2_inflation.check_inflation(path)   # the index that describes its chunk passes


@pytest.mark.parametrize("kind", ["mcap", "sqlite3"])
def test_a_message_stored_compressed_beyond_its_cap_is_refused(tmp_path, monkeypatch, kind):
    bag = write_bag(tmp_path, kind, "message")
    monkeypatch.setattr(caps, "MAX_MESSAGE_BYTES", 100)   # an odometry message has 36 + 36 doubles
    with pytest.raises(MessageError, match="a message inflates to more than 100 bytes"):
        Bag(bag)


def test_a_file_stored_compressed_inflating_beyond_its_cap_is_refused(tmp_path, monkeypatch):
    bag = write_bag(tmp_path, "sqlite3", "file")
    monkeypatch.setattr(caps, "MAX_CHUNK_BYTES", 1000)
    monkeypatch.setattr(ros2_inflation, "MAX_INFLATION", 1)
    with pytest.raises(MessageError, match=r"run-sqlite3.db3.zstd: inflates to more than [\d,]+ bytes, 1 times"):
        Bag(bag)


def test_an_mcap_stored_compressed_is_walked_as_it_inflates(tmp_path):
    folder = tmp_path / "bag"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information:\n  compression_format: zstd\n"
                                          "  compression_mode: file\n")
    (folder / "bag.mcap.zstd").write_bytes(_zstd().compress(_mcap(_chunk(_zeros_zstd(64 * MB), 1000))))
    error, peak = _peak_while(lambda: Bag(folder))
    assert "bag.mcap.zstd, MCAP chunk at byte" in str(error) and "inflates to more" in str(error)
    assert peak < 8 * MB
