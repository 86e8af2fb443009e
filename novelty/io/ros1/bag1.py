"""ROS 1 bags (format 2.0) read from their documented layout, every stated size checked before it is used.

``rosbags`` inflates a whole chunk as soon as one of its messages is asked
for, whatever size the chunk turns out to have: a 5 KB bz2 chunk can hold
hundreds of megabytes of zeros. This reader follows the format's
documentation instead (ROS wiki, "Bags/Format/2.0"):

- the bag header (op 3) gives the index's position; there the connection
  records (op 7: topic, type, message definition) and the chunk infos (op 6);
- each chunk record (op 5) states its compression (``none``, ``bz2``,
  ``lz4``) and its uncompressed ``size``, and is followed by one index
  record (op 4) a connection: the time and offset of each of its messages;
- a message record (op 2) states its length.

A chunk is inflated once, only as far as the messages read need, never
beyond the size it states nor beyond :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES`
(its messages due after another chunk's, where chunks' times interleave,
wait, at most :data:`~novelty.io.ros.caps.MAX_HELD_BYTES` of them); a
message's stated length must lie within its chunk and within the cap its
reader gives (a longer message's first bytes are read to name the field that
asks for too much), or the message is refused (:class:`~novelty.io.ros.caps.MessageError`, naming the file,
topic, message number and field) before it is inflated. Messages come in the
order of their record times (ties: the bag's order), as ``rosbags`` gives them.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from ..ros import caps
from ..ros.caps import MessageError, Where
from .chunks import Inflated, Limit

__all__ = ["Bag1", "Connection", "BagFormatError"]

MAGIC = b"#ROSBAG V2.0\n"
_BAG_HEADER, _INDEX, _CHUNK, _CHUNK_INFO, _CONNECTION = 3, 4, 5, 6, 7
#: The longest record header read (a connection's data, its message definition, is also a header block).
_MAX_HEADER = 4 * 2**20
_ENTRY = np.dtype([("sec", "<u4"), ("nsec", "<u4"), ("offset", "<u4")])
_U32, _U64 = struct.Struct("<I"), struct.Struct("<Q")


class BagFormatError(ValueError):
    """A file that does not follow the ROS 1 bag format where it is read."""


@dataclass(frozen=True)
class Connection:
    """A connection record: one publisher's topic, its message type (``package/msg/Type``) and definition."""

    id: int
    topic: str
    msgtype: str
    msgdef: str


class Bag1:
    """An open ROS 1 bag: its connections and topics; :meth:`messages` reads them."""

    def __init__(self, path):
        self.path = Path(path)
        self._fh = open(self.path, "rb")
        try:
            self._size = self.path.stat().st_size
            self._read_index()
        except BaseException:
            self._fh.close()
            raise

    def close(self) -> None:
        self._fh.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    # -------------------------------------------------------------- the index
    def _fail(self, text: str) -> BagFormatError:
        return BagFormatError(f"{self.path} is not a readable bag (ROS 1, format 2.0): {text}.")

    def _read_index(self) -> None:
        if self._fh.read(len(MAGIC)) != MAGIC:
            raise self._fail("it does not start with #ROSBAG V2.0")
        header = self._record(self._fh.tell(), _BAG_HEADER)[0]
        index_pos = self._u64(header, "index_pos")
        n_connections, n_chunks = self._u32(header, "conn_count"), self._u32(header, "chunk_count")
        if index_pos == 0:
            raise self._fail("it has no index (reindex it with 'rosbag reindex')")
        if index_pos > self._size:
            raise self._fail(f"its index is stated at byte {index_pos:,}, beyond its end (a truncated bag?)")
        self.connections: dict[int, Connection] = {}
        self.chunk_infos: list[tuple[int, dict[int, int]]] = []
        position = index_pos
        for _ in range(n_connections):
            header, data, data_pos, data_len = self._record(position, _CONNECTION, with_data=True)
            position = data_pos + data_len
            fields = self._fields(data)
            topic = header.get(b"topic", b"").decode("utf-8", "replace")
            connection = Connection(self._u32(header, "conn"), _topic_name(topic),
                                    _type_name(fields.get(b"type", b"").decode("ascii", "replace")),
                                    fields.get(b"message_definition", b"").decode("utf-8", "replace"))
            self.connections[connection.id] = connection
        for _ in range(n_chunks):
            header, data, data_pos, data_len = self._record(position, _CHUNK_INFO, with_data=True)
            position = data_pos + data_len
            count = self._u32(header, "count")
            if len(data) != 8 * count:
                raise self._fail(f"a chunk info lists {count} connections in {len(data)} bytes")
            pairs = np.frombuffer(data, "<u4").reshape(-1, 2)
            self.chunk_infos.append((self._u64(header, "chunk_pos"), dict(pairs.tolist())))

    def _record(self, position: int, op: int, with_data: bool = False):
        """The header fields of the record at ``position``, its data (or None) and where the data lies."""
        self._fh.seek(position)
        header_len = self._read_u32()
        if header_len > min(_MAX_HEADER, self._size - position):
            raise self._fail(f"a record at byte {position} states a {header_len:,}-byte header")
        header = self._fields(self._fh.read(header_len))
        if header.get(b"op") != bytes([op]):
            raise self._fail(f"expected a record of op {op} at byte {position}, found op {header.get(b'op')!r}")
        data_len = self._read_u32()
        data_pos = position + 8 + header_len
        if data_len > self._size - data_pos:
            raise self._fail(f"a record at byte {position} states {data_len:,} bytes of data beyond the file's end")
        if with_data and data_len > _MAX_HEADER:
            raise self._fail(f"a record at byte {position} states {data_len:,} bytes of index data")
        data = self._fh.read(data_len) if with_data else None
        return header, data, data_pos, data_len

    def _read_u32(self) -> int:
        raw = self._fh.read(4)
        if len(raw) != 4:
            raise self._fail("it ends inside a record")
        return _U32.unpack(raw)[0]

    def _fields(self, buf: bytes) -> dict[bytes, bytes]:
        fields, i = {}, 0
        while i < len(buf):
            if i + 4 > len(buf):
                raise self._fail("a record header ends inside a field's length")
            (n,) = _U32.unpack_from(buf, i)
            if i + 4 + n > len(buf):
                raise self._fail("a record header's field runs past the header")
            name, _, value = bytes(buf[i + 4:i + 4 + n]).partition(b"=")
            fields[name] = value
            i += 4 + n
        return fields

    def _u32(self, header: dict, name: str) -> int:
        return self._number(header, name, _U32)

    def _u64(self, header: dict, name: str) -> int:
        return self._number(header, name, _U64)

    def _number(self, header: dict, name: str, kind: struct.Struct) -> int:
        value = header.get(name.encode())
        if value is None or len(value) != kind.size:
            raise self._fail(f"a record's field {name} is missing or not {kind.size} bytes")
        return kind.unpack(value)[0]

    # -------------------------------------------------------------- topics
    @property
    def topics(self) -> dict[str, str]:
        """Every topic with its message type."""
        return {c.topic: c.msgtype for c in sorted(self.connections.values(), key=lambda c: c.topic)}

    def count(self, topic: str) -> int:
        """How many messages ``topic`` holds, from the index."""
        ids = {c.id for c in self.connections.values() if c.topic == topic}
        return sum(n for _, counts in self.chunk_infos for conn, n in counts.items() if conn in ids)

    # -------------------------------------------------------------- messages
    def messages(self, topics, limits: dict[str, Limit]) -> Iterator[tuple[Connection, int, int, bytes]]:
        """``(connection, time_ns, number, data)`` of each message of ``topics``, in time order.

        ``number`` counts the topic's messages from 1; ``limits[topic]``
        bounds a message's length (see :data:`Limit`). Each chunk is
        inflated once: when its first message is due, the messages read of
        it are taken out together, and those due after another chunk's are
        held until then, at most :data:`~novelty.io.ros.caps.MAX_HELD_BYTES`.
        """
        wanted = {c.id for c in self.connections.values() if c.topic in topics}
        entries, chunks = self._entries(wanted)
        held = _Held(self, entries, chunks, limits)
        for i in range(len(entries["time"])):
            where = held.where(i)
            yield self.connections[int(entries["conn"][i])], int(entries["time"][i]), where.number, held.take(i, where)

    def _entries(self, wanted: set[int]):
        """The index of the wanted connections' messages, sorted by time, with each record's room."""
        parts, chunks = [], []
        for info_pos, counts in sorted(self.chunk_infos):
            if not wanted & set(counts):
                continue
            header, _, data_pos, data_len = self._record(info_pos, _CHUNK)
            compression = header.get(b"compression", b"none").decode("ascii", "replace")
            size = self._u32(header, "size")
            chunks.append((data_pos, data_len, compression, size))
            offsets, mine, position = [], [], data_pos + data_len
            for _ in range(len(counts)):
                index_header, data, index_pos, index_len = self._record(position, _INDEX, with_data=True)
                position = index_pos + index_len
                conn, count = self._u32(index_header, "conn"), self._u32(index_header, "count")
                if len(data) != 12 * count:
                    raise self._fail(f"an index record lists {count} messages in {len(data)} bytes")
                rows = np.frombuffer(data, _ENTRY)
                offsets.append(rows["offset"])
                if conn in wanted:
                    mine.append((conn, rows))
            ends = np.unique(np.concatenate(offsets + [np.array([size], "<u4")]).astype(np.int64))
            for conn, rows in mine:
                offset = rows["offset"].astype(np.int64)
                nxt = ends[np.minimum(np.searchsorted(ends, offset, side="right"), len(ends) - 1)]
                parts.append(dict(time=rows["sec"].astype(np.int64) * 10**9 + rows["nsec"], offset=offset,
                                  chunk=np.full(len(rows), len(chunks) - 1), conn=np.full(len(rows), conn),
                                  extent=np.where(offset < size, nxt - offset, 0)))
        if not parts:
            return {k: np.zeros(0, np.int64) for k in ("time", "chunk", "offset", "conn", "extent")}, chunks
        entries = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
        order = np.lexsort((entries["offset"], entries["chunk"], entries["time"]))
        return {k: v[order] for k, v in entries.items()}, chunks


class _Held:
    """The messages of the chunks inflated so far that are not yet due, each chunk inflated once.

    A message's data, or the error reading it gave, waits here from its
    chunk's inflation until its turn; the bytes waiting are at most
    :data:`~novelty.io.ros.caps.MAX_HELD_BYTES`.
    """

    def __init__(self, bag: Bag1, entries: dict, chunks: list, limits: dict):
        self.bag, self.entries, self.chunks, self.limits = bag, entries, chunks, limits
        # each message's number on its topic, counted in time order
        self.topic_of = {c: bag.connections[c].topic for c in np.unique(entries["conn"]).tolist()}
        self.numbers = np.zeros(len(entries["conn"]), np.int64)
        for topic in set(self.topic_of.values()):
            mine = np.isin(entries["conn"], [c for c, t in self.topic_of.items() if t == topic])
            self.numbers[mine] = np.arange(1, int(mine.sum()) + 1)
        # each chunk's messages, by their place in it
        order = np.lexsort((entries["offset"], entries["chunk"]))
        bounds = np.searchsorted(entries["chunk"][order], np.arange(len(chunks) + 1))
        self.in_chunk = {k: order[bounds[k]:bounds[k + 1]] for k in range(len(chunks))}
        self.waiting: dict[int, bytes | MessageError] = {}
        self.bytes = 0

    def where(self, i: int) -> Where:
        return Where(self.bag.path, self.topic_of[int(self.entries["conn"][i])], int(self.numbers[i]))

    def take(self, i: int, where: Where) -> bytes:
        """Message ``i``'s data (its chunk inflated if it was not yet), or the error reading it gave."""
        if i not in self.waiting:
            self._inflate(int(self.entries["chunk"][i]), where)
        data = self.waiting.pop(i)
        if isinstance(data, MessageError):
            raise data
        self.bytes -= len(data)
        return data

    def _inflate(self, chunk: int, due: Where) -> None:
        """Take out the messages read of ``chunk`` (``due``: the message whose turn it is)."""
        inflated = Inflated(self.bag._fh, *self.chunks[chunk], due)
        offsets, extents = self.entries["offset"], self.entries["extent"]
        for j in self.in_chunk.pop(chunk).tolist():
            where = self.where(j)
            try:
                data = inflated.message(int(offsets[j]), int(extents[j]), self.limits[where.topic], where)
            except MessageError as exc:
                self.waiting[j] = exc
                continue
            self.waiting[j] = data
            self.bytes += len(data)
            if self.bytes > caps.MAX_HELD_BYTES:
                raise where.error("chunk", f"more than {caps.MAX_HELD_BYTES:,} bytes of messages would wait for "
                                  "their turn, their chunks' times interleaving so (novelty.io.ros.caps.MAX_HELD_BYTES).")


def _topic_name(name: str) -> str:
    """A topic's name without repeated or trailing slashes, as ``rosbags`` gives it."""
    return "/" * name.startswith("/") + "/".join(part for part in name.split("/") if part)


def _type_name(name: str) -> str:
    """A ROS 1 type name (``sensor_msgs/LaserScan``) in ROS 2's form (``sensor_msgs/msg/LaserScan``)."""
    parts = name.split("/")
    return name if len(parts) != 2 else f"{parts[0]}/msg/{parts[1]}"
