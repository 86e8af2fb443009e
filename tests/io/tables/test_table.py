"""Reading scan files is bounded by the library's limits, not the file's: non-regular files, long
lines, wide headers and inflating archives are refused after reading no more than a limit's worth."""

import io
import os
import stat
import time
import tracemalloc
import zipfile

import numpy as np
import pytest

from novelty.io.tables import table as tables
from novelty.io.tables.table import bounded_lines, read_table

from .craft import mat_cell_of_zeros, npz_with_member


class EndlessLine(io.TextIOBase):
    """A text stream of one line that never ends (a 2 GB line, or /dev/zero read as text)."""

    def __init__(self):
        self.served = 0

    def readable(self):
        return True

    def readline(self, size=-1):
        assert size > 0, "an unbounded readline would never return"
        self.served += size
        return "0," * (size // 2) + "0" * (size % 2)


def test_an_endless_line_is_refused_after_one_limits_worth():
    source = EndlessLine()
    with pytest.raises(ValueError, match=rf"standard input, line 1: longer than {tables.MAX_LINE_CHARS} characters"):
        list(bounded_lines(source, "standard input"))
    assert source.served == tables.MAX_LINE_CHARS + 1


def test_a_long_line_or_header_in_a_file_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(tables, "MAX_LINE_CHARS", 1000)  # the limit made small: the test stays fast
    path = tmp_path / "scans.csv"
    path.write_text("a,b\n" + ",".join(["0.5"] * 400) + "\n")
    with pytest.raises(ValueError, match=r"scans.csv, line 2: longer than 1000 characters"):
        read_table(path)
    path.write_text(",".join(f"name{i}" for i in range(300)) + "\n0.5\n")
    with pytest.raises(ValueError, match=r"scans.csv, line 1: longer than 1000 characters"):
        read_table(path)


def test_a_row_of_too_many_cells_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(tables, "MAX_COLUMNS", 8)
    path = tmp_path / "wide.csv"
    path.write_text(",".join(["1"] * 9) + "\n")
    with pytest.raises(ValueError, match=r"wide.csv, line 1: 9 cells; at most 8 are read"):
        read_table(path)


def _device(path):
    try:
        os.mknod(path, 0o600 | stat.S_IFCHR, os.makedev(1, 5))  # the numbers of a zero device
    except PermissionError:
        pytest.skip("making a device node needs privileges")


@pytest.mark.parametrize("make, kind", [(os.mkfifo, "a FIFO"), (_device, "a character device")])
def test_a_file_that_is_not_regular_is_refused_without_reading(tmp_path, make, kind):
    path = tmp_path / "scans.csv"
    make(path)
    started = time.perf_counter()
    with pytest.raises(ValueError, match=rf"scans.csv is {kind}.*not a regular file"):
        read_table(path)
    assert time.perf_counter() - started < 5  # a FIFO without a writer would block forever


def test_an_npz_inflating_beyond_the_limit_is_refused_before_inflating(tmp_path, monkeypatch):
    monkeypatch.setattr(tables, "MAX_NPZ_BYTES", 2**20)
    path = tmp_path / "bomb.npz"
    np.savez_compressed(path, X=np.zeros((2**15, 8)))  # 2 MiB of zeros in a few kB
    assert path.stat().st_size < 20_000
    with pytest.raises(ValueError, match=r"bomb.npz inflates to 2097\d+ bytes; at most 1048576 are read"):
        read_table(path)


def test_an_npz_array_declaring_more_than_it_holds_is_refused_before_allocation(tmp_path):
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False,
                                                  "shape": (10**9, 16)})  # 119 GiB declared
    path = tmp_path / "liar.npz"
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("X.npy", b"\x93NUMPY\x01\x00" + header.getvalue()[8:] + b"\x00" * 64)
    with pytest.raises(ValueError, match=r"liar.npz: the array 'X' declares shape \(1000000000, 16\)"):
        read_table(path)


def test_an_odds_mat_file_reads_x_and_its_column_of_labels(tmp_path):
    from scipy.io import savemat

    from novelty.datasets.files import read_scans

    X = np.arange(12.0).reshape(6, 2)
    savemat(tmp_path / "odds.mat", {"X": X, "y": np.array([[0], [0], [1], [0], [1], [0]], dtype=float)})
    data = read_scans(tmp_path / "odds.mat")
    np.testing.assert_array_equal(data.X, X)
    assert data.y.tolist() == [0, 0, 1, 0, 1, 0]
    (tmp_path / "broken.mat").write_bytes(b"MATLAB 5.0 MAT-file, but nothing after")
    with pytest.raises(ValueError, match="broken.mat"):
        read_scans(tmp_path / "broken.mat")


def test_a_mat_cell_array_is_refused_by_name_without_being_read(tmp_path):
    path = tmp_path / "cell.mat"
    mat_cell_of_zeros(path, "X", 32 * 2**20)   # 256 MiB of zeros in a cell the header says is 1 x 1
    assert path.stat().st_size < 400_000
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"cell.mat: its variable X, a 1 x 1 cell array; cell arrays, structs, "
                                             r"objects and functions are not read"):
            read_table(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 16 * 2**20


@pytest.mark.parametrize("shape", ["row", "column"])
def test_a_label_vector_of_one_row_or_one_column_is_a_column(tmp_path, shape):
    from scipy.io import savemat

    from novelty.datasets.files import read_scans

    X, y = np.arange(12.0).reshape(6, 2), np.array([0, 0, 1, 0, 1, 0])
    labels = y[None, :] if shape == "row" else y[:, None]
    savemat(tmp_path / "labels.mat", {"X": X, "y": y})   # scipy writes a 1-D array as 1 x n
    np.savez(tmp_path / "labels.npz", X=X, y=labels)
    for name in ("labels.mat", "labels.npz"):
        assert read_scans(tmp_path / name).y.tolist() == y.tolist(), name


def test_a_label_vector_of_another_length_is_named(tmp_path):
    np.savez(tmp_path / "short.npz", X=np.zeros((6, 2)), y=np.zeros((1, 5)))
    with pytest.raises(ValueError, match=r"short.npz: the array 'y' holds 5 values, one for each of X's 6 scans "
                                         r"expected"):
        read_table(tmp_path / "short.npz")


def test_numbers_stored_as_text_in_an_npz_are_read_as_a_csv_reads_them(tmp_path):
    from novelty.datasets.files import read_scans

    X = np.array([[0.5, 1.0], [2.0, 3.5], [1e-3, -4.0]])
    np.savez(tmp_path / "text.npz", X=X.astype(str), y=np.array(["0", "1", "0"]), split=np.array(["train"] * 3))
    data = read_scans(tmp_path / "text.npz")
    np.testing.assert_array_equal(data.X, X)
    assert data.y.tolist() == [0, 1, 0]
    words = X.astype(str)
    words[1, 1] = "n/a"
    np.savez(tmp_path / "words.npz", X=words)
    with pytest.raises(ValueError, match=r"words.npz, row 1, column 's1': expected a number, got text 'n/a'"):
        read_scans(tmp_path / "words.npz")


def test_an_npz_member_that_is_not_an_array_is_refused_by_name(tmp_path):
    npz_with_member(tmp_path / "notes.npz", {"X": np.zeros((3, 2))}, "notes.txt", b"written by hand")
    with pytest.raises(ValueError, match=r"notes.npz: its member 'notes.txt' is not a NumPy array \(.npy\); an .npz "
                                         r"of scans holds arrays only"):
        read_table(tmp_path / "notes.npz")
