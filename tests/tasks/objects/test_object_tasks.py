"""The inspection and exploration tasks of a recording with objects, on the corridor drive."""

import numpy as np
import pytest

from novelty import bench, datasets
from novelty.tasks.objects.casting import cast_all, passes, sightings
from novelty.tasks.objects.object_tasks import exploration_task, familiar_places, inspection_task, object_rings
from novelty.tasks.objects.shapes import Cylinder

from .conftest import corridor_sweeps, drive_poses

#: Beside the path at x = 5, standing from the third leg on (scans 42-83).
BIN = Cylinder("bin", 5.0, 0.6, 0.25, start=42.0)


def expected_sightings():
    sweeps = corridor_sweeps()
    return sightings(cast_all(sweeps, [BIN], within=4.0).shortened)[:, 0]


def test_the_inspection_learns_the_first_part_and_tests_later_scans_with_and_without_the_object(drive_log):
    task = inspection_task(drive_log, [BIN], learn=0.5, sectors=8)
    seen = expected_sightings()
    later = np.arange(84) >= 42
    assert (task.split == "train").sum() == 42 and not seen[:42].any()
    # every later scan retraces the first two legs: all at learned places; the scans that see the bin twice
    n_seen = int(seen[later].sum())
    assert n_seen > 0 and (task.split == "test").sum() == 42 + n_seen
    assert task.y.tolist() == [0] * 42 + seen[later].astype(int).tolist() + [0] * n_seen
    assert task.run.tolist() == [0] * 84 + [1] * n_seen
    assert task.columns["scan"].tolist() == list(range(84)) + np.flatnonzero(seen).tolist()
    # the second run is the same scans as recorded (the log keeps six decimals): the drive without the bin
    recorded = object_rings(corridor_sweeps(), 8)
    assert np.allclose(task.X[84:], recorded[seen], atol=1e-5)
    assert not np.allclose(task.X[42:84][seen[later]], recorded[seen], atol=1e-5)
    assert task.metadata["objects"][0]["name"] == "bin"


def test_the_exploration_counts_the_robots_passes_as_exposures(drive_log):
    task = exploration_task(drive_log, [BIN], warmup=0.5, run_scans=21, sectors=8)
    seen = expected_sightings()
    k = passes(seen, drive_poses(), BIN, 4.0)
    assert task.metadata["exploration"]["warmup_runs"] == 2 and task.run.tolist() == np.repeat(range(4), 21).tolist()
    assert task.columns["feature"].tolist() == np.where(seen, "bin", "").tolist()
    assert task.columns["exposure"].tolist() == k.tolist() and set(k[seen].tolist()) == {0, 1}
    assert task.y.tolist() == (k == 0).astype(int).tolist()


def test_objects_that_stand_in_the_learned_part_are_refused(drive_log):
    with pytest.raises(ValueError, match=r"appear before t=42.00 s, in the part the robot learns"):
        inspection_task(drive_log, [Cylinder("bin", 5.0, 0.6, 0.25, start=10.0)])
    with pytest.raises(ValueError, match="on the robot's path"):
        inspection_task(drive_log, [Cylinder("bin", 5.0, 0.2, 0.25, start=42.0)])


def test_registered_tasks_take_a_file_of_objects(drive_log, tmp_path):
    objects = tmp_path / "objects.csv"
    objects.write_text("kind,name,x,y,radius,start\ncylinder,bin,5,0.6,0.25,42\n")
    task = datasets.load("inspection-objects", path=str(drive_log), objects=str(objects), sectors=8)
    assert task.y.sum() == expected_sightings()[42:].sum()


def test_several_scales_sit_side_by_side():
    sweeps = corridor_sweeps()[:3]
    both = object_rings(sweeps, [4, 8])
    assert both.shape == (3, 12)
    assert np.array_equal(both[:, :4], object_rings(sweeps, 4)) and np.array_equal(both[:, 4:], object_rings(sweeps, 8))
    with pytest.raises(ValueError, match="sectors must be an int >= 1"):
        object_rings(sweeps, [4, 0])


def test_familiar_places_need_the_place_and_the_heading():
    known = [[0.0, 0.0, 0.0]]
    assert familiar_places([[0.9, 0.0, 0.1], [0.9, 0.0, 3.0], [1.1, 0.0, 0.0]], known).tolist() == [True, False,
                                                                                                     False]


def test_a_users_recording_is_benchmarked_by_name_as_the_command_line_gives_it(drive_log, tmp_path):
    objects = tmp_path / "objects.toml"
    objects.write_text('[[objects]]\nkind = "cylinder"\nname = "bin"\nx = 5.0\ny = 0.6\nradius = 0.25\nstart = 42\n')
    results = bench.run(["nearest-memory"], f"inspection-objects path={drive_log} objects={objects} sectors=8")
    row = results.rows[0]
    assert row["status"] == "ok" and row["n_novel"] == expected_sightings()[42:].sum() and row["roc_auc"] > 0.5


def test_a_suite_beside_its_recording_runs_from_anywhere(drive_log, tmp_path, monkeypatch):
    from novelty.bench import load_suite
    from novelty.bench.runner import run_bench

    (tmp_path / "objects.csv").write_text("kind,name,x,y,radius,start\ncylinder,bin,5.0,0.6,0.25,42\n")
    suite_path = tmp_path / "suite.toml"
    suite_path.write_text(f"""
[suite]
seeds = 1

[[detectors]]
name = "nearest-memory"

[[tasks]]
name = "inspection-objects"
options = {{ path = "{drive_log.name}", objects = "objects.csv", sectors = 8 }}
""")
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")      # the files are the suite's, wherever it is run from
    (row,) = run_bench(load_suite(suite_path), tmp_path / "out", plots=False, quiet=True).rows
    assert row["status"] == "ok" and row["n_novel"] == expected_sightings()[42:].sum()


#: Beyond the reach (4 m) of the first eight scans (x 0 to 3.5, facing +x): a place not seen by then.
FAR = Cylinder("far", 9.0, -0.6, 0.25, start=8.0)
#: In reach of them: a place seen by then.
NEAR = Cylinder("near", 5.0, 0.6, 0.25, start=8.0)


def test_the_inspection_says_per_scan_whether_the_objects_place_was_learned(drive_log):
    task = inspection_task(drive_log, [NEAR, FAR], learn=8 / 84, places=True, sectors=8)
    objects = {o["name"]: o for o in task.metadata["objects"]}
    assert objects["near"]["seen_place"] and objects["near"]["place_looks"] > 0
    assert not objects["far"]["seen_place"] and objects["far"]["place_looks"] == 0
    seen_place, names = task.columns["seen_place"], task.columns["object"]
    assert {"near", "far"} <= set(names.tolist())
    assert seen_place.tolist() == (names == "near").tolist()   # familiar scans: no object, no place
    assert "seen_place" in task.metadata["labels"]
    # unasked, a task is as it was: no column, nothing in the metadata
    plain = inspection_task(drive_log, [NEAR, FAR], learn=8 / 84, sectors=8)
    assert "seen_place" not in plain.columns and "seen_place" not in plain.metadata["labels"]
    assert "place_looks" not in plain.metadata["objects"][0]


def test_the_exploration_counts_the_scans_before_each_object_appears(drive_log):
    task = exploration_task(drive_log, [NEAR, FAR], warmup=0.1, run_scans=4, min_passes=1, places=True,
                            sectors=8)
    objects = {o["name"]: o for o in task.metadata["objects"]}
    assert objects["near"]["seen_place"] and not objects["far"]["seen_place"]
    assert task.columns["seen_place"].tolist() == (task.columns["object"] == "near").tolist()


def test_drawn_objects_in_unseen_places_were_never_looked_at(drive_log):
    task = inspection_task(drive_log, learn=8 / 84, n_objects=1, seed=0, unseen_places=True, sectors=8)
    assert [o["place_looks"] for o in task.metadata["objects"]] == [0]
    assert not task.columns["seen_place"].any() and task.y.any()
    with pytest.raises(ValueError, match="unseen_places draws the objects"):
        inspection_task(drive_log, [FAR], learn=8 / 84, unseen_places=True)
    with pytest.raises(ValueError, match="An unseen place was looked at 0 times"):
        exploration_task(drive_log, warmup=0.5, run_scans=4, seen_before=1, unseen_places=True)
