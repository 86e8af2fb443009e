"""novelty.bench.run: names, objects, task objects and arrays benchmarked without registering anything."""

import numpy as np
import pytest

import novelty
from novelty import bench
from novelty.bench import SuiteError
from novelty.exploration import from_runs


def _arrays(seed=0):
    rng = np.random.default_rng(seed)
    X_train, X_test = rng.random((120, 5)), rng.random((60, 5))
    X_test[:15] += 0.8
    return X_train, X_test, np.r_[np.ones(15), np.zeros(45)]


def test_an_array_task_and_a_detector_object_without_registering():
    results = bench.run({"kmeans": "kmeans-stanley", "parzen": novelty.make("parzen")},
                        {"mine": _arrays()}, seeds=2)
    assert results.tasks == ["mine"] and len(results.rows) == 4
    assert {r["detector"] for r in results.rows} == {"kmeans", "parzen"}
    assert all(r["status"] == "ok" for r in results.rows)
    assert results.per_task.n_seeds.tolist() == [[2], [2]]
    assert "## Comparison on one task: mine" in results.summary   # one task: the bootstrap, unasked
    records = results.compare_on_task("mine", reference="parzen", resamples=100)
    assert records[0]["detector"] == "kmeans" and records[0]["roc_auc"].resamples == 100


def test_a_from_runs_task_under_the_exploration_protocol():
    rng = np.random.default_rng(0)
    runs = [rng.random((30, 4)) for _ in range(4)]
    for r in runs[1:]:
        r[20:] += 0.7
    task = from_runs(runs, [[None] * 30] + [[None] * 20 + ["box"] * 10] * 3, name="box-room")
    results = bench.run(["parzen"], task, protocol="exploration")
    (row,) = results.rows
    assert row["status"] == "ok" and row["task"] == "box-room" and row["first_encounter_auc"] > 0.9
    assert "| parzen (frozen)" in results.table


def test_task_objects_change_their_cells_ids_with_their_data(tmp_path):
    a = bench.run("parzen", {"t": _arrays(0)}, out=tmp_path / "a", plots=False)
    b = bench.run("parzen", {"t": _arrays(1)}, out=tmp_path / "b", plots=False)
    assert a.rows[0]["cell_id"] != b.rows[0]["cell_id"]
    assert (tmp_path / "a" / "summary.md").exists()


def test_what_is_not_a_task_or_a_detector_is_refused():
    with pytest.raises(SuiteError, match="a tuple task is"):
        bench.run("parzen", {"t": (np.zeros((3, 2)), np.zeros((2, 2)))})
    with pytest.raises(SuiteError, match="A detector must be"):
        bench.run([3.5], {"t": _arrays()})
    with pytest.raises(SuiteError, match="Two tasks are named 't'"):
        bench.run("parzen", [bench.TaskSpec("inspection-easy", label="t"), bench.TaskSpec("paper-a", label="t")])
