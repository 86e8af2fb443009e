"""What a hold-out cell refuses: labels that are not 0/1, a test part of one class, scores that are not finite;
and the route metrics of a task without a route."""

import numpy as np
import pytest
from sklearn.base import BaseEstimator, OutlierMixin

from novelty import bench
from novelty.bench.holdout.evaluate import place_metrics
from novelty.bench.specs import SuiteError


class Infinite(OutlierMixin, BaseEstimator):
    """A scikit-learn outlier estimator whose scores are -inf (as PyOD's PCA's +inf on a degenerate split)."""

    def fit(self, X, y=None):
        self.n_features_in_ = X.shape[1]
        return self

    def score_samples(self, X):
        return np.full(len(X), -np.inf)


@pytest.fixture
def arrays():
    rng = np.random.default_rng(0)
    X_train, X_test = rng.random((60, 3)), rng.random((30, 3))
    X_test[:6] += 1.5
    return X_train, X_test, np.r_[np.ones(6), np.zeros(24)]


def test_scores_that_are_not_finite_fail_the_cell_with_their_count(arrays):
    # before: the calibration mapped +inf to 1 for every scan, the cell was ok with ROC AUC 0.5
    row = bench.run([Infinite()], {"t": arrays}).rows[0]
    assert row["status"] == "error" and "30 of 30 test scans NaN or infinite" in row["error"]
    assert "raw_novelty" in row["error"]


@pytest.mark.parametrize("labels, message", [
    (np.r_[np.full(6, -1), np.ones(24)], r"convert with y = \(y == -1\)\.astype\(int\)"),
    (np.r_[np.full(6, np.nan), np.zeros(24)], "the label is NaN"),
    (np.r_[np.full(6, 0.5), np.zeros(24)], "got 0.5"),
    (np.zeros(30), "no novel scan"),
    (np.ones(30), "no normal scan"),
])
def test_labels_that_would_change_the_verdict_are_refused_before_running(arrays, labels, message):
    with pytest.raises(SuiteError, match=message):
        bench.run(["parzen"], {"t": (arrays[0], arrays[1], labels)})


def test_a_table_without_a_route_gets_no_route_metrics(arrays):
    row = bench.run(["parzen"], {"t": arrays}).rows[0]
    assert row["status"] == "ok" and row["route"] is False and row["roc_auc"] > 0.9
    assert all(row[c] is None for c in ("detection_delay", "false_alarms", "integrated_novelty"))  # NaN
    results = bench.run(["parzen"], "inspection-easy train_runs=1")
    assert results.rows[0]["route"] is True and results.rows[0]["false_alarms"] is not None


def test_the_ranking_drops_route_columns_when_no_task_has_a_route(arrays):
    table = bench.run(["parzen"], {"t": arrays}).table
    assert "ROC AUC" in table and "delay" not in table and "false alarms" not in table


def test_objects_in_seen_and_unseen_places_are_scored_apart_against_the_same_normal_scans():
    novelty = np.array([0.1, 0.2, 0.9, 0.05, 0.5])
    y = np.array([0, 0, 1, 1, 1], dtype=bool)
    seen_place = np.array([False, False, True, True, False])
    # seen: 0.9 above both normal scans, 0.05 below both (1/2); unseen: 0.5 above both
    assert place_metrics(novelty, y, seen_place) == {"n_novel_seen": 2, "roc_auc_seen": 0.5,
                                                     "n_novel_unseen": 1, "roc_auc_unseen": 1.0}
    only_seen = place_metrics(novelty, y, np.ones(5, dtype=bool))
    assert only_seen["n_novel_unseen"] == 0 and np.isnan(only_seen["roc_auc_unseen"])
