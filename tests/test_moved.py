"""Module paths that moved: each still imports, with a FutureWarning, and gives the same objects as their new home."""

import importlib
import subprocess
import sys
import warnings

import pytest

from novelty._moved import MOVED, MovedModule

#: the public names each old path held before its names moved (the readers and tasks by layer)
OLD_NAMES = {
    "novelty.io.sweeps": ["Sweep", "read_sweeps", "sweep_ring", "RingMaker", "scan_sweep", "bag_scan_topics",
                          "mount_options", "reading_given", "CARMEN_SUFFIXES", "CARMEN_LASERS", "LASER_TYPES"],
    "novelty.io.scans": ["clean_ranges", "sector_index", "scan_limits", "all_round", "reduce_sectors", "laser_ring",
                         "REDUCTIONS", "SNAP"],
    "novelty.io.recording": ["Ring", "read_rings", "read_recording", "is_recording", "CARMEN_SUFFIXES",
                             "CARMEN_LASERS"],
    "novelty.io.carmen": ["CarmenLog", "CarmenError", "read_carmen", "CARMEN_MESSAGES", "MAX_LINE"],
    "novelty.io.messages": ["LaserScan", "RangeReading", "Pose", "Transform", "Sweep"],
    "novelty.io.rosbag": ["BagError", "Bag", "bag_topics", "topic_types", "topic_counts", "read_bag", "bag_messages",
                          "converted", "SUPPORTED_TYPES", "SCAN_TYPES", "POSE_TYPES", "TF_TYPES", "BAG_SUFFIXES",
                          "is_bag"],
    "novelty.io.tasks": ["Mark", "read_marks", "mark_features", "place_features", "split_runs", "visit_counts",
                         "recording_task"],
    "novelty.io.objects": ["Box", "Cylinder", "Wall", "SHAPES", "Injection", "inject", "beam_ranges", "cone_range",
                           "world_beams", "Cast", "cast_all", "sightings", "passes", "read_objects", "refusals",
                           "check_objects", "draw_objects", "inspection_task", "exploration_task", "object_rings"],
    "novelty.io.objects.tasks": ["object_rings", "object_inputs", "INPUTS", "read_drive", "inspection_task",
                                 "exploration_task", "familiar_places", "LABEL_DEFAULTS"],
    "novelty.io.objects.radish": ["radish_objects_inspection", "radish_objects_exploration", "SETTINGS",
                                  "inspection_objects_intel", "exploration_objects_csail"],
    "novelty.io.objects.points": ["sweep_points", "points_columns"],
    "novelty.maps.points": ["POSE_COLUMNS", "points_columns", "split_points", "check_points", "ring_points"],
    "novelty.datasets.tables": ["Table", "header_of", "read_table", "bounded_lines", "csv_rows", "check_data_file",
                                "MAX_LINE_CHARS", "MAX_COLUMNS", "MAX_NPZ_BYTES"],
    "novelty.datasets.columns": ["Layout", "plan_columns", "is_ros_export", "is_points_file", "LABEL_COLUMNS",
                                 "TIME_COLUMNS", "ROUTE_COLUMNS", "TEXT_COLUMNS", "cell_text"],
    "novelty.datasets._files": ["DATA_DIR_ENV", "resolve_data_file", "read_rows"],
    "novelty.datasets.labels": ["check_labels", "check_both_classes", "SKLEARN_CONVERSION"],
    "novelty.datasets.smoothing": ["smooth_by_distance"],
}


def _fresh(name):
    """Import ``name`` as a first import would, catching its warnings."""
    for key in [k for k in sys.modules if k == name or k.startswith(name + ".")]:
        if key in MOVED:
            del sys.modules[key]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(name)
    return module, [w for w in caught if issubclass(w.category, FutureWarning)]


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_imports_with_a_future_warning_naming_the_new_homes(old):
    module, warned = _fresh(old)
    assert isinstance(module, MovedModule)
    assert len(warned) == 1 and old in str(warned[0].message)
    assert all(new in str(warned[0].message) for new in MOVED[old])
    for new in MOVED[old]:
        importlib.import_module(new)   # every new home exists


@pytest.mark.parametrize("old", sorted(OLD_NAMES))
def test_the_names_an_old_path_held_are_the_same_objects_there(old):
    module, _ = _fresh(old)
    for name in OLD_NAMES[old]:
        found = [getattr(importlib.import_module(new), name) for new in MOVED.get(old, ())
                 if hasattr(importlib.import_module(new), name)]
        assert getattr(module, name) is (found[0] if found else getattr(module, name)), (old, name)


def test_a_name_set_on_an_old_path_is_set_at_its_new_home():
    module, _ = _fresh("novelty.io.caps")
    from novelty.io.ros import caps

    before = caps.MAX_BEAMS
    try:
        module.MAX_BEAMS = 7
        assert caps.MAX_BEAMS == 7 and module.MAX_BEAMS == 7
    finally:
        caps.MAX_BEAMS = before


def test_a_name_no_module_holds_is_an_attribute_error_naming_the_new_homes():
    module, _ = _fresh("novelty.io.sweeps")
    with pytest.raises(AttributeError, match=r"has no attribute 'nothing' \(its names moved to novelty.io.scans"):
        _ = module.nothing


def test_the_warning_points_at_the_code_that_imports():
    code = "import warnings; warnings.simplefilter('always'); import novelty.io.tf"
    err = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stderr
    assert err.startswith("<string>:1: FutureWarning: novelty.io.tf is deprecated"), err


def test_a_module_that_exists_is_never_shadowed():
    assert not any(importlib.util.find_spec(old.rpartition(".")[0]) is None for old in MOVED)
    for old in MOVED:
        parent = importlib.import_module(old.rpartition(".")[0])
        assert not (hasattr(parent, "__path__") and any(
            (p / (old.rpartition(".")[2] + ".py")).exists() for p in map(__import__("pathlib").Path,
                                                                          parent.__path__))), old
