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
