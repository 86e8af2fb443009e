"""Module paths that moved: each still imports, with a FutureWarning, and gives the same objects as their new home."""

import importlib
import subprocess
import sys
import warnings
from pathlib import Path

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
    "novelty.datasets.paper": ["paper_a", "paper_a_star", "paper_b", "paper_c", "paper_control", "paper_a_to_a_star",
                               "paper_a_to_b", "paper_a_to_c"],
    "novelty.datasets.inspection": ["inspection", "inspection_easy", "inspection_medium", "inspection_hard"],
    "novelty.datasets.inputs": ["INPUTS", "with_inputs"],
    "novelty.datasets.resampling": ["Resampling", "ResampledTask", "resampled", "ADBENCH", "RESAMPLE", "SCALES",
                                    "TRAINING", "OPTIONS"],
    "novelty.datasets.files": ["Table", "Layout", "read_table", "plan_columns", "read_scans", "files",
                               "smooth_by_distance", "PREPROCESSING"],
    "novelty.datasets.uci": ["uci_wall_following", "uci_wall_following_novelty", "uci_sonar", "uci_sonar_mines",
                             "WALL_FOLLOWING_CLASSES"],
    "novelty.datasets.exploration": ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
                                     "simulate_exploration", "irregular", "returning", "moving"],
    "novelty.datasets.exploration.runs": ["Leg", "simulate_exploration", "from_runs", "exposures", "FAMILIAR"],
    "novelty.datasets.exploration.tasks": ["Leg", "simulate_exploration", "from_runs", "exposures", "paper_tour",
                                           "open_door", "patrol", "FAMILIAR"],
    "novelty.datasets.exploration.objects": ["irregular", "returning", "moving"],
    "novelty.exploration": ["FAMILIAR", "Leg", "exposures", "from_runs", "open_door", "paper_tour", "patrol",
                            "simulate_exploration", "irregular", "returning", "moving"],
    "novelty.sonar.tasks": ["make_task", "TEST_RUN_OFFSET"],
    "novelty.sonar.inspection": ["CorridorPlan", "generate_corridor", "insert_novelties", "inspection_task",
                                 "DIFFICULTIES"],
    "novelty.cli.recording": ["add_recording_options", "recording_rings", "recording_points", "pose_columns",
                              "RowSink", "POINTS_SECTORS"],
}


def _fresh(name):
    """Import ``name`` as a first import would, catching its warnings."""
    for key in [k for k in sys.modules if k == name or k.startswith(name + ".")]:
        if key in MOVED:
            del sys.modules[key]
    parent = name.rpartition(".")[0]
    with warnings.catch_warnings():   # a parent that moved too warns of itself, whether or not it was imported before
        warnings.simplefilter("ignore", FutureWarning)
        importlib.import_module(parent)
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


def test_no_old_path_names_a_module_of_the_package():
    import novelty

    root = Path(novelty.__file__).resolve().parent
    for old in MOVED:
        path = root.joinpath(*old.split(".")[1:])
        assert not path.with_suffix(".py").exists() and not (path / "__init__.py").exists(), old
