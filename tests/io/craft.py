"""ROS 1 bags written byte by byte from the format's documentation, to craft what no writer would write.

A bag of one chunk: its records (a connection record, then message records)
are given as parts, each bytes or :class:`Zeros` (so that a chunk can hold
hundreds of megabytes of zeros without their being made: bz2 compresses each
run of zeros on its own, and a bz2 chunk is the concatenation of its parts'
streams). ``size`` and ``offsets`` can be stated falsely.
"""

import bz2
import functools
import struct

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
    conn_fields = header(topic=topic.encode(), type=msgtype.encode(), md5sum=MD5[msgtype].encode(),
                         message_definition=msgdef.encode())
    connection = record(header(op=b"\x07", conn=u32(0), topic=topic.encode()), conn_fields)
    parts, true_offsets, position = list(connection), [], _length(connection)
    for time_ns, data in messages:
        true_offsets.append(position)
        rec = record(header(op=b"\x02", conn=u32(0), time=time_bytes(time_ns)), data)
        parts += rec
        position += _length(rec)
    offsets = true_offsets if offsets is None else offsets
    payload = _compress(parts, compression)
    chunk = record(header(op=b"\x05", compression=compression.encode(), size=u32(position if size is None else size)),
                   payload)
    index = record(header(op=b"\x04", ver=u32(1), conn=u32(0), count=u32(len(messages))),
                   b"".join(time_bytes(t) + u32(o) for (t, _), o in zip(messages, offsets)))
    start = len(b"#ROSBAG V2.0\n") + 8 + 4096   # the bag header record, padded to 4 KB
    body = b"".join(_flat(chunk) + _flat(index))
    index_pos = start + len(body)
    times = [t for t, _ in messages] or [0]
    info = record(header(op=b"\x06", ver=u32(1), chunk_pos=struct.pack("<Q", start), start_time=time_bytes(min(times)),
                         end_time=time_bytes(max(times)), count=u32(1)), u32(0) + u32(len(messages)))
    bag_header_fields = header(op=b"\x03", index_pos=struct.pack("<Q", index_pos), conn_count=u32(1),
                               chunk_count=u32(1))
    padding = 4096 - len(bag_header_fields)
    head = b"#ROSBAG V2.0\n" + U32.pack(len(bag_header_fields)) + bag_header_fields + U32.pack(padding) + b" " * padding
    assert len(head) == start
    with open(path, "wb") as fh:
        fh.write(head + body + b"".join(_flat(connection_index(topic, msgtype, msgdef))) + b"".join(_flat(info)))
    return path


def connection_index(topic, msgtype, msgdef):
    fields = header(topic=topic.encode(), type=msgtype.encode(), md5sum=MD5[msgtype].encode(), message_definition=msgdef.encode())
    return record(header(op=b"\x07", conn=u32(0), topic=topic.encode()), fields)


def _length(parts) -> int:
    return sum(p.n if isinstance(p, Zeros) else len(p) for p in parts)


def _flat(parts) -> list:
    return [bytes(p.n) if isinstance(p, Zeros) else p for p in parts]
