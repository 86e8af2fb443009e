"""Reading a CSV, NPZ or MAT file of scans into named columns (the format is described in :mod:`novelty.io.tables.scan_file`).

Reading is bounded by limits the library sets, not by the file: only a
regular file is read (``/dev/zero`` would never end, a FIFO without a writer
never start); a CSV line holds at most :data:`MAX_LINE_CHARS` characters and
a row at most :data:`MAX_COLUMNS` cells (a header of a few hundred MB is
refused after reading one limit's worth, not loaded); an ``.npz`` file
inflates to at most :data:`MAX_NPZ_BYTES` in all, and each array's declared
shape must fit in the bytes its member holds, both checked before anything
is inflated, and a member that is not an array is refused. A MATLAB
``.mat`` file (ODDS's format: ``X`` and ``y``, the MATLAB 5 format scipy
reads) is held to the same total, from the shapes its header declares,
before anything is read, each compressed variable checked to inflate to no
more than its dimensions need, and a cell array, struct or object (whose
size says nothing of what it holds) refused (:mod:`novelty.io.tables.matlab`). A
vector written as one row or one column of a matrix (as scipy's ``savemat``
writes a 1-D array) is one value a scan, and numbers stored as text are read
as a CSV's are.
"""

from __future__ import annotations

import csv
import math
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from ..._atomic import not_regular
from .columns import LABEL_COLUMNS, ROUTE_COLUMNS, TIME_COLUMNS
from .data_files import is_float
from .matlab import check_variables, variables

__all__ = ["Table", "header_of", "read_table", "bounded_lines", "csv_rows", "check_data_file",
           "MAX_LINE_CHARS", "MAX_COLUMNS", "MAX_NPZ_BYTES"]

#: the longest line of a CSV file or stream read (a scan of 65,536 readings of 60 characters)
MAX_LINE_CHARS = 2**22
#: the most cells in a row (and names in a header)
MAX_COLUMNS = 2**16
#: the most bytes an .npz data file inflates to, all its arrays together
MAX_NPZ_BYTES = 2**30
#: the names of the columns that have a role beside X: an array of one of them is one value a scan
ROLE_COLUMNS = LABEL_COLUMNS + TIME_COLUMNS + ROUTE_COLUMNS


@dataclass(frozen=True)
class Table:
    """A file's columns, in file order: numbers (float64) or text (str).

    ``lines`` holds the line of the file each row was read from (a CSV file),
    or is ``None`` (an NPZ file: a row is its index in ``X``).
    """

    source: str
    names: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    lines: tuple[int, ...] | None = None

    @property
    def n_rows(self) -> int:
        return self.values[0].shape[0] if self.values else 0

    def where(self, i: int) -> str:
        """Where row ``i`` is, as a reader finds it: ``scans.csv, line 14`` or ``scans.npz, row 12``."""
        return f"{self.source}, line {self.lines[i]}" if self.lines is not None else f"{self.source}, row {i}"


def header_of(first_row: Sequence[str]) -> list[str] | None:
    """The column names if ``first_row`` is a header, else ``None``.

    A header is a row of names: at least half of its cells are not numbers,
    or the numbers in it are column positions (``,0,1,2`` as pandas writes
    integer column names). A row of numbers with a few bad cells is data,
    and its bad cells are reported, rather than taken as names (which would
    silently drop a scan).
    """
    numbers = [c for c in first_row if is_float(c)]
    if len(numbers) == len(first_row):
        return None
    if 2 * len(numbers) > len(first_row) and not all(
            c.strip().isdigit() and int(c) < len(first_row) for c in numbers):
        return None
    return [c.strip() for c in first_row]


def _column(cells: list[str]) -> np.ndarray:
    try:
        return np.array([float(c) for c in cells], dtype=np.float64)
    except ValueError:
        return np.array([c.strip() for c in cells])


def bounded_lines(fh, source: str):
    """The lines of the text stream ``fh``, refusing one longer than :data:`MAX_LINE_CHARS`
    (a ``ValueError`` naming ``source`` and the line) after reading no more than that."""
    limit = MAX_LINE_CHARS
    number = 0
    while True:
        try:
            line = fh.readline(limit + 1)
        except UnicodeDecodeError as exc:
            raise ValueError(f"{source} is not UTF-8 text ({exc.reason}); save it as UTF-8.") from None
        if not line:
            return
        number += 1
        if len(line) > limit and not line.endswith("\n"):
            raise ValueError(f"{source}, line {number}: longer than {limit} characters, the longest line "
                             "read (one scan a line); is it a CSV file of scans?")
        yield line


def csv_rows(reader, source: str):
    """The rows of a csv reader, each of at most :data:`MAX_COLUMNS` cells; csv's errors named."""
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:  # a NUL byte, a field beyond csv's limit
            raise ValueError(f"{source}, line {reader.line_num}: not CSV text ({exc}).") from None
        if len(row) > MAX_COLUMNS:
            raise ValueError(f"{source}, line {reader.line_num}: {len(row)} cells; at most {MAX_COLUMNS} "
                             "are read.")
        yield row


def check_data_file(path) -> Path:
    """``path`` if it is a regular file; else ``FileNotFoundError`` or ``ValueError`` saying what it is."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"Data file not found: {path}")
    if path.is_dir():
        raise ValueError(f"{path} is a folder; expected a .csv, .npz or .mat file of scans.")
    kind = not_regular(path)
    if kind is not None:
        raise ValueError(f"{path} is {kind}, not a regular file; scans are read only from a .csv, .npz or .mat "
                         "file (standard input: --data -).")
    return path


def _read_csv(path: Path) -> Table:
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            reader = csv.reader(bounded_lines(fh, str(path)))
            # the line a row ends on, so that an error names the line an editor shows
            rows, lines = [], []
            for r in csv_rows(reader, str(path)):
                if r and any(c.strip() for c in r):
                    rows.append(r)
                    lines.append(reader.line_num)
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path} is not UTF-8 text ({exc.reason}); "
                         "save it as UTF-8.") from None
    if not rows:
        raise ValueError(f"{path} is empty.")
    header = header_of(rows[0])
    if header is None:  # no names: every column is a sensor, every cell a number
        for j, cell in enumerate(rows[0]):
            if not is_float(cell):
                raise ValueError(f"{path}, line 1: column {j + 1} holds {cell.strip()!r}, which is "
                                 "not a number (and too few of the row's cells are names for a header).")
    body, lines = (rows[1:], lines[1:]) if header else (rows, lines)
    if not body:
        raise ValueError(f"{path} has a header but no scans.")
    width = len(header or body[0])
    for row, line in zip(body, lines):
        if len(row) != width:
            raise ValueError(f"{path}, line {line}: {len(row)} values, expected {width}.")
    names = header or [f"s{i}" for i in range(width)]
    return Table(str(path), tuple(names), tuple(_column([r[j] for r in body]) for j in range(width)),
                 tuple(lines))


def _check_npz_sizes(path: Path) -> None:
    """Refuse an .npz that would inflate beyond :data:`MAX_NPZ_BYTES`, or an array whose declared
    shape needs more bytes than its member holds (numpy allocates the shape first)."""
    with zipfile.ZipFile(path) as zf:
        members = zf.infolist()
        total = sum(info.file_size for info in members)
        if total > MAX_NPZ_BYTES:
            raise ValueError(f"{path} inflates to {total} bytes; at most {MAX_NPZ_BYTES} are read.")
        for info in members:
            if not info.filename.endswith(".npy"):
                raise ValueError(f"{path}: its member {info.filename!r} is not a NumPy array (.npy); an .npz of "
                                 "scans holds arrays only.")
            with zf.open(info) as fh:
                version = np.lib.format.read_magic(fh)
                read = {(1, 0): np.lib.format.read_array_header_1_0,
                        (2, 0): np.lib.format.read_array_header_2_0}.get(version)
                if read is None:
                    raise ValueError(f"{path}: the array {info.filename[:-4]!r} has npy format {version}.")
                shape, _, dtype = read(fh)
                declared = math.prod(shape) * dtype.itemsize
                if declared > info.file_size - fh.tell():
                    raise ValueError(f"{path}: the array {info.filename[:-4]!r} declares shape {shape} "
                                     f"({declared} bytes) but holds {info.file_size - fh.tell()} bytes.")


def _read_npz(path: Path) -> Table:
    try:
        _check_npz_sizes(path)
        npz = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        if str(exc).startswith(str(path)):   # ours: already says what
            raise
        raise ValueError(f"Cannot read {path} as an .npz file: {exc}") from None
    with npz:
        arrays = {k: npz[k] for k in npz.files}
    return _table_of(path, arrays)


def _read_mat(path: Path) -> Table:
    """A MATLAB 5 ``.mat`` file (ODDS's ``X`` and ``y``): its variables checked from their headers
    (:mod:`novelty.io.tables.matlab`), then its numeric arrays read."""
    # imported here: the command line reads tables and must start without scipy (tests/test_init.py)
    from scipy import io as matlab

    try:
        found = variables(path)
        total = sum(math.prod(v.shape) * 8 for v in found)
        if total > MAX_NPZ_BYTES:
            raise ValueError(f"{path} declares {total} bytes of arrays; at most {MAX_NPZ_BYTES} are read.")
        check_variables(path, found)
        numeric = [v.name for v in found if v.kind not in ("char", "sparse")]
        contents = matlab.loadmat(str(path), variable_names=numeric) if numeric else {}
    except NotImplementedError:  # scipy's answer to a MATLAB 7.3 file, which is HDF5
        raise ValueError(f"{path} is a MATLAB 7.3 (HDF5) file, which is not read; save it in MATLAB 5 format "
                         "(save -v7) or as an .npz of X and y.") from None
    except (OSError, ValueError, TypeError, EOFError, IndexError, KeyError) as exc:  # scipy's, on a damaged file
        if str(exc).startswith(str(path)):   # ours: already says what
            raise
        raise ValueError(f"Cannot read {path} as a MATLAB .mat file: {type(exc).__name__}: {exc}") from None
    arrays = {key: value for key, value in contents.items()
              if not key.startswith("__") and isinstance(value, np.ndarray) and value.dtype.kind in "biuf"}
    return _table_of(path, arrays)


def _table_of(path: Path, arrays: dict) -> Table:
    """The table of a file's arrays: ``X`` (or its one 2-D array) by columns, then each array of one value a
    row (1-D, or one row or column of a matrix, as MATLAB and scipy's ``savemat`` write a vector); numbers
    stored as text are read as a CSV's are."""
    if "X" not in arrays:
        two_d = [k for k, a in arrays.items() if a.ndim == 2 and min(a.shape) > 1] or \
            [k for k, a in arrays.items() if a.ndim == 2]
        if len(two_d) != 1:
            raise ValueError(f"{path} has no array named 'X' (it has {', '.join(arrays) or 'none'}).")
        arrays["X"] = arrays.pop(two_d[0])
    X = arrays.pop("X")
    if X.ndim != 2:
        raise ValueError(f"{path}: X must be a table of scans by sensors; got shape {X.shape}.")
    names = [f"s{j}" for j in range(X.shape[1])]
    values = [_numbers_of(X[:, j]) for j in range(X.shape[1])]
    for key, a in arrays.items():
        a = a.reshape(-1) if a.ndim == 2 and 1 in a.shape else a
        if a.ndim != 1:
            continue
        name = key.removeprefix("column_")
        if a.shape[0] != X.shape[0]:
            if name in ROLE_COLUMNS:
                raise ValueError(f"{path}: the array {key!r} holds {a.shape[0]} values, one for each of X's "
                                 f"{X.shape[0]} scans expected.")
            continue
        names.append(name)
        values.append(a.astype(np.float64) if np.issubdtype(a.dtype, np.number) else _numbers_of(a))
    return Table(str(path), tuple(names), tuple(values))


def _numbers_of(values: np.ndarray) -> np.ndarray:
    """A column as a file holds it: numbers as float64, text as numbers where every cell is one (as a CSV's
    are read), else as text."""
    if values.dtype.kind in "US":
        return _column([str(v) for v in values.tolist()])
    return np.asarray(values)


def read_table(path) -> Table:
    """The columns of a CSV, NPZ or MAT file (see the module docstring)."""
    path = check_data_file(path)
    suffix = path.suffix.lower()
    table = _read_npz(path) if suffix == ".npz" else _read_mat(path) if suffix == ".mat" else _read_csv(path)
    if table.n_rows == 0:
        raise ValueError(f"{path} has no scans.")
    return table
