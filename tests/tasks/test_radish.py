"""The tasks of the Radish logs: found from path= or $NOVELTY_DATA_DIR, labelled from the poses; their objects tasks."""

import numpy as np
import pytest

from novelty import datasets
from novelty.tasks.objects.placement import object_from_fields
from novelty.tasks.places import place_visits
from novelty.tasks.radish import RADISH_FOLDER, radish_exploration, radish_intel


def test_without_the_logs_the_error_says_where_to_put_them(tmp_path, monkeypatch):
    monkeypatch.delenv("NOVELTY_DATA_DIR", raising=False)
    with pytest.raises(FileNotFoundError, match="NOVELTY_DATA_DIR.*radish-carmen-logs/intel-corrected.log.gz"):
        radish_intel()
    with pytest.raises(FileNotFoundError, match="looked for"):
        radish_intel(path=tmp_path)
    with pytest.raises(ValueError, match="Unknown Radish log 'mit'; expected one of intel, aces, csail"):
        radish_exploration("mit", path=tmp_path)


def test_each_log_is_a_registered_task():
    for log in ("intel", "aces", "csail"):
        assert "Radish log" in datasets.available()[f"exploration-radish-{log}"]


def test_the_suite_finds_a_log_through_novelty_data_dir(radish, monkeypatch):
    monkeypatch.setenv("NOVELTY_DATA_DIR", str(radish.parent))
    assert radish.name == RADISH_FOLDER
    task = datasets.load("exploration-radish-aces")
    assert task.name == "exploration-radish-aces" and task.X.shape == (440, 16)
    np.testing.assert_array_equal(task.X, datasets.load("exploration-radish-aces", path=radish, seed=3).X)


def test_the_labels_are_the_places_and_visits_of_the_poses(radish):
    task = radish_exploration("aces", path=radish)
    poses, place, run = task.poses, task.columns["place"], task.run
    assert run.tolist() == [0] * 100 + [1] * 100 + [2] * 100 + [3] * 140
    founders = np.array([np.flatnonzero(place == k)[0] for k in range(place.max() + 1)])
    # every scan within 1 m of its place's founding pose; founders more than 1 m from every earlier founder
    assert np.all(np.hypot(*(poses[:, :2] - poses[founders[place], :2]).T) <= 1.0)
    gaps = np.hypot(*(poses[founders, None, :2] - poses[None, founders, :2]).T)
    assert np.all(gaps[np.triu_indices(len(founders), 1)] > 1.0)
    # familiar: the places founded in the warm-up; tracked: the rest, exposed once a visit
    familiar = founders[place] < 100
    assert np.array_equal(task.columns["feature"] == "", familiar)
    visits = place_visits(poses, place, founders, leave=2.0)
    np.testing.assert_array_equal(task.columns["exposure"], np.where(familiar, -1, visits))
    np.testing.assert_array_equal(task.y, task.columns["exposure"] == 0)
    assert task.metadata["places"]["n_places"] == len(founders)


# ------------------------------------------------------------------ objects
def test_the_csail_inspection_draws_objects_that_the_robot_sees_after_learning_the_first_half(radish):
    # one object (the registered task draws four, a second and a half more of CPU time)
    task = datasets.load("inspection-objects-radish-csail", path=radish, seed=0, n_objects=1)
    objects = [object_from_fields(o) for o in task.metadata["objects"]]
    assert len(objects) == 1 and {type(o).__name__ for o in objects} <= {"Box", "Cylinder"}
    assert all(0.3 <= (2 * o.radius if hasattr(o, "radius") else max(o.length, o.width)) <= 1.0 for o in objects)
    train, test = task.split == "train", task.split == "test"
    assert train.sum() == 203 and task.metadata["n_recorded_scans"] == 406     # half of the 406 scans
    # the scans that see an object, then the same scans as recorded: as many of each
    twins = test & (task.run == 1)
    assert task.y[test & (task.run == 0)].sum() == twins.sum() > 0 and task.y[twins].sum() == 0
    assert np.array_equal(task.columns["scan"][task.y == 1], task.columns["scan"][twins])
    assert set(task.columns["object"][task.y == 1]) <= {o.name for o in objects}
