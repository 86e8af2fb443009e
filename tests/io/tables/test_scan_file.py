"""Scans and tasks from the user's own files: columns, labels, timestamps, splits, preprocessing."""

import numpy as np
import pytest

from novelty.data import Dataset
from novelty.datasets.files import files, read_scans, smooth_by_distance

ROS_HEADER = ("%time,field.header.seq,field.header.stamp,field.header.frame_id,field.angle_min,"
              "field.ranges0,field.ranges1,field.ranges2")
ROS_ROWS = [
    "1700000000000000000,1,1700000000050000000,laser,-1.5,1.0,2.0,inf",
    "1700000000100000000,2,1700000000150000000,laser,-1.5,0.5,3.0,5.0",
    "1700000000200000000,3,1700000000250000000,laser,-1.5,4.0,2.5,0.0",
]


def write(tmp_path, text: str, name: str = "scans.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture
def ros(tmp_path):
    return write(tmp_path, "\n".join([ROS_HEADER, *ROS_ROWS]) + "\n", "scan.csv")


def six_scans(tmp_path):
    """Six scans: two sensors, a time column, labels, a text column."""
    rows = ["t,a,b,novel,note"] + [f"{i * 0.5},{i},{10 * i},{int(i in (3, 5))},n{i}" for i in range(6)]
    return write(tmp_path, "\n".join(rows) + "\n")


@pytest.fixture
def table(tmp_path):
    return six_scans(tmp_path)


def test_default_columns_leave_out_label_time_distance_run_split_and_exports(tmp_path):
    path = write(tmp_path, "s0,y,distance,run,split,time,features,s1\n1,0,0.1,0,train,5,,2\n3,1,0.2,0,test,6,f,4\n")
    data = read_scans(path)
    assert data.metadata["sensor_columns"] == ["s0", "s1"]
    np.testing.assert_array_equal(data.X, [[1, 2], [3, 4]])
    np.testing.assert_array_equal(data.y, [0, 1])
    np.testing.assert_array_equal(data.columns["time"], [5, 6])
    assert data.split.tolist() == ["train", "test"] and data.run.tolist() == [0, 0]


def test_a_text_column_is_refused_by_name_unless_columns_are_chosen(table):
    with pytest.raises(ValueError, match=r"line 2, column 'note': expected a number, got text 'n0'; "
                                         r"choose the sensor columns"):
        read_scans(table, label="novel", time="t")
    data = read_scans(table, columns="a,b", label="novel", time="t")
    np.testing.assert_array_equal(data.X[:, 1], [0, 10, 20, 30, 40, 50])
    np.testing.assert_array_equal(data.y, [0, 0, 0, 1, 0, 1])
    np.testing.assert_array_equal(data.columns["time"], np.arange(6) * 0.5)


def test_a_ros_export_needs_its_sensor_columns_chosen(ros):
    with pytest.raises(ValueError, match=r"ROS 'rostopic echo -p' export.*e\.g\. 'field\.ranges\*'"):
        read_scans(ros)
    with pytest.raises(ValueError, match=r"line 2, column 'field.header.frame_id': expected a number, got text 'laser'; "
                                         r"choose the sensor columns with columns= \(--columns\), e\.g\. 'field\.ranges\*'\."):
        read_scans(ros, columns="field.header.frame_id")


def test_a_ros_export_reads_ranges_with_the_header_stamp_in_seconds(ros):
    data = read_scans(ros, columns="field.ranges*", preprocess="paper")
    assert data.metadata["sensor_columns"] == ["field.ranges0", "field.ranges1", "field.ranges2"]
    assert data.metadata["time_column"] == "field.header.stamp"
    # 1 - min(r, 4) / 4, inf (no echo) to 0
    np.testing.assert_array_equal(data.X, [[0.75, 0.5, 0.0], [0.875, 0.25, 0.0], [0.0, 0.375, 1.0]])
    np.testing.assert_allclose(np.diff(data.columns["time"]), [0.1, 0.1], atol=1e-6)
    assert data.columns["time"][0] == pytest.approx(1700000000.05)


def test_inf_ranges_need_the_paper_preprocessing(ros):
    with pytest.raises(ValueError, match=r"line 2, column 'field.ranges2': expected a finite number, got inf "
                                         r"\(preprocess='paper' reads inf as no echo\)\."):
        read_scans(ros, columns="field.ranges*")


def test_a_headerless_csv_names_its_columns_s0_s1(tmp_path):
    data = read_scans(write(tmp_path, "1,2,3\n4,5,6\n"), columns="s0,s2")
    np.testing.assert_array_equal(data.X, [[1, 3], [4, 6]])


def test_an_npz_export_reads_back(tmp_path):
    source = Dataset("d", np.arange(12.0).reshape(4, 3), y=[0, 0, 1, 0], split=["train"] * 2 + ["test"] * 2,
                     distance=[0.0, 0.1, 0.2, 0.3], columns={"time": np.array([1.0, 2, 3, 4])})
    source.to_npz(tmp_path / "d.npz")
    data = read_scans(tmp_path / "d.npz", columns="s1,s2")
    np.testing.assert_array_equal(data.X, source.X[:, 1:])
    np.testing.assert_array_equal(data.y, source.y)
    np.testing.assert_array_equal(data.columns["time"], [1, 2, 3, 4])
    assert data.split.tolist() == source.split.tolist()


def test_smoothing_averages_each_bin_of_travel_within_a_run():
    data = Dataset("d", [[1.0], [3.0], [5.0], [7.0], [9.0]], y=[0, 1, 0, 0, 0],
                   distance=[0.00, 0.05, 0.12, 0.00, 0.04], run=[0, 0, 0, 1, 1],
                   columns={"time": np.array([1.0, 2, 3, 4, 5])})
    smooth = smooth_by_distance(data, 0.1)
    np.testing.assert_array_equal(smooth.X.ravel(), [2.0, 5.0, 8.0])
    np.testing.assert_allclose(smooth.distance, [0.025, 0.12, 0.02])
    assert smooth.y.tolist() == [1, 0, 0] and smooth.run.tolist() == [0, 0, 1]
    assert smooth.columns["time"].tolist() == [2.0, 3.0, 5.0]  # the moment each is presented


def test_a_first_row_with_one_bad_cell_is_not_taken_as_a_header(tmp_path):
    path = tmp_path / "scans.csv"
    path.write_text("0.1,abc,0.3\n0.2,0.5,0.6\n0.3,0.4,0.1\n")
    with pytest.raises(ValueError, match=rf"{path}, line 1: column 2 holds 'abc', which is not a number"):
        read_scans(path)


@pytest.mark.parametrize("first_row", ["s0,s1,s2", ",0,1", "time,0,1"])  # pandas writes the last two
def test_a_header_is_still_a_header(tmp_path, first_row):
    path = tmp_path / "scans.csv"
    path.write_text(f"{first_row}\n0.2,0.5,0.6\n0.3,0.4,0.1\n")
    assert len(read_scans(path, columns=[1, 2]).X) == 2


def test_a_file_that_is_not_utf8_is_named(tmp_path):
    path = tmp_path / "scans.csv"
    path.write_bytes(b"s0,s1\n0.1,0.2\n0.3,\xff\n")
    with pytest.raises(ValueError, match=rf"{path} is not UTF-8 text \(invalid start byte\)"):
        read_scans(path)


# -------------------------------------------------- where a bad cell is, and what it holds
BAD_CELLS = "us01,us05,y\n0.1,0.2,0\n\n0.3,{cell},1\n"  # the bad cell is on line 4 (a blank line 3)


@pytest.mark.parametrize("cell, options, got", [
    ("n/a", {}, r"expected a number, got text 'n/a'; choose the sensor columns"),
    ("", {}, r"expected a number, got an empty cell; choose the sensor columns"),
    ("nan", {}, r"expected a finite number, got nan\.$"),
    ("nan", {"preprocess": "paper"}, r"expected a range in metres \(inf for no echo\), got nan\.$"),
])
def test_a_bad_sensor_cell_is_named_by_line_and_column(tmp_path, cell, options, got):
    path = write(tmp_path, BAD_CELLS.format(cell=cell))
    with pytest.raises(ValueError, match=rf"^{path}, line 4, column 'us05': {got}"):
        read_scans(path, **options)


def test_a_nan_reading_does_not_mention_an_option_not_in_use(tmp_path):
    with pytest.raises(ValueError) as error:
        read_scans(write(tmp_path, BAD_CELLS.format(cell="nan")))
    assert "preprocess" not in str(error.value)


@pytest.mark.parametrize("cell, got", [("", "an empty cell"), ("x", "text 'x'"), ("nan", "nan")])
def test_a_bad_label_cell_is_named_by_line_and_column(tmp_path, cell, got):
    path = write(tmp_path, f"a,y\n0.1,0\n0.2,{cell}\n")
    with pytest.raises(ValueError, match=rf"^{path}, line 3, column 'y' \(the label\): expected a "
                                         rf"(finite )?number, got {got}\.$"):
        read_scans(path)


def test_a_bad_split_cell_is_named_by_line_and_column(tmp_path):
    path = write(tmp_path, "a,y,split\n0.1,0,train\n0.2,1,tset\n")
    with pytest.raises(ValueError, match=rf"^{path}, line 3, column 'split': expected 'train' or 'test', "
                                         r"got text 'tset'\.$"):
        read_scans(path)


def test_a_bad_cell_of_an_npz_file_is_named_by_row_and_column(tmp_path):
    X = np.array([[0.1, 0.2], [0.3, np.nan], [0.5, 0.6]])
    np.savez(tmp_path / "d.npz", X=X, y=np.array([0, 1, 0]))
    with pytest.raises(ValueError, match=r"d\.npz, row 1, column 's1': expected a finite number, got nan\."):
        read_scans(tmp_path / "d.npz")


@pytest.mark.parametrize("labels, message", [
    (["0", "1", "nan", "0"], r"scans.csv, line 4, column 'y' \(the label\): expected a finite number, got nan"),
    (["1", "-1", "1", "1"], r"scans.csv, line 3, column 'y' \(the label\): the labels are -1 and \+1, scikit-learn's"),
    (["0", "0.5", "1", "0"], r"scans.csv, line 3, column 'y' \(the label\): expected a label 0 \(normal\) or 1 \(novel\), got 0.5"),
])
def test_a_label_column_of_other_values_is_refused_by_line(tmp_path, labels, message):
    # before: y != 0 made NaN and -1 novel, and 0.5 novel too
    path = write(tmp_path, "a,y\n" + "".join(f"{i},{v}\n" for i, v in enumerate(labels)))
    with pytest.raises(ValueError, match=message):
        files(path, train_rows=2)
