"""Which column of a file is what: sensors by name, index or pattern; one clear error for a bad choice."""

import pytest

from novelty.io.tables.columns import plan_columns


@pytest.mark.parametrize("columns, expected", [
    ("b", ["b"]), ([2, 1], ["b", "a"]), ("1,2", ["a", "b"]), ("[ab]", ["a", "b"]), (["a", "a"], ["a"]),
])
def test_columns_by_name_index_and_pattern(columns, expected):
    layout = plan_columns(["t", "a", "b", "novel"], columns, label="novel", time="t")
    assert layout.sensor_names == expected


@pytest.mark.parametrize("kwargs, message", [
    (dict(columns="z"), r"columns: no column 'z'; the file has t, a, b, novel"),
    (dict(columns=7), r"column index 7 is out of range; the file has 4 columns \(0 to 3\)"),
    (dict(columns="a,t", time="t"), r"'t' is the label, time, distance, run or split column"),
    (dict(label="[ab]"), r"label: '\[ab\]' names 2 columns; expected one"),
])
def test_bad_column_choices_say_what_is_wrong(kwargs, message):
    with pytest.raises(ValueError, match=message):
        plan_columns(["t", "a", "b", "novel"], **kwargs)


def test_a_file_of_the_points_input_keeps_its_y_as_an_input():
    names = ["x", "y", "heading", "near_0", "near_1", "x_0", "x_1", "y_0", "y_1"]
    layout = plan_columns(names)
    assert layout.sensor_names == names and layout.label is None      # y is the robot's position
    labelled = plan_columns([*names, "label"])
    assert labelled.sensor_names == names and labelled.names[labelled.label] == "label"
    other = plan_columns(["x", "y", "heading", "near_0"])   # any other file keeps the rule: y is the label
    assert other.names[other.label] == "y"


def test_novelty_run_reads_a_file_of_points_rows_as_the_map_reads_them(tmp_path, capsys):
    import csv
    import io

    import numpy as np

    import novelty
    from novelty.cli import main
    from novelty.maps import points_columns, ring_points

    rng = np.random.default_rng(0)
    bearings = np.linspace(-np.pi, np.pi, 8, endpoint=False)
    poses = np.c_[np.linspace(0.0, 4.0, 12), np.zeros(12), np.zeros(12)]
    rows = ring_points(rng.uniform(0.0, 0.9, (12, 8)), poses, bearings, threshold=4.0)
    path = tmp_path / "points.csv"
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(points_columns(8))
        writer.writerows(rows.tolist())
    assert main(["run", "map-explore", "--data", str(path)]) == 0
    got = [float(r["novelty"]) for r in csv.DictReader(io.StringIO(capsys.readouterr().out))]
    det = novelty.make("map-explore")
    assert got == [float(f"{det.score_learn_one(r):.10g}") for r in rows]
