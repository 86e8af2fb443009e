"""Data files written byte by byte, to craft what no writer would write: a MATLAB 5 ``.mat`` whose cell array
inflates far beyond what its header declares, an ``.npz`` member that is not an array.

MATLAB 5 (MathWorks, "MAT-File Format", version 5): a 128-byte header, then
data elements, each a tag (type, byte count) and its data padded to 8 bytes;
a compressed element (miCOMPRESSED) holds a zlib stream of one element, here a
matrix (miMATRIX: array flags, dimensions, name, then its data or, for a cell
array, one matrix element a cell).
"""

import struct
import zipfile
import zlib

MI_INT8, MI_INT32, MI_UINT32, MI_DOUBLE, MI_MATRIX, MI_COMPRESSED = 1, 5, 6, 9, 14, 15
MX_CELL, MX_DOUBLE = 1, 6
BLOCK = 2**20


def _element(kind: int, data: bytes) -> bytes:
    return struct.pack("<II", kind, len(data)) + data + bytes(-len(data) % 8)


def _matrix_head(mx_class: int, dims: tuple, name: str, size: int) -> bytes:
    """A matrix element's tag (its byte count ``size`` after the tag), array flags, dimensions and name."""
    flags = _element(MI_UINT32, struct.pack("<II", mx_class, 0))
    shape = _element(MI_INT32, struct.pack(f"<{len(dims)}i", *dims))
    return struct.pack("<II", MI_MATRIX, size) + flags + shape + _element(MI_INT8, name.encode())


def mat_cell_of_zeros(path, name: str, n: int) -> None:
    """A .mat holding the cell array ``name`` (1 x 1) of one n x 1 double array of zeros, compressed: a few
    kilobytes a megabyte, never holding the zeros whole."""
    data = n * 8
    inner_head = _matrix_head(MX_DOUBLE, (n, 1), "", 0)
    inner_size = len(inner_head) - 8 + 8 + data
    inner_head = _matrix_head(MX_DOUBLE, (n, 1), "", inner_size) + struct.pack("<II", MI_DOUBLE, data)
    outer_head = _matrix_head(MX_CELL, (1, 1), name, 0)
    outer_head = _matrix_head(MX_CELL, (1, 1), name, len(outer_head) - 8 + len(inner_head) + data)
    compressor = zlib.compressobj()
    parts = [compressor.compress(outer_head + inner_head)]
    zeros = bytes(BLOCK)
    for at in range(0, data, BLOCK):
        parts.append(compressor.compress(zeros[:min(BLOCK, data - at)]))
    parts.append(compressor.flush())
    stream = b"".join(parts)
    header = b"MATLAB 5.0 MAT-file, crafted".ljust(116, b" ") + bytes(8) + struct.pack("<H", 0x0100) + b"IM"
    with open(path, "wb") as fh:
        fh.write(header + struct.pack("<II", MI_COMPRESSED, len(stream)) + stream)


def npz_with_member(path, arrays: dict, name: str, content: bytes) -> None:
    """An .npz of ``arrays`` (as numpy writes them) with one more member ``name`` holding ``content``."""
    import numpy as np

    np.savez(path, **arrays)
    with zipfile.ZipFile(path, "a") as zf:
        zf.writestr(name, content)
