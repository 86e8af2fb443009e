"""Metrics against values computed by hand on tiny arrays."""

import math

import numpy as np
import pytest

from novelty.bench.holdout import metrics

SCORES = [0.1, 0.4, 0.35, 0.8]
LABELS = [0, 0, 1, 1]


def test_roc_auc_by_hand():
    # novel 0.35 beats 0.1 only; novel 0.8 beats both: 3 of 4 pairs
    assert metrics.roc_auc(SCORES, LABELS) == 0.75


def test_roc_auc_counts_ties_one_half():
    # one novel/normal pair tied, one won: (1 + 0.5) / 2
    assert metrics.roc_auc([0.5, 0.5, 0.9], [0, 1, 1]) == 0.75


def test_roc_auc_perfect_and_reversed():
    assert metrics.roc_auc([0, 1, 2, 3], [0, 0, 1, 1]) == 1.0
    assert metrics.roc_auc([3, 2, 1, 0], [0, 0, 1, 1]) == 0.0


def test_average_precision_by_hand():
    # ranked: 0.8 (novel) P=1 R=.5; 0.4 (normal); 0.35 (novel) P=2/3 R=1
    assert metrics.average_precision(SCORES, LABELS) == pytest.approx(0.5 * 1 + 0.5 * 2 / 3)


def test_average_precision_with_a_tie_takes_the_whole_group():
    # threshold 0.5 calls three scans novel at once: P = 2/3, R = 1
    assert metrics.average_precision([0.5, 0.5, 0.5, 0.1], [1, 1, 0, 0]) == pytest.approx(2 / 3)


def test_roc_points_by_hand():
    fpr, tpr, thresholds = metrics.roc_points(SCORES, LABELS)
    np.testing.assert_allclose(fpr, [0, 0, 0.5, 0.5, 1])
    np.testing.assert_allclose(tpr, [0, 0.5, 0.5, 1, 1])
    assert thresholds[0] == np.inf and list(thresholds[1:]) == [0.8, 0.4, 0.35, 0.1]


def test_tpr_at_fpr_by_hand():
    assert metrics.tpr_at_fpr(SCORES, LABELS, 0.0) == 0.5
    assert metrics.tpr_at_fpr(SCORES, LABELS, 0.49) == 0.5
    assert metrics.tpr_at_fpr(SCORES, LABELS, 0.5) == 1.0
    # 100 normal scans, 10 novel: one normal scan above all novel ones costs 1% FPR
    scores = np.r_[np.linspace(0, 0.5, 99), 2.0, np.linspace(0.6, 1.5, 10)]
    y = np.r_[np.zeros(100), np.ones(10)]
    assert metrics.tpr_at_fpr(scores, y, 0.0) == 0.0
    assert metrics.tpr_at_fpr(scores, y, 0.01) == 1.0


def test_one_class_gives_nan():
    for f in (metrics.roc_auc, metrics.average_precision):
        assert math.isnan(f([0.1, 0.2], [0, 0]))
        assert math.isnan(f([0.1, 0.2], [1, 1]))
    assert math.isnan(metrics.tpr_at_fpr([0.1, 0.2], [0, 0], 0.05))


def test_threshold_from_training():
    assert metrics.training_threshold([0.05, 0.2, 0.1]) == 0.2
    assert metrics.training_threshold(np.arange(101.0), 0.9) == pytest.approx(90.0)
    with pytest.raises(ValueError):
        metrics.training_threshold([0.1], 1.5)


def test_detection_delay_by_hand():
    scores = [0.9, 0.1, 0.2, 0.7, 0.8]
    y = [0, 0, 1, 1, 1]
    assert metrics.detection_delay(scores, y, 0.5) == 1.0   # alarm at scan 0 is a false alarm
    assert metrics.detection_delay(scores, y, 0.1) == 0.0   # the first novel scan itself
    assert math.isnan(metrics.detection_delay(scores, y, 0.95))  # missed
    assert math.isnan(metrics.detection_delay(scores, [0] * 5, 0.5))  # nothing novel
    # an alarm exactly at the threshold is not an alarm
    assert metrics.detection_delay([0.5, 0.6], [1, 1], 0.5) == 1.0


def test_alarms_and_integrated_novelty():
    assert metrics.count_alarms([0.1, 0.5, 0.6], 0.5) == 1
    # Table 1 of the paper: resting activity 0.0476 a step subtracted
    assert metrics.integrated_novelty([1.0, 0.0476, 0.5476], 0.0476) == pytest.approx(1.4524)
    assert metrics.integrated_novelty([0.2, 0.3]) == pytest.approx(0.5)


def test_agrees_with_scikit_learn_on_random_data():
    from sklearn.metrics import average_precision_score, roc_auc_score

    rng = np.random.default_rng(0)
    for _ in range(5):
        y = rng.integers(0, 2, 60)
        s = np.round(rng.random(60) + 0.3 * y, 1)  # rounded: many ties
        assert metrics.roc_auc(s, y) == pytest.approx(roc_auc_score(y, s))
        assert metrics.average_precision(s, y) == pytest.approx(average_precision_score(y, s))


# ------------------------------------------------------------------ the table
def test_adding_a_metric_is_one_entry_of_the_table(toy_registered, tmp_path, monkeypatch):
    from novelty.bench import DetectorSpec, Suite, TaskSpec
    from novelty.bench.runner import run_bench
    from novelty.bench.holdout.summary import ranking_text

    median = metrics.Metric("median_novelty", lambda s: float(np.median(s.novelty)), "median", 2)
    monkeypatch.setattr(metrics, "METRICS", (*metrics.METRICS, median))
    suite = Suite([DetectorSpec("hsom", {"n_rows": 3, "n_columns": 3})], [TaskSpec(toy_registered.TASK)],
                  seeds=[0, 1], name="toy", memory=False).check()
    report = run_bench(suite, tmp_path, quiet=True, plots=False)
    assert report.failed == 0
    for row in report.rows:
        novelty = np.load(tmp_path / "cells" / f"{row['cell_id']}.npz")["novelty"]
        assert row["median_novelty"] == float(np.median(novelty))
    assert "median_novelty" in (tmp_path / "results.csv").read_text().splitlines()[0].split(",")
    header, _, line = ranking_text(report.rows).splitlines()
    heads = [h.strip() for h in header.strip("|").split("|")]
    cells = [c.strip() for c in line.strip("|").split("|")]
    mean = np.mean([row["median_novelty"] for row in report.rows])
    assert heads[heads.index("max") + 1] == "median" and cells[heads.index("median")] == f"{mean:.2f}"
