"""Detector and task specifications, cells and their ids, and specs read from the command line."""

import re
import pytest

from novelty.bench.specs import (Cell, DetectorSpec, SuiteError, TaskSpec, detector_from_text, parse_seeds,
                                 parse_value, task_from_text)


def test_cell_ids_are_stable_and_depend_on_what_is_computed():
    a = Cell(DetectorSpec("hsom", {"alpha": 1.2}), TaskSpec("t"), 0)
    b = Cell(DetectorSpec("hsom", {"alpha": 1.2}), TaskSpec("t"), 0)
    assert a.id == b.id
    assert a.id != Cell(DetectorSpec("hsom", {"alpha": 1.3}), TaskSpec("t"), 0).id
    assert a.id != Cell(DetectorSpec("hsom", {"alpha": 1.2}), TaskSpec("t"), 1).id


def test_command_line_specs():
    spec = detector_from_text("habituating clusterer=gwr alpha=1.2 'name=a b'")
    assert spec.name == "habituating"
    assert spec.params == {"clusterer": "gwr", "alpha": 1.2, "name": "a b"}
    assert parse_value("null") is None and parse_value("[1, 2]") == [1, 2] and parse_value("x=y") == "x=y"
    with pytest.raises(SuiteError, match="name=value"):
        detector_from_text("hsom alpha")


@pytest.mark.parametrize("given, seeds", [("3", [0, 1, 2]), ("1", [0]), ("0,1,2", [0, 1, 2]), ("5,", [5]),
                                          ("0,", [0]), (" 2 , 7 ", [2, 7]), (2, [0, 1]), ([4, 1], [4, 1]),
                                          (range(2), [0, 1])])
def test_seeds_are_a_count_or_a_list(given, seeds):
    assert parse_seeds(given) == seeds


@pytest.mark.parametrize("given, message", [
    ("0", "--seeds = 0 is a count of seeds and must be at least 1 (for seed 0 alone, give the list [0]"),
    ("a,b", "--seeds must be a count like 3"), ("-1", "--seeds must be a count like 3"), (",", "count like 3"),
    ([], "non-empty list"), ([1, -2], "non-negative integers; got -2"), ([1, True], "got True"),
    ([3, 3], "names a seed twice"), (1.5, "non-empty list of integers or a count"),
])
def test_zero_or_malformed_seeds_are_refused(given, message):
    with pytest.raises(SuiteError, match=re.escape(message)):
        parse_seeds(given, "--seeds")


def test_a_task_is_named_by_name_or_by_its_file(tmp_path):
    assert task_from_text("inspection-easy n_novelties=1").label == "inspection-easy"
    assert task_from_text("inspection-easy name=easy").label == "easy"
    assert task_from_text("files path=/data/lab-a.csv").label == "lab-a"
    spec = task_from_text("files path=/data/lab-a.csv name=corridor")
    assert spec.label == "corridor" and "name" not in spec.options
    with pytest.raises(SuiteError, match="name= must be a non-empty text"):
        task_from_text("files path=a.csv name=")


def test_a_folder_of_data_files_is_one_files_task_a_file(tmp_path):
    from novelty.bench.specs import tasks_from_text

    for name in ("b.npz", "a.mat", "c.csv", "notes.txt"):
        (tmp_path / name).write_text("")
    tasks = tasks_from_text(f"files path={tmp_path} resample=stratified scale=minmax")
    assert [t.label for t in tasks] == ["a", "b", "c"]
    assert all(t.options["resample"] == "stratified" and t.options["scale"] == "minmax" for t in tasks)
    assert tasks[1].options["path"] == str(tmp_path / "b.npz")
    with pytest.raises(SuiteError, match="one task a file"):
        tasks_from_text(f"files path={tmp_path} name=mine")
    (tmp_path / "empty").mkdir()
    with pytest.raises(SuiteError, match="holds no data file"):
        tasks_from_text(f"files path={tmp_path / 'empty'}")
