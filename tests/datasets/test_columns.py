"""Which column of a file is what: sensors by name, index or pattern; one clear error for a bad choice."""

import pytest

from novelty.datasets.columns import plan_columns


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
