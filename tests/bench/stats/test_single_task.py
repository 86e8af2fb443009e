"""One task: the paired, stratified bootstrap over test scans and the corrected resampled t-test."""

import math

import numpy as np
import pytest
from sklearn.metrics import average_precision_score, roc_auc_score

from novelty.bench.stats import single_task as st


def _scores(seed=0, n=300, share=0.2):
    rng = np.random.default_rng(seed)
    y = (np.arange(n) < share * n).astype(int)
    return y, y + rng.normal(0, 0.6, n), y + rng.normal(0, 3.0, n)


def test_the_rank_auc_and_average_precision_are_scikit_learns():
    rng = np.random.default_rng(1)
    y = rng.random(200) < 0.3
    s = np.round(rng.random((3, 200)), 1)   # many ties
    np.testing.assert_allclose(st.rank_auc(s, y), [roc_auc_score(y, row) for row in s])
    assert st._metric("average_precision", s, y) == pytest.approx([average_precision_score(y, r) for r in s])


def test_a_detector_against_itself_differs_by_exactly_zero():
    y, a, _ = _scores()
    b = st.paired_bootstrap(a, a, y, resamples=200)
    assert (b.difference, b.low, b.high, b.se) == (0.0, 0.0, 0.0, 0.0) and not b.excludes_zero


def test_a_much_better_detector_has_an_interval_above_zero_and_the_seed_fixes_it():
    y, good, poor = _scores()
    b = st.paired_bootstrap(good, poor, y, resamples=500)
    assert b.difference == pytest.approx(roc_auc_score(y, good) - roc_auc_score(y, poor))
    assert 0 < b.low < b.difference < b.high and b.excludes_zero
    assert b == st.paired_bootstrap(good, poor, y, resamples=500)
    assert st.paired_bootstrap(poor, good, y, "average_precision", resamples=300).high < 0


def test_resamples_keep_the_class_balance():
    # a detector perfect on every resample has AP 1 only if each resample holds positives: stratified
    y, _, poor = _scores()
    b = st.paired_bootstrap(y.astype(float), poor, y, "average_precision", resamples=200)
    assert b.high <= 1 and not math.isnan(b.low)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="both novel and normal"):
        st.paired_bootstrap([0.1, 0.2], [0.3, 0.4], [1, 1])
    with pytest.raises(ValueError, match="one value a scan"):
        st.paired_bootstrap([0.1, 0.2], [0.3], [0, 1])
    with pytest.raises(ValueError, match="Unknown metric"):
        st.paired_bootstrap([0.1, 0.2], [0.3, 0.4], [0, 1], metric="f1")


def test_the_corrected_t_by_hand():
    # d = 0.01, 0.03: mean 0.02, s^2 = 2e-4; corrected variance (1/2 + 1/4) 2e-4 = 1.5e-4
    r = st.corrected_resampled_t([0.01, 0.03], n_train=400, n_test=100)
    assert r.t == pytest.approx(0.02 / math.sqrt(1.5e-4))
    from scipy.stats import t as student

    assert r.pvalue == pytest.approx(2 * student.sf(r.t, 1))
    assert st.corrected_resampled_t([0.0, 0.0], 10, 5).pvalue == 1.0
    with pytest.raises(ValueError, match="at least two splits"):
        st.corrected_resampled_t([0.1], 10, 5)
