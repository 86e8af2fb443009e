"""Learning while the match scale is calibrated: any batching gives the same numbers."""

import numpy as np
import pytest

import novelty
from novelty.match_scale import nearest_distinct

from ..test_filter import data, euler


def mismatch(**params):
    return novelty.make("hsom", n_rows=2, n_columns=2, novelty_rule="mismatch", **params)


def test_match_scale_is_calibrated_on_the_first_scans():
    X = data(300)
    det = mismatch(calibration_scans=50).fit(X)
    assert det.match_scale_ == np.quantile(nearest_distinct(X[:50]), 0.9)
    np.testing.assert_array_equal(det.calibration_scans_, X[:50])
    det.partial_fit(data(20, seed=1))
    assert det.match_scale_ == np.quantile(nearest_distinct(X[:50]), 0.9)  # fixed once calibrated
    assert mismatch(match_quantile=0.5, calibration_scans=50).fit(X).match_scale_ < det.match_scale_


@pytest.mark.parametrize("name,params", [
    ("hsom", {"novelty_rule": "mismatch", "calibration_scans": 30}),
    ("gwr-novelty", {"novelty_rule": "mismatch", "activity_threshold": "auto",
                     "firing_condition": False, "new_unit_wins": True, "calibration_scans": 30}),
    ("gwr-explore", {"calibration_scans": 30}),
])
def test_mismatch_streaming_scan_by_scan_equals_batches(name, params):
    X = data(80)
    whole = novelty.make(name, **params)
    out_whole = whole.stream(X)
    parts = novelty.make(name, **params)
    out_parts = np.concatenate([parts.stream(X[:7]), parts.stream(X[7:45]), parts.stream(X[45:])])
    one = novelty.make(name, **params)
    out_one = np.array([one.score_learn_one(x) for x in X])
    np.testing.assert_array_equal(out_whole, out_parts)
    np.testing.assert_array_equal(out_whole, out_one)
    assert whole.match_scale_ == parts.match_scale_ == one.match_scale_ is not None
    np.testing.assert_array_equal(whole.novelty(X), one.novelty(X))


def test_before_two_distinct_scans_the_novelty_is_the_efficacy():
    det = mismatch()
    x = np.full(4, 0.5)
    out = [det.score_learn_one(x) for _ in range(3)]
    assert det.match_scale_ is None
    np.testing.assert_allclose(out, [1.0, euler(1), euler(2)], rtol=0, atol=1e-15)
    assert det.score_one(np.ones(4)) == det.synapse_.efficacy_[det.clusterer_.match(np.ones(4)).winner]
