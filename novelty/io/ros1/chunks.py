"""A ROS 1 bag's chunk, inflated only as far as the messages asked for need, and their records read.

A chunk record (op 5) holds message records, stored as they are or
compressed (``bz2``, ``lz4``), and states its uncompressed size. An
:class:`Inflated` chunk is decompressed incrementally (``max_length``) up
to the end of the message asked for, never beyond the size the chunk
states nor beyond :data:`~novelty.io.ros.caps.MAX_CHUNK_BYTES`; a message's
record is checked (its header, its op, its stated length against the room
its chunk's index leaves and against its reader's cap) before its bytes
are inflated. A message longer than its cap has only its first bytes
inflated, so that its reader can name the field that asks for too much.

References
----------
ROS wiki, "Bags/Format/2.0": the record, chunk and message data formats.
"""

from __future__ import annotations

import bz2
import struct
from typing import Callable

from ..ros import caps
from ..ros.caps import MessageError, Where

__all__ = ["Inflated", "Limit"]

_MESSAGE, _CONNECTION = 2, 7
#: The longest record header read.
_MAX_HEADER = 4 * 2**20
#: A message's first bytes, enough to read the sizes a LaserScan or a PointCloud2 states.
_PEEK = 3 * caps.MAX_NAME
_U32 = struct.Struct("<I")

#: what a reader says of a topic's messages: the largest length accepted, and a check of a longer
#: message's first bytes that raises the error naming the field beyond its cap
Limit = tuple[int, Callable[[bytes, Where], None] | None]



class Inflated:
    """A chunk's records, inflated as far as the messages asked for need and never beyond its stated size."""

    def __init__(self, fh, data_pos: int, data_len: int, compression: str, size: int, where: Where):
        if compression not in ("none", "bz2", "lz4"):
            raise where.error("chunk", f"compression {compression!r}; a ROS 1 bag's are none, bz2 and lz4.")
        fh.seek(data_pos)
        self.size, self.compression = size, compression
        self.pending = fh.read(data_len)   # at most the file's own bytes
        self.buf = self.pending if compression == "none" else bytearray()
        self.decompressor = None

    def upto(self, end: int, where: Where) -> None:
        """Inflate the chunk's first ``end`` bytes (``end`` within its stated size)."""
        if end > caps.MAX_CHUNK_BYTES and len(self.buf) < end:
            raise where.error("chunk", f"lies {end:,} bytes into its chunk's {self.size:,}; at most "
                              f"{caps.MAX_CHUNK_BYTES:,} are inflated (novelty.io.ros.caps.MAX_CHUNK_BYTES).")
        while len(self.buf) < end:
            if self.decompressor is None:
                if self.compression == "none" or not self.pending:
                    raise self._short(where)
                self.decompressor = _decompressor(self.compression)
                data, self.pending = self.pending, b""
            else:
                data = b""
            before = len(self.buf)
            try:
                self.buf += self.decompressor.decompress(data, max_length=end - len(self.buf))
            except (OSError, EOFError, RuntimeError, ValueError) as exc:
                raise where.error("chunk", f"its chunk cannot be inflated ({type(exc).__name__}: {exc}).") from None
            if self.decompressor.eof:
                # a stream (an lz4 frame) ended: the next one, if any, is in its unused data
                self.pending, self.decompressor = self.decompressor.unused_data, None
            elif len(self.buf) == before and self.decompressor.needs_input:
                raise self._short(where)

    def _short(self, where: Where) -> MessageError:
        return where.error("chunk", f"the chunk ends after {len(self.buf):,} of the {self.size:,} bytes it "
                           "states (a truncated or corrupt chunk).")

    def message(self, offset: int, extent: int, limit: Limit, where: Where) -> bytes:
        """The data of the message record at ``offset``, its length checked before it is inflated."""
        position = offset
        while True:
            self.upto(min(position + 4, self.size), where)
            header_len = self._u32(position, where)
            if position + 8 + header_len > min(self.size, offset + extent) or header_len > _MAX_HEADER:
                raise where.error("record", f"a {header_len:,}-byte record header at byte {position:,} "
                                  "runs past the message's room in its chunk.")
            self.upto(position + 8 + header_len, where)
            op = _op(self.buf[position + 4:position + 4 + header_len])
            data_len = self._u32(position + 4 + header_len, where)
            start = position + 8 + header_len
            if op != _CONNECTION:
                break
            position = start + data_len   # a connection record before its first message: passed over
        if op != _MESSAGE:
            raise where.error("record", f"the index points at a record of op {op}, not a message.")
        room = offset + extent - start
        if data_len > room:
            raise where.error("length", f"states {data_len:,} bytes where its chunk's index leaves {max(room, 0):,} "
                              "(a corrupt bag).")
        largest, explain = limit
        if data_len > largest:
            self.upto(start + min(data_len, _PEEK), where)
            if explain is not None:
                explain(bytes(self.buf[start:start + min(data_len, _PEEK)]), where)
            raise where.error("length", f"states {data_len:,} bytes; at most {largest:,} are read for its type "
                              "(novelty.io.ros.caps).")
        self.upto(start + data_len, where)
        return bytes(self.buf[start:start + data_len])

    def _u32(self, position: int, where: Where) -> int:
        if position + 4 > len(self.buf):
            raise where.error("record", "the chunk ends inside a record.")
        return _U32.unpack_from(self.buf, position)[0]


def _op(header) -> int | None:
    i = 0
    while i + 4 <= len(header):
        (n,) = _U32.unpack_from(header, i)
        if header[i + 4:i + 7] == b"op=" and n == 4:
            return header[i + 7]
        i += 4 + n
    return None


def _decompressor(compression: str):
    if compression == "bz2":
        return bz2.BZ2Decompressor()
    # deferred: lz4 comes with rosbags (the ros extra), needed only for an lz4 chunk
    import lz4.frame

    return lz4.frame.LZ4FrameDecompressor()
