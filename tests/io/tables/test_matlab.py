"""MATLAB 5 files' variables listed from their headers as scipy lists them, and what their headers do not bound refused."""

import tracemalloc

import numpy as np
import pytest

from novelty.io.tables.matlab import check_variables, variables

from .craft import mat_big_endian, mat_cell_of_zeros, mat_double_with_zeros_after

scipy_io = pytest.importorskip("scipy.io")


@pytest.mark.parametrize("compressed", [False, True])
def test_the_variables_are_those_scipy_lists(tmp_path, compressed):
    path = tmp_path / "mixed.mat"
    arrays = {"X": np.arange(12.0).reshape(4, 3), "y": np.array([0, 1, 0, 1], np.uint8), "a_long_name": np.ones(1),
              "flags": np.array([True, False]), "text": "hello", "empty": np.zeros((0, 2)), "b": np.int64(7)}
    scipy_io.savemat(path, arrays, do_compression=compressed)
    listed = [(v.name, v.shape, v.kind) for v in variables(path)]
    # scipy gives a text's shape as one string; its header says 1 x 5 characters
    assert listed == [(name, (1, 5) if kind == "char" else shape, kind) for name, shape, kind in scipy_io.whosmat(path)]
    check_variables(path, variables(path))


def test_a_big_endian_file_is_read_as_scipy_reads_it(tmp_path):
    path = tmp_path / "sparc.mat"
    mat_big_endian(path, "X", [[1.0, 2.0], [3.0, 4.5], [5.0, 6.0]])
    assert [(v.name, v.shape, v.kind, v.compressed) for v in variables(path)] == [("X", (3, 2), "double", False)]
    assert scipy_io.loadmat(path)["X"].tolist() == [[1.0, 2.0], [3.0, 4.5], [5.0, 6.0]]


def test_a_compressed_variable_holding_more_than_its_dimensions_is_refused_in_bounded_memory(tmp_path):
    path = tmp_path / "padded.mat"
    mat_double_with_zeros_after(path, "X", (3, 2), 256 * 2**20)   # 6 values, then 256 MiB of zeros
    tracemalloc.start()
    try:
        found = variables(path)
        assert [(v.name, v.shape, v.kind, v.compressed) for v in found] == [("X", (3, 2), "double", True)]
        with pytest.raises(ValueError, match=r"padded.mat: its variable X, a 3 x 2 double array inflates to more "
                                             r"than the 1,1\d\d bytes its dimensions need"):
            check_variables(path, found)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2**20


def test_a_cell_array_is_refused_by_its_name_from_its_header_alone(tmp_path):
    path = tmp_path / "cell.mat"
    mat_cell_of_zeros(path, "notes", 1000)
    found = variables(path)
    assert [v.describe() for v in found] == ["notes, a 1 x 1 cell array"]
    with pytest.raises(ValueError, match="cell.mat: its variable notes, a 1 x 1 cell array; cell arrays"):
        check_variables(path, found)


def test_a_file_without_a_matlab_5_header_is_refused(tmp_path):
    (tmp_path / "text.mat").write_text("not a mat file")
    with pytest.raises(ValueError, match="text.mat is not a MATLAB 5 .mat file"):
        variables(tmp_path / "text.mat")
