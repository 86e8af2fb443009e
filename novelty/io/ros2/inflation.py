"""What a ROS 2 bag would inflate, checked before ``rosbags`` inflates it, from what ``rosbags`` reads it by.

``rosbags`` decompresses without a limit: a whole MCAP chunk at once, each
message of a bag stored with ``compression_mode: message`` as it is read, and
each file of a bag stored with ``compression_mode: file`` (into a temporary
file). A few kilobytes of zstd can inflate to gigabytes, and a chunk may
state one size and hold another. So a bag's compressed parts are checked
first (:class:`StoredBag`), found as ``rosbags`` finds them, each inflated
incrementally (``max_length``), never holding more than one cap of inflated
bytes, and refused (:class:`~novelty.io.ros.caps.MessageError`, naming the file,
the part and the cap) beyond its cap or other than the size it states:

- **the folder's metadata**: ``metadata.yaml`` read as YAML, as ``rosbags``
  reads it (its ``compression_mode``, its ``storage_identifier``, its
  ``relative_file_paths``); every file it lists is checked as its storage
  and compression say, whatever the file's name;
- **an MCAP file** is walked record by record from its header to its
  footer: a record reaching past the file's end, a footer anywhere but at
  the end, or a summary offset where no record begins is refused (``rosbags``
  reads the summary where the footer says, and scans the data section past
  any opcode); every chunk's stated uncompressed size is at most
  :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES` and its records inflate to
  exactly that size; every chunk index points at a checked chunk, with its
  sizes and compression (``rosbags`` reads a chunk where the index says);
- **a message stored compressed** inflates to at most
  :data:`~novelty.io.ros.caps.MAX_MESSAGE_BYTES`; only the topics read are
  checked, when they are read (:meth:`StoredBag.check_messages`);
- **a file stored compressed** is streamed through its decompressor, an
  MCAP inside it walked as above as it streams.

All the parts of one file inflate to at most :data:`MAX_INFLATION` times the
file's own size (and at least :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES` are
allowed), so that the checks, and ``rosbags`` after them, take a time
bounded by the file's size. A bag without compression is only walked.

One module although over 300 lines: the three places a ROS 2 bag can be
compressed share the one budgeted inflation, and each reader is a few
dozen lines of the formats' records.

References
----------
Foxglove, "MCAP format specification" (mcap.dev/spec): the magic, the
record framing (opcode u8, length u64), the Header (0x01), Footer (0x02),
Channel (0x04), Message (0x05), Chunk (0x06) and Chunk Index (0x08)
records, the summary section and the footer's summary offset. ROS 2
``rosbag2`` metadata (``compression_mode``: none, file, message;
``compression_format``: zstd; ``storage_identifier``: sqlite3, mcap).
"""

from __future__ import annotations

import functools
import sqlite3
import struct
from contextlib import closing
from pathlib import Path, PurePath
from typing import Callable, Sequence

from ..ros import caps
from ..ros.caps import MessageError

__all__ = ["StoredBag", "check_inflation", "MAX_INFLATION"]

#: How many times its own size the compressed parts of one file of a bag may inflate to, all together.
MAX_INFLATION = 100

MCAP_MAGIC = b"\x89MCAP0\r\n"
_HEADER, _FOOTER, _CHANNEL, _MESSAGE, _CHUNK, _CHUNK_INDEX = 0x01, 0x02, 0x04, 0x05, 0x06, 0x08
#: a message record's channel id (u16), sequence (u32), log and publish times (u64), before its data
_MESSAGE_HEADER = 22
#: the footer's content: the summary's offset (u64), the summary offsets' offset (u64), a crc (u32)
_FOOTER_LENGTH = 20
#: the footer record and the magic after it: the last bytes of a file, where rosbags reads them
_FOOTER_SIZE = 9 + _FOOTER_LENGTH + len(MCAP_MAGIC)
_LAST = bytes([_FOOTER]) + struct.pack("<Q", _FOOTER_LENGTH)
#: the longest channel record whose topic is read (its id, its schema's, its topic, its encoding, metadata)
_MAX_CHANNEL = 16 * caps.MAX_NAME
_U16, _U32, _U64, _RECORD = struct.Struct("<H"), struct.Struct("<I"), struct.Struct("<Q"), struct.Struct("<BQ")
_BLOCK = 2**20
#: what ``rosbags`` raises for metadata it refuses (before it inflates anything)
_REFUSED = (OSError, UnicodeDecodeError, KeyError, TypeError, AttributeError, ValueError)


class StoredBag:
    """A ROS 2 bag as ``rosbags`` will read it: its files, their storage, and how they are compressed.

    :meth:`check_storage` checks what opening the bag inflates (MCAP chunks,
    files stored compressed), :meth:`check_messages` the messages stored
    compressed of the topics about to be read.

    Attributes
    ----------
    mode : str
        ``"file"``, ``"message"`` or ``""`` (none).
    storage : str
        ``"mcap"`` or ``"sqlite3"``.
    files : list of Path
        The storage files, as the metadata lists them (or the one file given).
    """

    def __init__(self, path):
        path = Path(path)
        self.mode, self.storage, self.files = "", "mcap" if path.suffix == ".mcap" else "sqlite3", [path]
        if path.is_dir():
            self.mode, self.storage, self.files = _listing(path) or ("", "", [])
        self._channels: dict[Path, dict[int, set[str]]] = {}

    def check_storage(self) -> None:
        """Refuse a chunk or a file stored compressed beyond its cap (see the module docstring)."""
        for file in self.files:
            budget = _Budget(file)
            if self.mode == "file":
                _check_compressed_file(file, self.storage, budget)
            elif self.storage == "mcap":
                with file.open("rb") as fh:
                    walk = _McapWalk(_Reader(fh, file, file.stat().st_size), budget, self.mode == "message")
                    self._channels[file] = walk.run()

    def check_messages(self, topics: Sequence[str] | None = None) -> None:
        """Refuse a message of ``topics`` (None: of every topic) stored compressed beyond its cap, or all of
        them together beyond the file's budget; nothing to do unless the bag's messages are compressed."""
        if self.mode != "message":
            return
        for file in self.files:
            budget = _Budget(file)
            if self.storage == "sqlite3":
                _check_db3_messages(file, topics, budget)
                continue
            if file not in self._channels:   # the channels are gathered as the storage is checked
                self.check_storage()
            read = {k for k, names in self._channels[file].items() if topics is None or names & set(topics)}
            if read:
                messages = _MessageCheck(file, self._channels[file], read, budget)
                with file.open("rb") as fh:
                    _McapWalk(_Reader(fh, file, file.stat().st_size), budget, True, messages.check).run()


def check_inflation(path) -> None:
    """Refuse a ROS 2 bag (a ``.db3`` or ``.mcap`` file, or a bag folder) whose compressed parts, messages of
    every topic included, inflate beyond the caps (:class:`StoredBag`)."""
    bag = StoredBag(path)
    bag.check_storage()
    bag.check_messages()


def _listing(folder: Path) -> tuple[str, str, list[Path]] | None:
    """``(mode, storage, files)`` of a bag folder, read as ``rosbags`` reads its ``metadata.yaml``; None for
    metadata ``rosbags`` refuses (which it does before inflating anything)."""
    from ruamel.yaml import YAML   # deferred: comes with rosbags (the ros extra)
    from ruamel.yaml.error import YAMLError

    try:
        info = YAML(typ="safe").load((folder / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
        files = [folder / PurePath(name).name for name in info["relative_file_paths"]]
        mode = info.get("compression_mode", "").lower()
        storage = info["storage_identifier"]
        compression = info.get("compression_format", None) or None
    except (*_REFUSED, YAMLError):
        return None
    mode = "" if mode == "none" else mode
    if storage not in ("mcap", "sqlite3") or (mode and compression != "zstd") or not all(f.exists() for f in files):
        return None
    return mode, storage, files


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


class _Budget:
    """The bytes one file's compressed parts may inflate to in all: MAX_INFLATION times its size."""

    def __init__(self, path: Path):
        self.path, self.total = path, 0
        self.limit = max(caps.MAX_CHUNK_BYTES, MAX_INFLATION * path.stat().st_size)

    @property
    def left(self) -> int:
        return self.limit - self.total

    def spend(self, n: int, what: str = "inflates") -> None:
        """Count ``n`` more inflated bytes; beyond the limit, the error saying ``what`` inflates."""
        self.total += n
        if self.total > self.limit:
            whose = "its own" if what == "inflates" else "the file's"
            raise MessageError(f"{self.path}: {what} to more than {self.limit:,} bytes, {MAX_INFLATION} times "
                               f"{whose} size (novelty.io.ros2.inflation.MAX_INFLATION).")


class _Reader:
    """A file's bytes read in order, by position (``size`` None: a stream, of an unknown size, read forward)."""

    def __init__(self, fh, path: Path, size: int | None):
        self.fh, self.path, self.size, self.position = fh, path, size, 0
        self.tail = b""   # a stream's last bytes read

    def read(self, n: int) -> bytes:
        data = self.fh.read(n)
        self.position += len(data)
        if self.size is None and data:
            self.tail = (self.tail + data[-_FOOTER_SIZE:])[-_FOOTER_SIZE:]
        return data

    def last(self, n: int) -> bytes:
        """The file's last ``n`` bytes but the magic (a footer record's framing, where ``rosbags`` reads one)."""
        if self.size is not None:
            if self.size < n:
                return b""
            self.fh.seek(self.size - n)
            data = self.fh.read(n)
        else:
            data = self.tail
        return data[:len(_LAST)] if data[-len(MCAP_MAGIC):] == MCAP_MAGIC else b""

    def skip(self, n: int, where: str) -> None:
        """Pass over the next ``n`` bytes, which must lie in the file."""
        if self.size is not None:
            self.fh.seek(n, 1)
            self.position += n
            return
        for _ in self.blocks(n, where):
            pass

    def blocks(self, n: int, where: str):
        """The next ``n`` bytes, a block at a time; the error naming ``where`` if the file ends first."""
        while n > 0:
            data = self.read(min(n, _BLOCK))
            if not data:
                raise self.error(where, "the file ends inside it (a truncated or corrupt file).")
            n -= len(data)
            yield data

    def exactly(self, n: int, where: str) -> bytes:
        data = self.read(n)
        if len(data) < n:
            raise self.error(where, "the file ends inside it (a truncated or corrupt file).")
        return data

    def string(self, where: str) -> str:
        n = _U32.unpack(self.exactly(4, where))[0]
        if n > caps.MAX_NAME:
            raise self.error(where, f"states a name of {n:,} bytes; at most {caps.MAX_NAME:,} are read.")
        return self.exactly(n, where).decode("utf-8", errors="replace")

    def error(self, part: str, text: str) -> MessageError:
        return MessageError(f"{self.path}, {part}: {text}")


class _McapWalk:
    """An MCAP file's records from its header to its footer, each checked (see the module docstring).

    ``channels``: the channels' topics are gathered (records in chunks too);
    ``on_message(channel, data)`` is called with each message record's
    channel and stored data.
    """

    def __init__(self, reader: _Reader, budget: _Budget, channels: bool = False,
                 on_message: Callable[[int, bytes], None] | None = None):
        self.reader, self.budget, self.on_message = reader, budget, on_message
        self.keep = channels or on_message is not None
        self.channels: dict[int, set[str]] = {}
        self.chunks: dict[int, tuple[str, int, int]] = {}
        self.indexes: list[tuple[int, int, tuple[str, int, int]]] = []
        self.starts: set[int] = set()

    def run(self) -> dict[int, set[str]]:
        """Walk the file; its channels' topics (``{channel id: topics}``), when gathered."""
        reader = self.reader
        if reader.read(len(MCAP_MAGIC)) != MCAP_MAGIC:
            return {}   # not MCAP: rosbags says so
        framing = reader.read(_RECORD.size)
        if len(framing) < _RECORD.size or framing[0] != _HEADER:
            return {}   # rosbags refuses a file that does not start with its header
        self._within(0, len(MCAP_MAGIC), _RECORD.unpack(framing)[1], "header")
        reader.skip(_RECORD.unpack(framing)[1], f"MCAP header at byte {len(MCAP_MAGIC)}")
        while self._record():
            pass
        for at, offset, described in self.indexes:
            if self.chunks.get(offset) != described:
                compression, stored, size = described
                raise reader.error(f"MCAP chunk index at byte {at:,}", f"points at byte {offset:,}, where no chunk of "
                                   f"compression {compression!r}, {stored:,} bytes stored and {size:,} inflated "
                                   "begins (a corrupt or hostile file).")
        return self.channels

    def _within(self, opcode: int, start: int, length: int, name: str = "") -> None:
        """Refuse a record that reaches past the file's end (a stream's end is met as it is read)."""
        size = self.reader.size
        if size is not None and start + _RECORD.size + length > size:
            raise self.reader.error(f"MCAP {name or f'record of opcode 0x{opcode:02x}'} at byte {start:,}",
                                    f"states {length:,} bytes, past the file's end at byte {size:,} (a corrupt or "
                                    "hostile file).")

    def _record(self) -> bool:
        """Check the next record; False after the footer (or at a file's end without one)."""
        reader = self.reader
        start = reader.position
        self.starts.add(start)
        framing = reader.read(_RECORD.size)
        if not framing:
            if reader.last(_FOOTER_SIZE) == _LAST:   # a footer inside a record: rosbags reads one there
                raise reader.error(f"MCAP record at byte {start:,}", "the file ends without a footer record, its "
                                   "last bytes a footer's inside another record (a corrupt or hostile file).")
            return False   # no footer: rosbags refuses the file
        if len(framing) < _RECORD.size:
            raise reader.error(f"MCAP record at byte {start:,}", "the file ends inside it (a truncated or corrupt "
                               "file).")
        opcode, length = _RECORD.unpack(framing)
        self._within(opcode, start, length)
        where = f"MCAP {_NAMES.get(opcode, f'record of opcode 0x{opcode:02x}')} at byte {start:,}"
        if opcode == _FOOTER:
            self._footer(start, length, where)
            return False
        if opcode == _CHUNK:
            self.chunks[start] = self._chunk(length, where)
        elif opcode == _CHUNK_INDEX:
            self.indexes.append((start, *self._chunk_index(length, where)))
        elif opcode == _CHANNEL and self.keep and length <= _MAX_CHANNEL:
            self._channel(reader.exactly(length, where), where)
        elif opcode == _MESSAGE and self.on_message is not None:
            if length > caps.MAX_MESSAGE_BYTES:
                raise reader.error(where, f"states {length:,} bytes; at most {caps.MAX_MESSAGE_BYTES:,} are read "
                                   "(novelty.io.ros.caps.MAX_MESSAGE_BYTES).")
            self._message(reader.exactly(length, where), where)
        else:
            reader.skip(length, where)
        return True

    def _footer(self, start: int, length: int, where: str) -> None:
        """The footer: the last record, followed by the magic alone; its summary offset where a record begins."""
        reader = self.reader
        content = reader.read(length) if length == _FOOTER_LENGTH else b""
        end = reader.read(len(MCAP_MAGIC) + 1)
        if len(content) != _FOOTER_LENGTH or end != MCAP_MAGIC:
            raise reader.error(where, "before the file's end (a footer ends it; a corrupt or hostile file).")
        summary = _U64.unpack_from(content)[0]
        if summary and summary not in self.starts:
            raise reader.error(where, f"states the summary at byte {summary:,}, where no record begins (a corrupt "
                               "or hostile file).")

    def _chunk(self, length: int, where: str) -> tuple[str, int, int]:
        """Check one chunk record (its framing read); its ``(compression, stored size, uncompressed size)``."""
        reader = self.reader
        end = reader.position + length
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
        self.budget.spend(size, "its chunks inflate")
        blocks = reader.blocks(stored, where)
        try:
            inflated = _inflate(blocks, compression, size, keep=self.keep)
        except _Damaged as exc:
            raise reader.error(where, f"its {compression} data are damaged ({exc}).") from None
        if len(inflated) != size:
            raise reader.error(where, f"states {size:,} bytes uncompressed and inflates to "
                               f"{'more' if len(inflated) > size else f'{len(inflated):,}'} (a corrupt or hostile "
                               "file).")
        for _ in blocks:   # what is left of the records past a bad size
            pass
        reader.skip(end - reader.position, where)
        if self.keep:
            self._records(bytes(inflated), where)
        return compression, stored, size

    def _records(self, records: bytes, where: str) -> None:
        """The channel and message records among a chunk's inflated ``records``."""
        i = 0
        while i + _RECORD.size <= len(records):
            opcode, length = _RECORD.unpack_from(records, i)
            i += _RECORD.size
            if opcode == _CHANNEL:
                self._channel(records[i:i + length], where)
            elif opcode == _MESSAGE and self.on_message is not None:
                self._message(records[i:i + length], where)
            i += length

    def _channel(self, content: bytes, where: str) -> None:
        if len(content) >= 8:
            channel, n = _U16.unpack_from(content)[0], _U32.unpack_from(content, 4)[0]
            self.channels.setdefault(channel, set()).add(content[8:8 + n].decode("utf-8", errors="replace"))

    def _message(self, content: bytes, where: str) -> None:
        if len(content) >= _MESSAGE_HEADER:
            self.on_message(_U16.unpack_from(content)[0], content[_MESSAGE_HEADER:])

    def _chunk_index(self, length: int, where: str) -> tuple[int, tuple[str, int, int]]:
        """A chunk index's ``(chunk offset, (compression, stored size, uncompressed size))``."""
        reader = self.reader
        end = reader.position + length
        head = reader.exactly(32, where)
        offsets = _U32.unpack(reader.exactly(4, where))[0]
        reader.skip(min(offsets, end - reader.position), where)   # message index offsets
        reader.exactly(8, where)   # their length
        compression = reader.string(where)
        stored, size = struct.unpack("<QQ", reader.exactly(16, where))
        if reader.position > end:
            raise reader.error(where, "its fields run past its record (a corrupt file).")
        reader.skip(end - reader.position, where)
        return _U64.unpack_from(head, 16)[0], (compression, stored, size)


_NAMES = {_HEADER: "header", _FOOTER: "footer", _CHANNEL: "channel", _MESSAGE: "message", _CHUNK: "chunk",
          _CHUNK_INDEX: "chunk index"}


class _MessageCheck:
    """Each message of the channels read, stored compressed, within its cap and the file's budget."""

    def __init__(self, path: Path, channels: dict[int, set[str]], read: set[int], budget: _Budget):
        self.path, self.read, self.budget = path, read, budget
        self.topics = {k: " or ".join(sorted(channels[k])) for k in read}
        self.numbers = dict.fromkeys(read, 0)

    def check(self, channel: int, data: bytes) -> None:
        if channel not in self.read:
            return
        self.numbers[channel] += 1
        where = f"{self.path}, topic {self.topics[channel]}, message {self.numbers[channel]}"
        self.budget.spend(_message_size(data, where, self.budget.left),
                          f"the messages of {', '.join(sorted(set(self.topics.values())))} inflate")


def _message_size(data: bytes, where: str, left: int) -> int:
    """The bytes a message stored compressed (zstd) inflates to, within MAX_MESSAGE_BYTES (``where`` names
    it); inflated at most ``left + 1`` bytes far (the file's budget tells when it is more)."""
    cap = caps.MAX_MESSAGE_BYTES
    try:
        size = len(_inflate(iter((data,)), "zstd", min(cap, max(left, 0))))
    except _Damaged as exc:
        raise MessageError(f"{where}: a message's zstd data are damaged ({exc}).") from None
    if size > cap:
        raise MessageError(f"{where}: a message inflates to more than {cap:,} bytes (novelty.io.ros.caps.MAX_MESSAGE_BYTES).")
    return size


def _check_db3_messages(path: Path, topics: Sequence[str] | None, budget: _Budget) -> None:
    """Each message of ``topics`` in a ``.db3`` stored with ``compression_mode: message`` within its cap."""
    with closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as db:
        try:
            names = dict(db.execute("SELECT id, name FROM topics"))
            ids = [k for k, name in names.items() if topics is None or name in topics]
            rows = db.execute(f"SELECT id, topic_id, data FROM messages WHERE topic_id IN ({','.join('?' * len(ids))}) "
                              "ORDER BY id", ids)
        except sqlite3.DatabaseError:
            return   # not a rosbag2 database: rosbags says so
        what = f"the messages of {', '.join(sorted({names[k] for k in ids}))} inflate"
        for number, topic, data in rows:
            where = f"{path}, topic {names.get(topic, topic)}, message id {number}"
            budget.spend(_message_size(data, where, budget.left), what)


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
    whose ``len`` is their number (inflated a block at a time, never held).
    """
    out = bytearray() if keep else _Counted()
    step = size + 1 if keep else _BLOCK
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
            out += decompressor.decompress(pending, max_length=min(step, size + 1 - len(out)))
            while len(out) <= size and not decompressor.eof and not decompressor.needs_input:
                out += decompressor.decompress(b"", max_length=min(step, size + 1 - len(out)))
            pending = decompressor.unused_data if decompressor.eof else b""
    except Exception as exc:   # zstd and lz4 raise their own kinds for damaged data
        raise _Damaged(f"{type(exc).__name__}: {exc}") from None
    return out


def _check_compressed_file(path: Path, storage: str, budget: _Budget) -> None:
    """A file stored compressed inflates within its budget; an MCAP inside it is walked as it streams."""
    with path.open("rb") as raw, _zstd().open(raw, "rb") as fh:
        stream = _Bounded(fh, budget, path)
        if storage == "mcap":
            _McapWalk(_Reader(stream, path, None), budget).run()
        while stream.read(_BLOCK):
            pass


class _Bounded:
    """A decompressing stream that counts what it gives against the file's budget."""

    def __init__(self, fh, budget: _Budget, path: Path):
        self.fh, self.budget, self.path = fh, budget, path

    def read(self, n: int) -> bytes:
        try:
            data = self.fh.read(min(n, self.budget.left + 1))
        except Exception as exc:   # zstd raises its own kinds for damaged data
            raise MessageError(f"{self.path}: its zstd data are damaged ({type(exc).__name__}: {exc}).") from None
        self.budget.spend(len(data))
        return data
