"""Serialized ROS messages read field by field: ROS 1's serialization and ROS 2's CDR, every size checked.

Two encodings carry the same message definitions:

- **ROS 1** (ROS wiki, "roscpp/Overview/MessagesSerializationAndAdaptingTypes",
  "msg"): little-endian, packed without padding; a ``string`` or a
  variable-length array is a uint32 count then its elements; ``time`` is two
  uint32 (s, ns); ``std_msgs/Header`` starts with a uint32 ``seq``.
- **CDR** (OMG "Common Data Representation", as ROS 2's rmw layers write
  it): a 4-byte encapsulation header (its second byte 1 for little-endian,
  0 for big-endian), then each primitive aligned to its own size counted from
  the end of that header; a ``string`` is a uint32 length counting its
  terminating NUL, then the characters and the NUL; a sequence a uint32
  count then its elements; ``builtin_interfaces/Time`` an int32 and a uint32;
  ``std_msgs/Header`` has no ``seq``.

A :class:`Cursor` reads one message front to back. Every count it reads is
checked against the cap given and against the bytes left before anything is
sliced or allocated; an error names the field (:class:`~novelty.io.ros.caps.MessageError`
through :class:`~novelty.io.ros.caps.Where`).
"""

from __future__ import annotations

import struct

import numpy as np

from . import caps
from .caps import Where

__all__ = ["Cursor"]

_FORMATS = {"u1": "B", "u4": "I", "i4": "i", "f4": "f", "f8": "d"}
_STRUCTS = {(order, kind): struct.Struct(order + fmt) for order in "<>" for kind, fmt in _FORMATS.items()}


class Cursor:
    """A position in one serialized message (``ros1`` or CDR), read front to back."""

    __slots__ = ("data", "pos", "ros1", "order", "base", "where")

    def __init__(self, data: bytes, ros1: bool, where: Where):
        self.data, self.ros1, self.where = data, ros1, where
        if ros1:
            self.pos, self.base, self.order = 0, 0, "<"
        else:
            if len(data) < 4 or data[1] not in (0, 1):
                raise where.error("encapsulation", f"not a CDR message (its first bytes are {bytes(data[:4])!r}).")
            self.pos, self.base, self.order = 4, 4, "<" if data[1] == 1 else ">"

    def _align(self, size: int) -> None:
        if not self.ros1 and size > 1:
            self.pos += -(self.pos - self.base) % size

    def take(self, kind: str, field: str, count: int = 1) -> tuple:
        """``count`` values of ``kind`` (``u1``, ``u4``, ``i4``, ``f4``, ``f8``), aligned as the encoding says."""
        size = _STRUCTS[("<", kind)].size
        self._align(size)
        end = self.pos + size * count
        self.where.within(end, len(self.data), field)
        fmt = _STRUCTS[(self.order, kind)] if count == 1 else struct.Struct(self.order + _FORMATS[kind] * count)
        values = fmt.unpack_from(self.data, self.pos)
        self.pos = end
        return values

    def one(self, kind: str, field: str):
        return self.take(kind, field)[0]

    def string(self, field: str, cap: int = caps.MAX_NAME) -> str:
        n = self.where.count(self.one("u4", field), cap, field, "characters", "MAX_NAME")
        self.where.within(self.pos + n, len(self.data), field)
        raw = bytes(self.data[self.pos:self.pos + n])
        self.pos += n
        if not self.ros1:
            raw = raw.rstrip(b"\0")   # CDR counts the terminating NUL
        return raw.decode("utf-8", "replace")

    def header(self) -> tuple[float, str]:
        """A ``std_msgs/Header``: its stamp (s) and frame."""
        if self.ros1:
            self.one("u4", "header.seq")
            sec, nsec = self.take("u4", "header.stamp", 2)
        else:
            sec, nsec = self.one("i4", "header.stamp"), self.one("u4", "header.stamp")
        return sec + nsec * 1e-9, self.string("header.frame_id")

    def count(self, field: str, cap: int, what: str, cap_name: str, item_bytes: int) -> int:
        """A sequence's count, checked against ``cap`` and the bytes left (each item at least ``item_bytes``)."""
        n = self.where.count(self.one("u4", field), cap, field, what, cap_name)
        self.where.within(self.pos + n * item_bytes, len(self.data), field)
        return n

    def array(self, kind: str, field: str, cap: int, what: str, cap_name: str) -> np.ndarray:
        """A variable-length array of ``kind``: a view of the message's bytes, checked before it is made."""
        size = _STRUCTS[("<", kind)].size
        n = self.count(field, cap, what, cap_name, size)
        self._align(size)
        self.where.within(self.pos + n * size, len(self.data), field)
        values = np.frombuffer(self.data, self.order + kind, n, self.pos)
        self.pos += n * size
        return values

    def skip_array(self, size: int, field: str, cap: int, what: str, cap_name: str) -> None:
        n = self.count(field, cap, what, cap_name, size)
        self._align(size)
        self.where.within(self.pos + n * size, len(self.data), field)
        self.pos += n * size
