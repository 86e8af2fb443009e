"""novelty.bench.run: names, objects, task objects and arrays benchmarked without registering anything."""

import gc
import warnings

import numpy as np
import pytest

import novelty
from novelty import bench
from novelty.bench import SuiteError
from novelty.tasks.exploration import from_runs


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


# ---------------------------------------------------------------- other libraries' detectors, as they are
class _Centroid(novelty.detector.OutlierMixin, __import__("sklearn").base.BaseEstimator):
    """An ordinary scikit-learn outlier estimator (a BaseEstimator without parameter constraints)."""

    def __init__(self, power=2):
        self.power = power

    def fit(self, X, y=None):
        self.centre_ = np.mean(X, axis=0)
        return self

    def score_samples(self, X):
        return -np.sum(np.abs(X - self.centre_) ** self.power, axis=1)


def test_a_scikit_learn_estimator_and_a_pyod_detector_are_taken_as_they_are():
    pytest.importorskip("pyod")
    from pyod.models.knn import KNN
    from sklearn.ensemble import IsolationForest

    results = bench.run([_Centroid(), IsolationForest(n_estimators=50, random_state=0), KNN(n_neighbors=5)], {"mine": _arrays()})
    assert {r["detector"]: r["status"] for r in results.rows} == {"_Centroid": "ok", "IsolationForest": "ok",
                                                                 "KNN": "ok"}
    assert all(r["roc_auc"] > 0.9 for r in results.rows)
    with pytest.raises(SuiteError, match="not an outlier detector"):
        bench.run([__import__("sklearn").linear_model.LinearRegression()], {"mine": _arrays()})


# ---------------------------------------------------------------- a folder of benchmark files, a protocol per seed
def _benchmark_folder(folder):
    """ADBench's format (X, y in an .npz) and ODDS's (X, y in a MATLAB .mat) from the shared UCI data."""
    import os
    from pathlib import Path

    from scipy.io import savemat

    shared = Path(os.environ.get("NOVELTY_DATA_DIR") or Path(__file__).resolve().parents[2].parent / "shared"
                  / "datasets")
    if not (shared / "sonar-mines-vs-rocks").is_dir() or not (shared / "wall-following-robot-navigation").is_dir():
        pytest.skip(f"the shared UCI data is not in {shared}")
    sonar = novelty.datasets.load("uci-sonar", path=shared)
    np.savez(folder / "1_sonar.npz", X=sonar.X, y=(sonar.columns["class"] == "M").astype(int)[:, None].ravel())
    walls = novelty.datasets.load("uci-wall-following", path=shared, normalise=False)
    turns = np.isin(walls.columns["class"], ["Sharp-Right-Turn", "Slight-Left-Turn"])
    keep = np.flatnonzero(~turns)[:900].tolist() + np.flatnonzero(turns)[:100].tolist()   # anomalies last
    savemat(folder / "2_walls.mat", {"X": walls.X[keep], "y": turns[keep].astype(float)[:, None]})
    (folder / "notes.txt").write_text("not a data file")
    return folder


ADBENCH = "resample=stratified test=0.3 min_rows=1000 max_rows=10000 scale=minmax training=contaminated"


def test_a_folder_of_benchmark_files_is_a_suite_drawn_per_seed_by_the_protocol(tmp_path):
    folder = _benchmark_folder(tmp_path)
    results = bench.run(["lof"], f"files path={folder} {ADBENCH}", seeds=2)
    assert results.tasks == ["1_sonar", "2_walls"]
    rows = {(r["task"], r["seed"]): r for r in results.rows}
    assert all(r["status"] == "ok" and r["route"] is False for r in rows.values())
    assert rows["1_sonar", 0]["n_train"] == 700 and rows["1_sonar", 0]["n_test"] == 300      # bootstrapped to 1000
    assert rows["2_walls", 0]["n_novel"] == 30                                               # stratified: 10 % of 300
    assert rows["2_walls", 0]["roc_auc"] != rows["2_walls", 1]["roc_auc"]                    # a split a seed
    assert "stratified 70/30 train/test split drawn for each seed" in rows["2_walls", 0]["task_split"]
    assert "## How each task was split" in results.summary


def test_first_rows_of_a_file_stored_anomalies_last_are_said_to_be_so(tmp_path):
    folder = _benchmark_folder(tmp_path)
    with pytest.raises(SuiteError, match="no normal scan"):       # the last 5 % are all anomalies
        bench.run(["lof"], f"files path={folder}/2_walls.mat train_rows=0.95")
    row = bench.run(["lof"], f"files path={folder}/2_walls.mat train_rows=0.5").rows[0]
    assert row["task_split"].startswith("the first 500 of 1000 rows in file order trained (not shuffled)")


def test_results_without_out_leave_no_folder_and_no_resource_warning():
    rng = np.random.default_rng(0)
    results = bench.run("parzen", {"t": (rng.random((30, 3)), rng.random((10, 3)), np.r_[np.ones(3), np.zeros(7)])})
    folder = results.out
    assert (folder / "results.csv").exists()
    with warnings.catch_warnings(record=True) as caught:  # a finalizer's warning is recorded, never raised
        warnings.simplefilter("always")
        del results
        gc.collect()
    assert not folder.exists()
    assert not [w for w in caught if issubclass(w.category, ResourceWarning)], [str(w.message) for w in caught]
