"""The match scale and the habituation x mismatch novelty (novelty.match_scale)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from novelty.match_scale import (ScaleCalibration, linear_quantile, mismatch_novelty, nearest_distinct,
                                  product_novelty, scott_scale)


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


def test_product_novelty_by_hand():
    y = np.array([0.5, 0.5, 0.0, 1.0])
    d2 = np.array([0.0, 2.0, 8.0, 3.0])  # sigma = 1: exp(-d2 / 2)
    expected = [0.0, 0.5 * (1 - np.exp(-1.0)), 0.0, 1 - np.exp(-1.5)]
    np.testing.assert_allclose(product_novelty(y, d2, 1.0), expected, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(product_novelty(y, d2, None), y)  # no scale: the efficacy


@settings(max_examples=50, deadline=None)
@given(y=hnp.arrays(np.float64, 5, elements=st.floats(0, 1)),
       d2=hnp.arrays(np.float64, 5, elements=st.floats(0, 100)),
       scale=st.floats(0.01, 10))
def test_product_and_mismatch_are_the_and_and_the_or_of_efficacy_and_mismatch(y, d2, scale):
    m = 1.0 - np.exp(-d2 / (2.0 * scale * scale))
    product, either = product_novelty(y, d2, scale), mismatch_novelty(y, d2, scale)
    assert np.all(product >= 0.0) and np.all(product <= np.minimum(y, m) + 1e-12)
    np.testing.assert_allclose(product + either, y + m, rtol=0, atol=1e-12)  # y m + (y + m - y m)


def test_nearest_distinct_ignores_repeats():
    X = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 4.0], [0.0, 1.0]])
    np.testing.assert_array_equal(nearest_distinct(X), [1.0, np.sqrt(18.0), np.sqrt(18.0), 1.0])
    assert np.all(np.isinf(nearest_distinct(np.zeros((3, 2)))))


@settings(max_examples=60, deadline=None)
@given(X=hnp.arrays(np.float64, st.tuples(st.integers(1, 70), st.sampled_from([1, 2, 7, 8, 9, 16, 130])),
                    elements=st.one_of(st.floats(-1e3, 1e3), st.sampled_from([0.0, 1.0]))))
def test_nearest_distinct_is_each_rows_own_distances_bit_for_bit(X):
    expected = np.full(X.shape[0], np.inf)
    for i, x in enumerate(X):
        d = np.sqrt(((X - x) ** 2).sum(axis=1))
        d = d[d > 0.0]
        if d.size:
            expected[i] = d.min()
    np.testing.assert_array_equal(nearest_distinct(X), expected)


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


@settings(max_examples=300, deadline=None)
@given(values=hnp.arrays(np.float64, st.integers(1, 60),
                         elements=st.one_of(st.floats(0, 1e6), st.sampled_from([0.5, 1.0, 2.0]))),
       q=st.one_of(st.floats(0, 1), st.sampled_from([0.0, 0.1, 0.5, 0.9, 1.0, 1 / 3])))
def test_the_quantile_is_numpys_bit_for_bit(values, q):
    before = values.copy()
    got = linear_quantile(values, q)
    assert type(got) is float
    assert got == float(np.quantile(values, q))
    np.testing.assert_array_equal(values, before)  # the values are not reordered


def test_the_quantile_by_hand():
    # ranks (m - 1) q = 3 x 0.9 = 2.7: between 3.0 and 10.0, 0.7 of the way (from 10.0's side)
    assert linear_quantile(np.array([10.0, 0.0, 3.0, 1.0]), 0.9) == 10.0 - 7.0 * (1 - 0.7000000000000002)
    assert linear_quantile(np.array([10.0, 0.0, 3.0, 1.0]), 1.0) == 10.0
    assert linear_quantile(np.array([10.0, 0.0, 3.0, 1.0]), 0.0) == 0.0
    assert linear_quantile(np.array([7.0]), 0.3) == 7.0


# ------------------------------------------------------------- Scott's rule
def test_scott_scale_by_hand():
    # columns (0, 2, 1) and (0, 0, 3): sample variances 1 and 3, mean 2; m = 3, d = 2
    X = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 3.0]])
    assert scott_scale(X) == np.sqrt(2.0) * 3.0 ** (-1.0 / 6.0)
    # one column: Scott's univariate rule s * m^(-1/5)
    assert scott_scale(np.array([[1.0], [3.0]])) == np.sqrt(2.0) * 2.0 ** (-0.2)


def test_scott_scale_is_none_without_two_distinct_scans():
    assert scott_scale(np.empty((0, 3))) is None
    assert scott_scale(np.ones((1, 3))) is None
    assert scott_scale(np.full((5, 3), 0.25)) is None


def test_calibration_rule_scott_takes_the_first_scans():
    X = np.array([[0.0], [2.0], [4.0], [100.0]])
    cal = ScaleCalibration(np.empty((0, 1)), capacity=3, quantile=0.9, rule="scott")
    changed = [cal.add(x) for x in X]
    assert changed == [False, True, True, False]  # no scale after one scan; the fourth is not collected
    assert cal.scale == 2.0 * 3.0 ** (-0.2)       # s = 2 over (0, 2, 4)


def test_calibration_rule_is_checked():
    with pytest.raises(ValueError, match="rule"):
        ScaleCalibration(np.empty((0, 1)), 3, 0.9, rule="silverman")


@settings(max_examples=30, deadline=None)
@given(X=hnp.arrays(np.float64, st.tuples(st.integers(1, 30), st.integers(1, 4)),
                    elements=st.sampled_from([0.0, 0.5, 1.0, 2.5, -3.0])),
       capacity=st.integers(2, 40))
def test_scott_one_at_a_time_equals_all_at_once(X, capacity):
    cal = ScaleCalibration(np.empty((0, X.shape[1])), capacity, 0.9, "scott").extend(X)
    kept = X[:capacity]
    assert cal.scale == scott_scale(kept)
    assert ScaleCalibration(kept, capacity, 0.9, "scott") == cal


@settings(max_examples=30, deadline=None)
@given(X=hnp.arrays(np.float64, st.tuples(st.integers(2, 30), st.integers(1, 4)),
                    elements=st.floats(-10, 10)),
       shift=st.floats(-100, 100), factor=st.floats(0.01, 100))
def test_scott_scale_is_shift_invariant_and_scales_with_the_data(X, shift, factor):
    base = scott_scale(X)
    if base is None or base < 1e-6:
        return
    np.testing.assert_allclose(scott_scale(X + shift), base, rtol=1e-6)
    np.testing.assert_allclose(scott_scale(X * factor), base * factor, rtol=1e-9)


# ------------------------------------------------------------- in the filter
def test_filter_scott_scale_is_that_of_the_first_scans_in_any_batching():
    import novelty

    X = np.random.default_rng(0).uniform(size=(60, 4))
    whole = novelty.make("hsom", novelty_rule="mismatch", match_scale="scott", calibration_scans=40)
    out = whole.stream(X)
    assert whole.match_scale_ == scott_scale(X[:40])
    pieces = novelty.make("hsom", novelty_rule="mismatch", match_scale="scott", calibration_scans=40)
    parts = np.concatenate([pieces.stream(X[:7]), pieces.stream(X[7:33]), pieces.stream(X[33:])])
    assert parts.tobytes() == out.tobytes()
    assert pieces.match_scale_ == whole.match_scale_


@pytest.mark.parametrize("bad", ["silverman", "Scott", -1.0, 0.0, True])
def test_filter_refuses_a_bad_match_scale(bad):
    import novelty

    det = novelty.make("hsom", novelty_rule="mismatch", match_scale=bad)
    with pytest.raises(ValueError, match="match_scale"):
        det.fit(np.zeros((3, 2)))
    assert not hasattr(det, "clusterer_")


@pytest.mark.parametrize("name, params", [
    ("hsom", {"novelty_rule": "mismatch"}),
    ("hsom", {"novelty_rule": "product", "match_scale": "scott"}),
    ("gng-stanley", {}),
    ("gwr-explore", {}),  # its clusterer learns by the scale: the one-scan-at-a-time path
    ("gwr-novelty", {}),
    ("gwr-novelty", {"novelty_rule": "efficacy"}),
    ("kmeans-stanley", {}),
])
def test_calibrating_in_one_call_equals_one_scan_at_a_time(name, params):
    """Learning a block while the scale calibrates gives what scan-by-scan learning gives,
    novelty and state, whichever path the clusterer takes."""
    import novelty

    X = np.random.default_rng(3).uniform(size=(90, 5))
    whole = novelty.make(name, calibration_scans=50, **params)
    out = whole.stream(X)
    single = novelty.make(name, calibration_scans=50, **params)
    one_by_one = np.array([single.score_learn_one(x) for x in X])
    assert one_by_one.tobytes() == out.tobytes()
    assert single.match_scale_ == whole.match_scale_
    np.testing.assert_array_equal(single.calibration_scans_, whole.calibration_scans_)
    np.testing.assert_array_equal(single.synapse_.efficacy_, whole.synapse_.efficacy_)
    np.testing.assert_array_equal(single.clusterer_.weights_, whole.clusterer_.weights_)
