"""What a ROS 2 bag would inflate, checked before ``rosbags`` reads it.

``rosbags`` decompresses without a limit: a whole MCAP chunk at once (every
chunk of a file without a summary as soon as it is opened), each message of
a ``.db3`` stored with ``compression_mode: message``, and a whole
``.db3.zstd`` or ``.mcap.zstd`` stored with ``compression_mode: file``
(into a temporary file). A few kilobytes of zstd can inflate to gigabytes,
and a chunk may state one size and hold another. So, before a ROS 2 bag is
handed to ``rosbags``, :func:`check_inflation` reads every compressed part
once, incrementally (``max_length``), never holding more than one cap of
inflated bytes, and refuses (:class:`~novelty.io.ros.caps.MessageError`, naming
the file, the part and the cap) a part beyond its cap or other than the size
it states:

- an MCAP chunk: its stated uncompressed size at most
  :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES`, its records inflating to exactly
  that size; every chunk index of the summary pointing at a chunk record
  checked so, with its sizes and compression (``rosbags`` reads a chunk
  where the index says);
- a message stored compressed: at most :data:`~novelty.io.ros.caps.MAX_MESSAGE_BYTES`;
- a file stored compressed: at most :data:`MAX_INFLATION` times its own
  size (and at least :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES` allowed), an
  MCAP inside it checked as above while it streams.

The check costs one more decompression of a compressed bag (an
uncompressed one is only walked record by record); a bag without
compression is not inflated at all.

One module although over 300 lines: the three places a ROS 2 bag can be
compressed share the one budgeted inflation, and each reader is a few
dozen lines of the formats' records.

References
----------
Foxglove, "MCAP format specification" (mcap.dev/spec): the magic, the
record framing (opcode u8, length u64) and the Chunk (0x06), Chunk Index
(0x08) and Footer (0x02) records. ROS 2 ``rosbag2`` metadata
(``compression_mode``: none, file, message; ``compression_format``: zstd).
"""

from __future__ import annotations

import functools
import re
import sqlite3
import struct
from contextlib import closing
from pathlib import Path

from ..ros import caps
from ..ros.caps import MessageError

__all__ = ["check_inflation", "MAX_INFLATION"]

#: How many times its own size a file stored compressed (``compression_mode: file``) may inflate to.
MAX_INFLATION = 100

MCAP_MAGIC = b"\x89MCAP0\r\n"
_FOOTER, _MESSAGE, _CHUNK, _CHUNK_INDEX = 0x02, 0x05, 0x06, 0x08
#: a message record's channel id (u16), sequence (u32), log and publish times (u64), before its data
_MESSAGE_HEADER = 22
_U32, _U64, _RECORD = struct.Struct("<I"), struct.Struct("<Q"), struct.Struct("<BQ")
_BLOCK = 2**20
_MODE = re.compile(r"^\s*compression_mode:\s*['\"]?(\w*)", re.M)


def check_inflation(path) -> None:
    """Refuse a ROS 2 bag (a ``.db3`` or ``.mcap`` file, or a bag folder) whose compressed parts inflate beyond the caps."""
    path = Path(path)
    mode = ""
    if path.is_dir():
        metadata = path / "metadata.yaml"
        found = _MODE.search(metadata.read_text(encoding="utf-8", errors="replace")) if metadata.exists() else None
        mode = found.group(1).lower() if found else ""
        files = sorted(p for p in path.iterdir() if p.name.endswith((".mcap", ".db3", ".mcap.zstd", ".db3.zstd")))
    else:
        files = [path]
    for file in files:
        if file.name.endswith(".zstd"):
            _check_compressed_file(file)
        elif file.suffix == ".mcap":
            with file.open("rb") as fh:
                _check_mcap(_Reader(fh, file, seekable=True), compressed_messages=mode == "message")
        elif file.suffix == ".db3" and mode == "message":
            _check_compressed_messages(file)


@functools.cache
def _zstd():
    # deferred: zstd comes with rosbags (the ros extra; the standard library's from Python 3.14)
    try:
        from compression import zstd
    except ImportError:
        from backports import zstd
    return zstd


@functools.cache
def _decompressor_class(compression: str):
    if compression == "zstd":
        return _zstd().ZstdDecompressor
    import lz4.frame   # deferred: lz4 comes with rosbags (the ros extra), needed only for an lz4 chunk

    return lz4.frame.LZ4FrameDecompressor


class _Reader:
    """A file's bytes read in order, by position, for the record walk (a stream can only skip forward)."""

    def __init__(self, fh, path: Path, seekable: bool):
        self.fh, self.path, self.seekable, self.position = fh, path, seekable, 0

    def read(self, n: int) -> bytes:
        data = self.fh.read(n)
        self.position += len(data)
        return data

    def skip(self, n: int) -> None:
        if self.seekable:
            self.fh.seek(n, 1)
            self.position += n
            return
        for _ in self.blocks(n):
            pass

    def blocks(self, n: int):
        """The next ``n`` bytes (or fewer, at the file's end), a block at a time."""
        while n > 0:
            data = self.read(min(n, _BLOCK))
            if not data:
                return
            n -= len(data)
            yield data

    def exactly(self, n: int, where: str) -> bytes:
        data = self.read(n)
        if len(data) < n:
            raise self.error(where, "the file ends inside it.")
        return data

    def string(self, where: str) -> str:
        n = _U32.unpack(self.exactly(4, where))[0]
        if n > caps.MAX_NAME:
            raise self.error(where, f"states a name of {n:,} bytes; at most {caps.MAX_NAME:,} are read.")
        return self.exactly(n, where).decode("utf-8", errors="replace")

    def error(self, part: str, text: str) -> MessageError:
        return MessageError(f"{self.path}, {part}: {text}")


def _check_mcap(reader: _Reader, compressed_messages: bool = False) -> None:
    """Walk an MCAP file's records; check every chunk, chunk index and (stored compressed) message."""
    if reader.read(len(MCAP_MAGIC)) != MCAP_MAGIC:
        return   # not MCAP: rosbags says so
    chunks = {}
    while True:
        start = reader.position
        framing = reader.read(_RECORD.size)
        if len(framing) < _RECORD.size:
            break   # truncated: rosbags says so
        opcode, length = _RECORD.unpack(framing)
        if opcode == _CHUNK:
            chunks[start] = _check_chunk(reader, start, length, compressed_messages)
        elif opcode == _CHUNK_INDEX:
            _check_chunk_index(reader, length, chunks)
        elif opcode == _MESSAGE and compressed_messages:
            where = f"MCAP message at byte {start:,}"
            if length > caps.MAX_MESSAGE_BYTES:
                raise reader.error(where, f"states {length:,} bytes; at most {caps.MAX_MESSAGE_BYTES:,} are read "
                                   "(novelty.io.ros.caps.MAX_MESSAGE_BYTES).")
            _check_message(reader.exactly(length, where)[_MESSAGE_HEADER:], f"{reader.path}, {where}")
        else:
            reader.skip(length)
            if opcode == _FOOTER:
                break


def _check_chunk(reader: _Reader, start: int, length: int, compressed_messages: bool) -> tuple[str, int, int]:
    """Check one chunk record (the framing read); its ``(compression, compressed size, uncompressed size)``."""
    end = reader.position + length
    where = f"MCAP chunk at byte {start:,}"
    head = reader.exactly(28, where)
    size = _U64.unpack_from(head, 16)[0]
    if size > caps.MAX_CHUNK_BYTES:
        raise reader.error(where, f"states {size:,} bytes uncompressed; at most {caps.MAX_CHUNK_BYTES:,} are "
                           "inflated (novelty.io.ros.caps.MAX_CHUNK_BYTES).")
    compression = reader.string(where)
    stored = _U64.unpack(reader.exactly(8, where))[0]
    if reader.position + stored > end:
        raise reader.error(where, f"states {stored:,} bytes of records where its record leaves "
                           f"{end - reader.position:,} (a corrupt file).")
    if compression not in ("", "zstd", "lz4"):
        raise reader.error(where, f"compression {compression!r}; MCAP's are zstd, lz4 and none.")
    blocks = reader.blocks(stored)
    try:
        inflated = _inflate(blocks, compression, size, keep=compressed_messages)
    except _Damaged as exc:
        raise reader.error(where, f"its {compression} data are damaged ({exc}).") from None
    if len(inflated) != size:
        raise reader.error(where, f"states {size:,} bytes uncompressed and inflates to "
                           f"{'more' if len(inflated) > size else f'{len(inflated):,}'} (a corrupt or hostile file).")
    for _ in blocks:   # what is left of the records past a bad size
        pass
    reader.skip(end - reader.position)
    if compressed_messages:
        _check_records(bytes(inflated), f"{reader.path}, {where}")
    return compression, stored, size


def _check_records(records: bytes, where: str) -> None:
    """Each message record among a chunk's inflated ``records``, stored compressed, within its cap."""
    i = 0
    while i + _RECORD.size <= len(records):
        opcode, length = _RECORD.unpack_from(records, i)
        i += _RECORD.size
        if opcode == _MESSAGE:
            _check_message(records[i + _MESSAGE_HEADER:i + length], where)
        i += length


def _check_message(data: bytes, where: str) -> None:
    """A message stored compressed (zstd) inflates to at most MAX_MESSAGE_BYTES (``where`` names it)."""
    cap = caps.MAX_MESSAGE_BYTES
    try:
        decompressor = _decompressor_class("zstd")()
        size = len(decompressor.decompress(data, max_length=cap + 1))
        if not decompressor.eof or decompressor.unused_data:   # more to come, or more frames: all counted
            size = len(_inflate(iter((data,)), "zstd", cap))
    except Exception as exc:   # zstd raises its own kinds for damaged data
        raise MessageError(f"{where}: a message's zstd data are damaged ({type(exc).__name__}: {exc}).") from None
    if size > cap:
        raise MessageError(f"{where}: a message inflates to more than {cap:,} bytes (novelty.io.ros.caps.MAX_MESSAGE_BYTES).")


class _Damaged(Exception):
    """Compressed data its decompressor refuses."""


class _Counted:
    """What a bounded inflation gives when its bytes are not kept: their number alone."""

    def __init__(self):
        self.n = 0

    def __iadd__(self, data: bytes):
        self.n += len(data)
        return self

    def __len__(self) -> int:
        return self.n


def _inflate(blocks, compression: str, size: int, keep: bool = False):
    """Inflate ``blocks`` of ``compression`` (frames one after another, all of them, as ``rosbags`` does).

    Stops once more than ``size`` bytes came out, so that it never holds
    more than ``size + 1``; gives the inflated bytes (``keep``) or an object
    whose ``len`` is their number.
    """
    out = bytearray() if keep else _Counted()
    if compression == "":
        for block in blocks:
            out += block[:size + 1 - len(out)]
        return out
    new = _decompressor_class(compression)
    decompressor, pending = new(), b""
    try:
        while len(out) <= size:
            if not pending:
                pending = next(blocks, b"")
                if not pending:
                    break
            if decompressor.eof:   # a next frame
                decompressor = new()
            out += decompressor.decompress(pending, max_length=size + 1 - len(out))
            while len(out) <= size and not decompressor.eof and not decompressor.needs_input:
                out += decompressor.decompress(b"", max_length=size + 1 - len(out))
            pending = decompressor.unused_data if decompressor.eof else b""
    except Exception as exc:   # zstd and lz4 raise their own kinds for damaged data
        raise _Damaged(f"{type(exc).__name__}: {exc}") from None
    return out


def _check_chunk_index(reader: _Reader, length: int, chunks: dict) -> None:
    """A chunk index must point at a checked chunk record, with its sizes and compression."""
    end = reader.position + length
    where = f"MCAP chunk index at byte {reader.position - _RECORD.size:,}"
    head = reader.exactly(32, where)
    offset = _U64.unpack_from(head, 16)[0]
    reader.skip(_U32.unpack(reader.exactly(4, where))[0] + 8)   # message index offsets, their length
    compression = reader.string(where)
    stored, size = struct.unpack("<QQ", reader.exactly(16, where))
    if chunks.get(offset) != (compression, stored, size):
        raise reader.error(where, f"points at byte {offset:,}, where no chunk of compression {compression!r}, "
                           f"{stored:,} bytes stored and {size:,} inflated begins (a corrupt or hostile file).")
    reader.skip(end - reader.position)


def _check_compressed_file(path: Path) -> None:
    """A file stored compressed inflates to at most MAX_INFLATION times its size; an MCAP inside is walked."""
    limit = max(caps.MAX_CHUNK_BYTES, MAX_INFLATION * path.stat().st_size)
    with path.open("rb") as raw, _zstd().open(raw, "rb") as fh:
        stream = _Bounded(fh, limit, path)
        if path.name.endswith(".mcap.zstd"):
            _check_mcap(_Reader(stream, path, seekable=False))
        while stream.read(_BLOCK):
            pass


class _Bounded:
    """A decompressing stream that refuses to give more than ``limit`` bytes."""

    def __init__(self, fh, limit: int, path: Path):
        self.fh, self.limit, self.path, self.total = fh, limit, path, 0

    def read(self, n: int) -> bytes:
        try:
            data = self.fh.read(min(n, self.limit + 1 - self.total))
        except Exception as exc:   # zstd raises its own kinds for damaged data
            raise MessageError(f"{self.path}: its zstd data are damaged ({type(exc).__name__}: {exc}).") from None
        self.total += len(data)
        if self.total > self.limit:
            raise MessageError(f"{self.path}: inflates to more than {self.limit:,} bytes, {MAX_INFLATION} times its "
                               "own size (novelty.io.ros2.inflation.MAX_INFLATION).")
        return data


def _check_compressed_messages(path: Path) -> None:
    """Each message of a ``.db3`` stored with ``compression_mode: message`` inflates to at most MAX_MESSAGE_BYTES."""
    with closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as db:
        try:
            topics = dict(db.execute("SELECT id, name FROM topics"))
            rows = db.execute("SELECT id, topic_id, data FROM messages")
        except sqlite3.DatabaseError:
            return   # not a rosbag2 database: rosbags says so
        for number, topic, data in rows:
            _check_message(data, f"{path}, topic {topics.get(topic, topic)}, message id {number}")
