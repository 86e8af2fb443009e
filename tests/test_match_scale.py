"""The match scale and the habituation x mismatch novelty (novelty.match_scale)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from novelty.match_scale import ScaleCalibration, mismatch_novelty, nearest_distinct


def test_mismatch_novelty_by_hand():
    y = np.array([0.5, 0.5, 0.0, 1.0])
    d2 = np.array([0.0, 2.0, 8.0, 3.0])  # sigma = 1: exp(-d2 / 2)
    expected = [0.5, 1 - 0.5 * np.exp(-1.0), 1 - np.exp(-4.0), 1.0]
    np.testing.assert_allclose(mismatch_novelty(y, d2, 1.0), expected, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(mismatch_novelty(y, d2, None), y)  # no scale: the efficacy


@settings(max_examples=50, deadline=None)
@given(y=hnp.arrays(np.float64, 5, elements=st.floats(0, 1)),
       d2=hnp.arrays(np.float64, 5, elements=st.floats(0, 100)),
       scale=st.floats(0.01, 10))
def test_mismatch_novelty_lies_between_the_efficacy_and_one(y, d2, scale):
    n = mismatch_novelty(y, d2, scale)
    assert np.all(n >= y - 1e-12) and np.all(n <= 1.0)
    np.testing.assert_allclose(mismatch_novelty(y, np.zeros(5), scale), y, atol=1e-15)


def test_nearest_distinct_ignores_repeats():
    X = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 4.0], [0.0, 1.0]])
    np.testing.assert_array_equal(nearest_distinct(X), [1.0, np.sqrt(18.0), np.sqrt(18.0), 1.0])
    assert np.all(np.isinf(nearest_distinct(np.zeros((3, 2)))))


def test_calibration_is_the_quantile_of_the_first_scans():
    X = np.array([[0.0], [1.0], [3.0], [7.0], [100.0]])
    cal = ScaleCalibration(np.empty((0, 1)), capacity=4, quantile=0.5).extend(X)
    assert cal.full and cal.scans.shape == (4, 1)  # the fifth scan is not collected
    assert cal.scale == np.quantile([1.0, 1.0, 2.0, 4.0], 0.5) == 1.5


@settings(max_examples=30, deadline=None)
@given(X=hnp.arrays(np.float64, st.tuples(st.integers(1, 30), st.integers(1, 4)),
                    elements=st.sampled_from([0.0, 0.5, 1.0, 2.5, -3.0])),
       capacity=st.integers(2, 40), q=st.floats(0, 1))
def test_one_at_a_time_equals_all_at_once(X, capacity, q):
    cal = ScaleCalibration(np.empty((0, X.shape[1])), capacity, q).extend(X)
    kept = X[:capacity]
    nearest = nearest_distinct(kept)
    finite = nearest[np.isfinite(nearest)]
    assert cal.scale == (float(np.quantile(finite, q)) if finite.size else None)
    np.testing.assert_array_equal(cal.scans, kept)
    assert ScaleCalibration(kept, capacity, q).scale == cal.scale  # rebuilt from a model file
