"""The task of the user's own files: its training and test parts, by rows, by a column or by a second file."""

import numpy as np
import pytest

from novelty.datasets import load
from novelty.datasets.files import files

from ..io.tables.test_scan_file import six_scans, write


@pytest.fixture
def table(tmp_path):
    return six_scans(tmp_path)


def test_the_files_task_splits_by_rows_count_and_fraction(table):
    task = files(table, columns="a,b", label="novel", time="t", train_rows=4)
    assert task.split.tolist() == ["train"] * 4 + ["test"] * 2 and task.train_passes == 1
    assert files(table, columns="a,b", label="novel", train_rows=0.5).split.tolist().count("train") == 3


def test_the_files_task_splits_by_a_column_and_by_a_second_file(tmp_path):
    path = write(tmp_path, "a,phase,y\n1,train,0\n2,train,0\n3,test,1\n4,test,0\n")
    task = files(path, split="phase")
    assert task.split.tolist() == ["train", "train", "test", "test"]
    np.testing.assert_array_equal(task.test().y, [1, 0])
    train = write(tmp_path, "a\n1\n2\n", "train.csv")  # no labels: learned scans are familiar
    test = write(tmp_path, "a,y\n3,1\n4,0\n", "test.csv")
    task = files(train, test_path=test)
    np.testing.assert_array_equal(task.X.ravel(), [1, 2, 3, 4])
    np.testing.assert_array_equal(task.y, [0, 0, 1, 0])


@pytest.mark.parametrize("kwargs, message", [
    (dict(train_rows=3, split="phase"), "one way to split the scans into training and test; got split and train_rows"),
    (dict(), "how are the scans split"),
    (dict(train_rows=6), r"1 to 5 of 6; got 6"),
    (dict(train_rows=1.5), r"fraction must lie in \(0, 1\)"),
    (dict(train_rows=3, label=None, columns="a,b,novel"), "the test scans need labels"),
    (dict(train_rows=3, preprocess="log"), "preprocess must be one of none, paper; got 'log'"),
])
def test_the_files_task_refuses_what_it_cannot_split(table, kwargs, message):
    options = dict(columns="a,b", label="novel", time="t") | kwargs
    with pytest.raises(ValueError, match=message):
        files(table, **options)


def test_the_files_task_is_registered(table):
    task = load("files", path=str(table), columns="a,b", label="novel", train_rows=4)
    assert task.name == "files" and len(task.train()) == 4


# -------------------------------------------------- where a bad cell is, and what it holds
BAD_CELLS = "us01,us05,y\n0.1,0.2,0\n\n0.3,{cell},1\n"  # the bad cell is on line 4 (a blank line 3)


