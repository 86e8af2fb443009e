"""Detector and task specifications, cells and their ids, and specs read from the command line."""

import pytest

from novelty.bench.specs import Cell, DetectorSpec, SuiteError, TaskSpec, detector_from_text, parse_value


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
