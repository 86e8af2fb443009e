"""Comparing detectors on one task of a run: the records, the table, and what is refused."""

import numpy as np
import pytest

from novelty import bench
from novelty.bench.compare import compare_on_task, comparison_text
from novelty.bench.results import ResultsStore


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    rng = np.random.default_rng(0)
    X_train, X_test = rng.random((100, 4)), rng.random((50, 4))
    X_test[:10] += 1.0
    return bench.run(["parzen", "isolation-forest"], {"t": (X_train, X_test, np.r_[np.ones(10), np.zeros(40)])},
                     out=tmp_path_factory.mktemp("compare"), plots=False)


def test_each_detector_against_the_reference_with_both_intervals(run):
    (record,) = compare_on_task(run.rows, ResultsStore(run.out).arrays, "t", "parzen", resamples=100)
    assert record["detector"] == "isolation-forest" and record["seed"] == 0
    assert record["roc_auc"].low <= record["roc_auc"].difference <= record["roc_auc"].high
    assert record["corrected_t"] is None     # one seed: no splits to test over
    text = comparison_text([record])
    assert "ΔROC AUC vs parzen [95% CI]" in text and "100 stratified resamples" in text


def test_an_unknown_task_or_reference_names_what_there_is(run):
    arrays = ResultsStore(run.out).arrays
    with pytest.raises(ValueError, match="tasks of this run: t"):
        compare_on_task(run.rows, arrays, "nope")
    with pytest.raises(ValueError, match="detectors there: parzen, isolation-forest"):
        compare_on_task(run.rows, arrays, "t", "lof")


def exploration_rows(worlds):
    """Hand rows of an exploration task: seed j of 'a' and of the reference 'ref', worlds[j] their task_data."""
    aucs = {"a": [0.8, 0.7, 0.9], "ref": [0.7, 0.6, 0.7]}
    return [{"status": "ok", "detector": d, "task": "x", "seed": j, "cell_id": f"{d}{j}", "policy": "online",
             "first_encounter_auc": auc, **({"task_data": worlds[j]} if worlds else {})}
            for d, values in aucs.items() for j, auc in enumerate(values)]


def test_on_an_exploration_task_the_unit_is_the_seed_of_an_independently_built_world():
    (record,) = compare_on_task(exploration_rows(["w0", "w1", "w2"]), lambda cell_id: None, "x", "ref")
    # differences 0.1, 0.1, 0.2: mean 0.4/3, sd 0.057735, t(0.975, 2) = 4.302653
    half = 4.302653 * 0.0577350 / 3 ** 0.5
    assert (record["detector"], record["seeds"], record["worlds"]) == ("a", 3, "built")
    assert record["difference"] == pytest.approx(0.4 / 3)
    assert (record["low"], record["high"]) == pytest.approx((0.4 / 3 - half, 0.4 / 3 + half), abs=1e-6)
    text = comparison_text([record])
    assert "each seed an independently built world" in text and "[-0.010, +0.277]" in text


@pytest.mark.parametrize("worlds, kind, says", [(["w", "w", "w"], "one", "one world: no interval"),
                                                (None, "unknown", "worlds not recorded: no interval")])
def test_seeds_of_one_world_get_no_interval(worlds, kind, says):
    (record,) = compare_on_task(exploration_rows(worlds), lambda cell_id: None, "x", "ref")
    assert record["worlds"] == kind and record["difference"] == pytest.approx(0.4 / 3)
    assert np.isnan(record["low"]) and np.isnan(record["high"])
    assert says in comparison_text([record])
