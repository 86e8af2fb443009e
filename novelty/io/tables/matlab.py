"""A MATLAB 5 ``.mat`` file's variables listed from their headers, and checked to hold no more than they state.

A ``.mat`` file (MATLAB's ``-v7`` and earlier, ODDS's format) is a 128-byte
header, then one data element a variable: a matrix (miMATRIX) or a zlib
stream of one (miCOMPRESSED), whose header states the array's class,
dimensions and name. scipy's reader inflates a compressed variable a block at
a time (131,072 compressed bytes, up to 135 MB of zeros inflated) even to
read its header or to pass over it, and a cell array, struct or object
states dimensions that say nothing of what it holds: a 1.2 MB file can hold
a 1 x 1 cell of 1.4 GB. So the variables are listed here first, each
compressed header inflated only as far as it reaches
(:data:`HEADER_BYTES`), and a file is refused (``ValueError`` naming the
variable) that holds a variable of a class other than numbers, text or a
sparse matrix, or a compressed variable inflating beyond what its
dimensions need, before scipy reads anything.

References
----------
The MathWorks, "MAT-File Format" (version 5): the file header, the data
element tag (and its small-element form), the miMATRIX sub-elements (array
flags, dimensions, name) and miCOMPRESSED.
"""

from __future__ import annotations

import math
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Variable", "variables", "check_variables", "HEADER_BYTES"]

#: the inflated bytes of a compressed variable read to find its header (its dimensions and its name)
HEADER_BYTES = 2**16
_INT8, _INT32, _UINT32, _MATRIX, _COMPRESSED = 1, 5, 6, 14, 15
#: array classes: a number's class, and the others by name
_CLASSES = {1: "cell", 2: "struct", 3: "object", 4: "char", 5: "sparse", 6: "double", 7: "single", 8: "int8",
            9: "uint8", 10: "int16", 11: "uint16", 12: "int32", 13: "uint32", 14: "int64", 15: "uint64",
            16: "function", 17: "opaque"}
#: the classes whose dimensions bound what they hold: numbers, text, sparse matrices
_BOUNDED = {"char", "sparse", "double", "single", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
            "uint64", "logical"}
_BLOCK = 2**16


@dataclass(frozen=True)
class Variable:
    """One variable of a ``.mat`` file, from its header."""

    name: str
    shape: tuple[int, ...]
    kind: str
    #: where its data element's data lie in the file, and their length; compressed or not
    position: int
    length: int
    compressed: bool

    def describe(self) -> str:
        return f"{self.name}, a {' x '.join(map(str, self.shape))} {self.kind} array"

    @property
    def most_bytes(self) -> int:
        """The most bytes its matrix element may take: 16 a value (a complex double; a sparse matrix's index
        with its value) and its sub-elements' headers."""
        return 16 * math.prod(self.shape) + 8 * len(self.shape) + len(self.name) + 1024


def variables(path) -> list[Variable]:
    """The variables of the MATLAB 5 file ``path``, in file order, from their headers alone."""
    path = Path(path)
    with path.open("rb") as fh:
        head = fh.read(128)
        if len(head) < 128 or head[126:128] not in (b"IM", b"MI"):
            raise ValueError(f"{path} is not a MATLAB 5 .mat file (no MATLAB 5 header).")
        order = "<" if head[126:128] == b"IM" else ">"
        size = path.stat().st_size
        out, position = [], 128
        while position + 8 <= size:
            fh.seek(position)
            kind, length, inline = _tag(fh.read(8), order)
            start = position + 8
            if inline is not None or start + length > size:
                raise ValueError(f"{path}: the element at byte {position:,} is not a variable reaching "
                                 f"{length:,} bytes within the file.")
            if kind == _COMPRESSED:
                header = _inflated_head(fh, length)
            elif kind == _MATRIX:
                header = struct.pack(f"{order}II", _MATRIX, length) + fh.read(min(length, HEADER_BYTES))
            else:
                raise ValueError(f"{path}: the element at byte {position:,} is of type {kind}, not a variable.")
            out.append(_variable(header, order, path, position, start, length, kind == _COMPRESSED))
            position = start + length   # as scipy goes on (a matrix's sub-elements are padded already)
    return out


def check_variables(path, found: list[Variable]) -> None:
    """Refuse a variable whose class does not bound what it holds, and a compressed one inflating beyond its
    dimensions' need (inflated a block at a time, never more than :data:`HEADER_BYTES` held)."""
    for v in found:
        if v.kind not in _BOUNDED:
            raise ValueError(f"{path}: its variable {v.describe()}; cell arrays, structs, objects and functions "
                             "are not read (their sizes say nothing of what they hold): save the scans as a "
                             "numeric matrix X and the labels as a vector y.")
    with Path(path).open("rb") as fh:
        for v in found:
            if v.compressed and _inflated_size(fh, v.position, v.length, v.most_bytes) > v.most_bytes:
                raise ValueError(f"{path}: its variable {v.describe()} inflates to more than the "
                                 f"{v.most_bytes:,} bytes its dimensions need (a corrupt or hostile file).")


def _tag(raw: bytes, order: str) -> tuple[int, int, bytes | None]:
    """A data element's type, its data's length and, in the small-element form, its data."""
    kind, length = struct.unpack(f"{order}II", raw)
    if kind >> 16:   # the small form: the length in the upper half, the data in the tag's last 4 bytes
        return kind & 0xFFFF, kind >> 16, raw[4:4 + (kind >> 16)]
    return kind, length, None


def _inflated_head(fh, length: int) -> bytes:
    """The first :data:`HEADER_BYTES` inflated bytes of a compressed element of ``length`` bytes at the file's place."""
    decompressor, out, left = zlib.decompressobj(), b"", length
    while left > 0 and len(out) < HEADER_BYTES and not decompressor.eof:
        data = decompressor.unconsumed_tail or fh.read(min(left, _BLOCK))
        if not decompressor.unconsumed_tail:
            left -= len(data)
        if not data:
            break
        try:
            out += decompressor.decompress(data, HEADER_BYTES - len(out))
        except zlib.error:
            break   # damaged: scipy says so
    return out


def _inflated_size(fh, position: int, length: int, most: int) -> int:
    """The bytes a compressed element inflates to, counted a block at a time, stopping beyond ``most``."""
    fh.seek(position)
    decompressor, total, left = zlib.decompressobj(), 0, length
    while total <= most and not decompressor.eof:
        if decompressor.unconsumed_tail:
            data = decompressor.unconsumed_tail
        else:
            data = fh.read(min(left, _BLOCK))
            left -= len(data)
            if not data:
                break
        try:
            total += len(decompressor.decompress(data, _BLOCK))
        except zlib.error:
            break   # damaged: scipy says so
    return total


def _variable(header: bytes, order: str, path: Path, at: int, start: int, length: int, compressed: bool) -> Variable:
    """A variable from its matrix element's first bytes: the tag, the array flags, the dimensions, the name."""
    try:
        kind, _, _ = _tag(header[:8], order)
        if kind != _MATRIX:
            raise ValueError
        i, fields = 8, []
        for _ in range(3):   # array flags, dimensions, name
            element, n, inline = _tag(header[i:i + 8], order)
            if inline is not None:
                fields.append(inline)
                i += 8
            else:
                fields.append(header[i + 8:i + 8 + n])
                if len(fields[-1]) < n:
                    raise ValueError
                i += 8 + n + (-n % 8)
        flags = struct.unpack(f"{order}I", fields[0][:4])[0]
        shape = struct.unpack(f"{order}{len(fields[1]) // 4}i", fields[1][:len(fields[1]) // 4 * 4])
        if min(shape, default=0) < 0:
            raise ValueError
    except (ValueError, struct.error):
        raise ValueError(f"{path}: the variable at byte {at:,} has no readable header (a corrupt file).") from None
    name = fields[2].decode("latin-1")
    kind_name = "logical" if flags & 0x0200 else _CLASSES.get(flags & 0xFF, "unknown")
    return Variable(name, tuple(shape), kind_name, start, length, compressed)
