"""Data files written byte by byte, to craft what no writer would write: a MATLAB 5 ``.mat`` whose cell array
or compressed stream inflates far beyond what its header declares, an ``.npz`` member that is not an array.

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


def _element(kind: int, data: bytes, order: str = "<") -> bytes:
    return struct.pack(f"{order}II", kind, len(data)) + data + bytes(-len(data) % 8)


def _matrix_head(mx_class: int, dims: tuple, name: str, size: int, order: str = "<") -> bytes:
    """A matrix element's tag (its byte count ``size`` after the tag), array flags, dimensions and name."""
    flags = _element(MI_UINT32, struct.pack(f"{order}II", mx_class, 0), order)
    shape = _element(MI_INT32, struct.pack(f"{order}{len(dims)}i", *dims), order)
    return struct.pack(f"{order}II", MI_MATRIX, size) + flags + shape + _element(MI_INT8, name.encode(), order)


def mat_big_endian(path, name: str, values) -> None:
    """A big-endian .mat (as a SPARC or PowerPC MATLAB wrote it) of one uncompressed double matrix."""
    rows, columns = len(values), len(values[0])
    data = struct.pack(f">{rows * columns}d", *(values[i][j] for j in range(columns) for i in range(rows)))
    head = _matrix_head(MX_DOUBLE, (rows, columns), name, 0, ">")
    body = head[8:] + _element(MI_DOUBLE, data, ">")
    header = b"MATLAB 5.0 MAT-file, big-endian".ljust(116, b" ") + bytes(8) + struct.pack(">H", 0x0100) + b"MI"
    with open(path, "wb") as fh:
        fh.write(header + struct.pack(">II", MI_MATRIX, len(body)) + body)


def mat_double_with_zeros_after(path, name: str, shape: tuple, n: int) -> None:
    """A .mat holding the double array ``name`` of ``shape`` (zeros, as its header says), compressed with ``n``
    more zero bytes after it in the same stream, which no dimension accounts for."""
    data = 8 * shape[0] * shape[1]
    head = _matrix_head(MX_DOUBLE, shape, name, 0)
    head = _matrix_head(MX_DOUBLE, shape, name, len(head) - 8 + 8 + data) + struct.pack("<II", MI_DOUBLE, data)
    _write_compressed(path, head, data + n)


def mat_cell_of_zeros(path, name: str, n: int) -> None:
    """A .mat holding the cell array ``name`` (1 x 1) of one n x 1 double array of zeros, compressed: a few
    kilobytes a megabyte, never holding the zeros whole."""
    data = n * 8
    inner_head = _matrix_head(MX_DOUBLE, (n, 1), "", 0)
    inner_size = len(inner_head) - 8 + 8 + data
    inner_head = _matrix_head(MX_DOUBLE, (n, 1), "", inner_size) + struct.pack("<II", MI_DOUBLE, data)
    outer_head = _matrix_head(MX_CELL, (1, 1), name, 0)
    outer_head = _matrix_head(MX_CELL, (1, 1), name, len(outer_head) - 8 + len(inner_head) + data)
    _write_compressed(path, outer_head + inner_head, data)


def _write_compressed(path, head: bytes, zeros: int) -> None:
    """A .mat of one compressed element: ``head``, then ``zeros`` zero bytes, compressed a block at a time."""
    compressor = zlib.compressobj()
    parts = [compressor.compress(head)]
    block = bytes(BLOCK)
    for at in range(0, zeros, BLOCK):
        parts.append(compressor.compress(block[:min(BLOCK, zeros - at)]))
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
