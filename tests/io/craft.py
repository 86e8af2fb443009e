"""Bags written byte by byte from the formats' documentation, to craft what no writer would write.

ROS 1: a bag of chunks, each of records (a connection record, then message
records) given as parts, each bytes or :class:`Zeros` (so that a chunk can
hold hundreds of megabytes of zeros without their being made: bz2 compresses
each run of zeros on its own, and a bz2 chunk is the concatenation of its
parts' streams). ``size`` and ``offsets`` can be stated falsely.

ROS 2: MCAP records (:func:`mcap_file`, a summary optional) and the
``metadata.yaml`` of a bag folder as text (:func:`rewrite_metadata`).
"""

import bz2
import functools
import struct
from pathlib import Path

try:
    from compression import zstd
except ImportError:   # before Python 3.14: the backport rosbags depends on
    from backports import zstd

U32 = struct.Struct("<I")
#: the standard definitions' md5 sums, as ROS 1 connection records state them
MD5 = {"sensor_msgs/LaserScan": "90c7ef2dc6895d81024acba2ac42f369",
       "sensor_msgs/PointCloud2": "1158d486dd51d683ce2f1be655c3c181"}
LASER_DEF = """Header header
float32 angle_min
float32 angle_max
float32 angle_increment
float32 time_increment
float32 scan_time
float32 range_min
float32 range_max
float32[] ranges
float32[] intensities
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
"""


class Zeros:
    """``n`` zero bytes, never made."""

    def __init__(self, n: int):
        self.n = n


def header(**fields) -> bytes:
    out = b""
    for name, value in fields.items():
        field = name.encode() + b"=" + value
        out += U32.pack(len(field)) + field
    return out


def record(fields: bytes, data) -> list:
    """A record's parts: its header, its data's length, its data (bytes or Zeros parts)."""
    data = data if isinstance(data, list) else [data]
    size = sum(p.n if isinstance(p, Zeros) else len(p) for p in data)
    return [U32.pack(len(fields)) + fields + U32.pack(size)] + data


def u32(v: int) -> bytes:
    return U32.pack(v)


def time_bytes(ns: int) -> bytes:
    return struct.pack("<II", ns // 10**9, ns % 10**9)


def laser_prefix(n_beams: int, frame: str = "laser", stamp_ns: int = 10**9) -> bytes:
    """A ROS 1 LaserScan's bytes up to and including its ranges' count."""
    return (u32(0) + time_bytes(stamp_ns) + u32(len(frame)) + frame.encode()
            + struct.pack("<7f", -1.5, 1.5, 3.0 / max(n_beams - 1, 1), 0.0, 0.1, 0.05, 30.0) + u32(n_beams))


@functools.lru_cache(maxsize=None)
def _zeros_stream(n: int) -> bytes:
    return bz2.compress(bytes(n), 1)


def _compress(parts, compression: str) -> bytes:
    if compression == "none":
        return b"".join(bytes(p.n) if isinstance(p, Zeros) else p for p in parts)
    block, out = 4 * 2**20, []
    for part in parts:
        if isinstance(part, Zeros):
            whole, rest = divmod(part.n, block)
            out += [_zeros_stream(block)] * whole + ([_zeros_stream(rest)] if rest else [])
        else:
            out.append(bz2.compress(part))
    return b"".join(out)


def ros1_bag(path, messages, *, topic="/scan", msgtype="sensor_msgs/LaserScan", msgdef=LASER_DEF,
             compression="none", size=None, offsets=None):
    """Write a one-chunk bag of ``messages`` (each ``(time_ns, data parts)``) on ``topic``; its path."""
    return ros1_chunked_bag(path, [messages], topic=topic, msgtype=msgtype, msgdef=msgdef, compression=compression,
                            sizes=[size], offsets=[offsets])


def ros1_chunked_bag(path, chunks, *, topic="/scan", msgtype="sensor_msgs/LaserScan", msgdef=LASER_DEF,
                     compression="none", sizes=None, offsets=None, gap=0):
    """Write a bag of ``chunks`` (each a list of messages ``(time_ns, data parts)``, in the file's order, their
    times free to interleave with other chunks') on ``topic``; each chunk's stated ``sizes`` and index
    ``offsets`` may be given (None: the true ones), and ``gap`` zero bytes before each message record (the
    room other topics' messages would take); its path."""
    start = len(b"#ROSBAG V2.0\n") + 8 + 4096   # the bag header record, padded to 4 KB
    body, infos, position = [], [], start
    for k, messages in enumerate(chunks):
        size = None if sizes is None else sizes[k]
        stated = None if offsets is None else offsets[k]
        parts = _chunk(messages, topic, msgtype, msgdef, compression, size, stated, gap)
        times = [t for t, _ in messages] or [0]
        infos += record(header(op=b"\x06", ver=u32(1), chunk_pos=struct.pack("<Q", position),
                               start_time=time_bytes(min(times)), end_time=time_bytes(max(times)), count=u32(1)),
                        u32(0) + u32(len(messages)))
        body += parts
        position += _length(parts)
    bag_header_fields = header(op=b"\x03", index_pos=struct.pack("<Q", position), conn_count=u32(1),
                               chunk_count=u32(len(chunks)))
    padding = 4096 - len(bag_header_fields)
    head = b"#ROSBAG V2.0\n" + U32.pack(len(bag_header_fields)) + bag_header_fields + U32.pack(padding) + b" " * padding
    assert len(head) == start
    with open(path, "wb") as fh:
        fh.write(head)
        for part in body:
            fh.write(bytes(part.n) if isinstance(part, Zeros) else part)
        fh.write(b"".join(_flat(connection_index(topic, msgtype, msgdef))) + b"".join(_flat(infos)))
    return path


def _chunk(messages, topic, msgtype, msgdef, compression, size, offsets, gap=0) -> list:
    """A chunk record of ``messages`` and its index record, as parts."""
    conn_fields = header(topic=topic.encode(), type=msgtype.encode(), md5sum=MD5[msgtype].encode(),
                         message_definition=msgdef.encode())
    connection = record(header(op=b"\x07", conn=u32(0), topic=topic.encode()), conn_fields)
    parts, true_offsets, position = list(connection), [], _length(connection)
    for time_ns, data in messages:
        if gap:
            parts.append(Zeros(gap))
            position += gap
        true_offsets.append(position)
        rec = record(header(op=b"\x02", conn=u32(0), time=time_bytes(time_ns)), data)
        parts += rec
        position += _length(rec)
    offsets = true_offsets if offsets is None else offsets
    chunk = record(header(op=b"\x05", compression=compression.encode(), size=u32(position if size is None else size)),
                   _compress(parts, compression))
    index = record(header(op=b"\x04", ver=u32(1), conn=u32(0), count=u32(len(messages))),
                   b"".join(time_bytes(t) + u32(o) for (t, _), o in zip(messages, offsets)))
    return chunk + index


def connection_index(topic, msgtype, msgdef):
    fields = header(topic=topic.encode(), type=msgtype.encode(), md5sum=MD5[msgtype].encode(), message_definition=msgdef.encode())
    return record(header(op=b"\x07", conn=u32(0), topic=topic.encode()), fields)


def _length(parts) -> int:
    return sum(p.n if isinstance(p, Zeros) else len(p) for p in parts)


def _flat(parts) -> list:
    return [bytes(p.n) if isinstance(p, Zeros) else p for p in parts]


# ------------------------------------------------------------------ MCAP (ROS 2)
MCAP_MAGIC = b"\x89MCAP0\r\n"
MB = 2**20


def mcap_record(opcode: int, content: bytes, length: int | None = None) -> bytes:
    """A record: its opcode, its length (stated falsely if ``length`` is given), its content."""
    return struct.pack("<BQ", opcode, len(content) if length is None else length) + content


def mcap_string(text: str) -> bytes:
    return struct.pack("<I", len(text)) + text.encode()


def mcap_chunk(stored: bytes, size: int, compression: str = "zstd") -> bytes:
    """A chunk record (0x06): times, the uncompressed size it states, no crc, its compression, its records."""
    return mcap_record(0x06, struct.pack("<QQQI", 0, 0, size, 0) + mcap_string(compression)
                       + struct.pack("<Q", len(stored)) + stored)


def mcap_chunk_index(offset: int, stored: int, size: int, compression: str = "zstd", channel: int | None = None) -> bytes:
    """A chunk index record (0x08) of the chunk at ``offset``; with ``channel``, listing one message of it."""
    offsets = b"" if channel is None else struct.pack("<HQ", channel, offset + 100)
    return mcap_record(0x08, struct.pack("<QQQQ", 0, 0, offset, 100) + struct.pack("<I", len(offsets)) + offsets
                       + struct.pack("<Q", 0 if channel is None else 100) + mcap_string(compression)
                       + struct.pack("<QQ", stored, size))


def mcap_channel(channel: int, topic: str, msgtype: str) -> list[bytes]:
    """A schema record (0x03) of ``msgtype`` and a channel record (0x04) of ``topic``, CDR without QoS."""
    schema = mcap_record(0x03, struct.pack("<H", channel) + mcap_string(msgtype) + mcap_string("ros2msg")
                         + mcap_string(""))
    return [schema, mcap_record(0x04, struct.pack("<HH", channel, channel) + mcap_string(topic) + mcap_string("cdr")
                                + struct.pack("<I", 0))]


def mcap_header() -> bytes:
    return mcap_record(0x01, mcap_string("ros2") + mcap_string("a test"))


def mcap_file(*records: bytes, summary=()) -> bytes:
    """An MCAP file of ``records`` after its header; its footer points at the ``summary`` records, if any."""
    data = MCAP_MAGIC + mcap_header() + b"".join(records)
    start = len(data) if summary else 0
    footer = mcap_record(0x02, struct.pack("<QQI", start, 0, 0))
    return data + b"".join(summary) + footer + MCAP_MAGIC


def mcap_offset(*records: bytes) -> int:
    """Where the record after the magic, the header and ``records`` begins."""
    return len(MCAP_MAGIC) + len(mcap_header()) + sum(len(r) for r in records)


def zeros_zstd(n: int) -> bytes:
    """A zstd frame of ``n`` zero bytes, compressed a megabyte at a time (never holding ``n`` bytes)."""
    compressor = zstd.ZstdCompressor()
    block = bytes(min(n, MB))
    parts = [compressor.compress(block[:min(MB, n - i)]) for i in range(0, n, MB)]
    return b"".join(parts) + compressor.flush()


def rewrite_metadata(folder, edit) -> Path:
    """A ROS 2 bag folder's ``metadata.yaml`` rewritten as ``edit(text)`` gives it; the folder."""
    path = Path(folder) / "metadata.yaml"
    path.write_text(edit(path.read_text()))
    return Path(folder)
