"""The ranking of a run on a hand-made results table (tests.bench.hand_rows)."""

import math

import pytest

from novelty.bench.reports.ranking import per_task, rank_detectors, reference_of


def test_detectors_ranked_by_the_mean_over_seeds_of_the_task_mean(rows):
    # b: seed 0 (0.85 + 0.70) / 2 = 0.775, seed 1 (0.75 + 0.95) / 2 = 0.85; ref: 0.70, 0.80;
    # a: seed 0 (0.90 + 0.50) / 2 = 0.70, seed 1 0.70 alone (t2/1 failed)
    records = rank_detectors(rows)
    assert [(r["rank"], r["detector"]) for r in records] == [(1, "b"), (2, "ref"), (3, "a")]
    b, ref, a = records
    assert b["roc_auc"] == pytest.approx(0.8125) and b["roc_auc_sd"] == pytest.approx(0.075 / math.sqrt(2))
    assert ref["roc_auc"] == pytest.approx(0.75) and ref["roc_auc_sd"] == pytest.approx(0.1 / math.sqrt(2))
    assert a["roc_auc"] == pytest.approx(0.70) and a["roc_auc_sd"] == pytest.approx(0.0, abs=1e-12)
    assert (a["cells"], a["failed"], b["cells"], b["failed"]) == (4, 1, 4, 0)


def test_a_single_seed_has_no_spread(rows):
    (record,) = rank_detectors([r for r in rows if r["detector"] == "b" and r["seed"] == 0])
    assert record["roc_auc"] == pytest.approx(0.775) and math.isnan(record["roc_auc_sd"])


def test_per_task_mean_and_spread_over_seeds(rows):
    table = per_task(rows)
    mean, sd = table["a"]["t1"]
    assert mean == pytest.approx(0.80) and sd == pytest.approx(math.sqrt(0.02))
    mean, sd = table["a"]["t2"]  # one successful seed: no spread
    assert mean == pytest.approx(0.50) and math.isnan(sd)


def test_the_default_reference_does_not_depend_on_the_results(rows):
    # mean over seeds of the task mean: b 0.8125, ref 0.75, a 0.70; the default is the first label, not b
    assert reference_of(rows) == "a"
    worse = [dict(r, roc_auc=0.0) if r["detector"] == "a" else r for r in rows]
    assert reference_of(worse) == "a"
    assert reference_of(rows, "ref") == "ref"
    assert reference_of([]) is None
